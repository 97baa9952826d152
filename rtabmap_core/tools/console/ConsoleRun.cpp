#include "console/ConsoleRun.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>

#include <Eigen/Geometry>

#include <unistd.h>

#include "common/ProgressBar.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/memory/LoopClosureDetector.h"

namespace rtabmap::tools::console {

namespace {

void writeTumLine(std::ostream& out, double stamp, const Transform& pose) {
  const Eigen::Quaterniond q(pose.toEigen().linear());
  const Eigen::Vector3d t = pose.toEigen().translation();
  out << std::fixed << std::setprecision(6) << stamp << std::setprecision(9) << ' ' << t.x() << ' ' << t.y() << ' '
      << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << std::defaultfloat << '\n';
}

// The files of a run and the bookkeeping from location ids back to image numbers.
class RunOutput {
 public:
  RunOutput(const std::string& dir, ConsoleReport& report) : dir_(dir), report_(report) {
    log_.open(report.logPath);
    detections_.open(report.detectionsPath);
    if (!log_ || !detections_) throw Error("cannot write in " + dir);
    log_ << "# image location loop_id highest_id highest_value wm_size vocabulary_size update_ms\n";
    detections_ << "# image matched_image value (highest hypothesis of each image; value 0 when VhEp refused it)\n";
  }

  void add(int image, const DatasetRecord& record, const memory::LoopClosureUpdate& u) {
    if (u.id > 0 && !u.merged) imageOfLocation_[u.id] = image;
    log_ << image << ' ' << u.id << ' ' << imageOf(u.loopClosureId) << ' ' << imageOf(u.highest.id) << ' '
         << u.highest.value << ' ' << u.wmSize << ' ' << u.vocabularySize << ' ' << std::fixed << std::setprecision(2)
         << u.totalMs << std::defaultfloat << '\n';
    // A hypothesis the epipolar check (VhEp) refused is no detection, whatever its probability:
    // the verification is part of the detector when enabled.
    const bool refused = u.epipolarInliers >= 0 && !u.highest.accepted;
    const LoopDetection d{image, imageOf(u.highest.id), refused ? 0.f : u.highest.value};
    detections_ << d.queryId << ' ' << d.matchedId << ' ' << d.confidence << '\n';
    found_.push_back(d);
    // The ground truth of each image, in image order, when the dataset has it: the poses file
    // `rtabmap-eval pr --gt` reads (one pose per image).
    if (record.data.groundTruth().isNull()) return;
    if (!groundTruth_.is_open()) {
      report_.groundTruthPath = (std::filesystem::path(dir_) / "groundtruth.txt").string();
      groundTruth_.open(report_.groundTruthPath);
      groundTruth_ << "# timestamp tx ty tz qx qy qz qw (ground truth of each image, in image order)\n";
    }
    writeTumLine(groundTruth_, record.stamp, record.data.groundTruth());
  }

  const std::vector<LoopDetection>& detections() const { return found_; }

 private:
  int imageOf(int location) const {
    auto it = imageOfLocation_.find(location);
    return it == imageOfLocation_.end() ? 0 : it->second;
  }

