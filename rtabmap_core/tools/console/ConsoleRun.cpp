#include "console/ConsoleRun.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>

#include <unistd.h>

#include "common/ProgressBar.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/features/FeatureDetector.h"
#include "rtabmap_core/memory/LoopClosureDetector.h"

namespace rtabmap::tools::console {

ConsoleReport run(const ConsoleOptions& options) {
  namespace fs = std::filesystem;
  ConsoleReport report;
  fs::create_directories(options.outputDir);
  report.databasePath = (fs::path(options.outputDir) / "rtabmap.db").string();
  report.logPath = (fs::path(options.outputDir) / "log.txt").string();
  report.detectionsPath = (fs::path(options.outputDir) / "detections.txt").string();
  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(report.databasePath + suffix);

  DatasetReaderOptions readerOptions;
  readerOptions.maxFrames = options.maxImages;
  readerOptions.imu = readerOptions.odometry = readerOptions.scans = false;
  auto reader = openDatasetReader(options.format, options.imagesPath, readerOptions);
  const auto features = FeatureDetector::create(options.parameters, FeatureGroup::kKp);
  const auto detectorOptions = memory::LoopClosureDetectorOptions::fromParameters(options.parameters);

  db::DatabaseOptions dbOptions = db::DatabaseOptions::fromParameters(options.parameters);
  dbOptions.sessionParameters = Parameters::serialize(options.parameters);
  db::Database ltm(report.databasePath, dbOptions);
  memory::LoopClosureDetector detector(detectorOptions, &ltm);

  std::ofstream log(report.logPath), detections(report.detectionsPath);
  if (!log || !detections) throw Error("cannot write in " + options.outputDir);
  log << "# image location loop_id highest_id highest_value wm_size vocabulary_size update_ms\n";
  detections << "# image matched_image value (highest hypothesis of each image)\n";

  std::map<int, int> imageOfLocation;
  std::vector<LoopDetection> found;
  double totalMs = 0.0;
  const int count = reader->frameCount();
  ProgressBar progress("images", count > 0 ? static_cast<size_t>(count) : 0, options.progress && isatty(2), std::cerr);
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame) continue;
    const int image = ++report.images;
    ImageFeatures f = features->extract(record.data);
    memory::LocationInput in;
    in.keypoints = std::move(f.keypoints);
    in.descriptors = f.descriptors;
    in.stamp = record.stamp;
    const memory::LoopClosureUpdate u = detector.process(in);
    if (u.id > 0 && !u.merged) imageOfLocation[u.id] = image;
    report.rehearsalMerges += u.merged;
    report.loopClosures += u.loopClosureId != 0;
    report.transferred += static_cast<int>(u.transferred.size());
    report.retrieved += static_cast<int>(u.retrieved.size());
    totalMs += u.totalMs;
    report.maxUpdateMs = std::max(report.maxUpdateMs, u.totalMs);
    report.maxWmSize = std::max(report.maxWmSize, u.wmSize);
    report.maxVocabularySize = std::max(report.maxVocabularySize, u.vocabularySize);
    auto imageOf = [&](int location) {
      auto it = imageOfLocation.find(location);
      return it == imageOfLocation.end() ? 0 : it->second;
    };
    log << image << ' ' << u.id << ' ' << imageOf(u.loopClosureId) << ' ' << imageOf(u.highest.id) << ' '
        << u.highest.value << ' ' << u.wmSize << ' ' << u.vocabularySize << ' ' << std::fixed
        << std::setprecision(2) << u.totalMs << std::defaultfloat << '\n';
    LoopDetection d{image, imageOf(u.highest.id), u.highest.value};
    detections << d.queryId << ' ' << d.matchedId << ' ' << d.confidence << '\n';
    found.push_back(d);
    progress.update(static_cast<size_t>(image));
  }
  progress.finish();
  detector.memory().saveAll();
  ltm.close();
  report.meanUpdateMs = report.images ? totalMs / report.images : 0.0;
  if (!options.groundTruthPath.empty()) {
    const auto gt = LoopGroundTruth::readMatrix(options.groundTruthPath);
    report.pr = computeLoopClosurePR(found, gt, detectorOptions.hypothesis.loopThr);
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
  out << "wrote " << r.databasePath << ", " << r.logPath << ", " << r.detectionsPath << "\n";
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