  std::string dir_;
  ConsoleReport& report_;
  std::ofstream log_, detections_, groundTruth_;
  std::map<int, int> imageOfLocation_;
  std::vector<LoopDetection> found_;
};

void accumulate(ConsoleReport& r, const memory::LoopClosureUpdate& u, double* totalMs) {
  r.rehearsalMerges += u.merged;
  r.loopClosures += u.loopClosureId != 0;
  r.transferred += static_cast<int>(u.transferred.size());
  r.retrieved += static_cast<int>(u.retrieved.size());
  *totalMs += u.totalMs;
  r.maxUpdateMs = std::max(r.maxUpdateMs, u.totalMs);
  r.maxWmSize = std::max(r.maxWmSize, u.wmSize);
  r.maxVocabularySize = std::max(r.maxVocabularySize, u.vocabularySize);
}

}  // namespace

ConsoleReport run(const ConsoleOptions& options) {
  namespace fs = std::filesystem;
  if (options.inputs.empty()) throw Error("no input dataset");
  ConsoleReport report;
  fs::create_directories(options.outputDir);
  report.databasePath = (fs::path(options.outputDir) / "rtabmap.db").string();
  report.logPath = (fs::path(options.outputDir) / "log.txt").string();
  report.detectionsPath = (fs::path(options.outputDir) / "detections.txt").string();

  // Open every input first: a wrong path fails before minutes of work.
  DatasetReaderOptions readerOptions;
  readerOptions.imu = readerOptions.odometry = readerOptions.scans = false;
  std::vector<std::unique_ptr<DatasetReader>> readers;
  int count = 0;
  for (const std::string& input : options.inputs) {
    readers.push_back(openDatasetReader(options.format, input, readerOptions));
    const int frames = readers.back()->frameCount();
    count = count >= 0 && frames >= 0 ? count + frames : -1;
  }
  if (options.maxImages > 0 && count >= 0) count = std::min(count, options.maxImages);
  const auto features = FeatureDetector::create(options.parameters, FeatureGroup::kKp);
  const auto detectorOptions = memory::LoopClosureDetectorOptions::fromParameters(options.parameters);

  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(report.databasePath + suffix);
  db::DatabaseOptions dbOptions = db::DatabaseOptions::fromParameters(options.parameters);
  dbOptions.sessionParameters = Parameters::serialize(options.parameters);
  db::Database ltm(report.databasePath, dbOptions);
  memory::LoopClosureDetector detector(detectorOptions, &ltm);
  RunOutput output(options.outputDir, report);

  double totalMs = 0.0;
  ProgressBar progress("images", count > 0 ? static_cast<size_t>(count) : 0, options.progress && isatty(2), std::cerr);
  const auto full = [&] { return options.maxImages > 0 && report.images >= options.maxImages; };
  DatasetRecord record;
  for (auto& reader : readers) {
    while (!full() && reader->next(record)) {
      if (record.kind != DatasetRecord::Kind::kFrame) continue;
      const int image = ++report.images;
      ImageFeatures f = features->extract(record.data);
      memory::LocationInput in;
      in.keypoints = std::move(f.keypoints);
      in.descriptors = f.descriptors;
      in.stamp = record.stamp;
      const memory::LoopClosureUpdate u = detector.process(in);
      accumulate(report, u, &totalMs);
      output.add(image, record, u);
      progress.update(static_cast<size_t>(image));
    }
  }
  progress.finish();
  detector.memory().saveAll();
  ltm.close();
  report.meanUpdateMs = report.images ? totalMs / report.images : 0.0;
  if (!options.groundTruthPath.empty()) {
    const auto gt = LoopGroundTruth::readMatrix(options.groundTruthPath);
    report.pr = computeLoopClosurePR(output.detections(), gt, detectorOptions.hypothesis.loopThr);
  }
  return report;
}

void printReport(const ConsoleReport& r, std::ostream& out) {
  out << "images            " << r.images << "\n"
      << "loop closures     " << r.loopClosures << " accepted\n"
      << "rehearsal merges  " << r.rehearsalMerges << "\n"
      << "update time       mean " << r.meanUpdateMs << " ms, max " << r.maxUpdateMs << " ms\n"
      << "working memory    max " << r.maxWmSize << " locations (" << r.transferred << " transferred, "
      << r.retrieved << " retrieved)\n"
      << "vocabulary        max " << r.maxVocabularySize << " words\n";
  if (r.pr) {
    out << "precision         " << r.pr->precision << " (" << r.pr->truePositives << " true, " << r.pr->falsePositives
        << " false at Rtabmap/LoopThr)\n"
        << "recall            " << r.pr->recall << " of " << r.pr->positives << " images with a loop\n"
        << "recall @100% precision " << r.pr->recallAt100Precision << "\n";
  }
  out << "wrote " << r.databasePath << ", " << r.logPath << ", " << r.detectionsPath
      << (r.groundTruthPath.empty() ? "" : ", " + r.groundTruthPath) << "\n";
}

nlohmann::json toJson(const ConsoleReport& r) {
  nlohmann::json j;
  j["images"] = r.images;
  j["loop_closures"] = r.loopClosures;
  j["rehearsal_merges"] = r.rehearsalMerges;
  j["mean_update_ms"] = r.meanUpdateMs;
  j["max_update_ms"] = r.maxUpdateMs;
  j["max_wm_size"] = r.maxWmSize;
  j["max_vocabulary_size"] = r.maxVocabularySize;
  j["transferred"] = r.transferred;
  j["retrieved"] = r.retrieved;
  j["database"] = r.databasePath;
  if (!r.groundTruthPath.empty()) j["groundtruth"] = r.groundTruthPath;
  if (r.pr) {
    j["precision"] = r.pr->precision;
    j["recall"] = r.pr->recall;
    j["recall_at_100_precision"] = r.pr->recallAt100Precision;
    j["true_positives"] = r.pr->truePositives;
    j["false_positives"] = r.pr->falsePositives;
  }
  return j;
}

}  // namespace rtabmap::tools::console
