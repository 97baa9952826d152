#include "eval/Commands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include "common/CommandLine.h"
#include "common/Json.h"
#include "common/ProgressBar.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/LoopClosureEval.h"
#include "rtabmap_core/eval/PathDeviation.h"
#include "rtabmap_core/eval/RelationError.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/eval/TrajectoryError.h"

namespace rtabmap::tools::eval {
namespace {

constexpr const char* kTrajectoryFormats = "tum, kitti, g2o, euroc or auto (detected from the content)";

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

nlohmann::json statsJson(const ErrorStats& s) {
  return {{"count", s.count}, {"rmse", s.rmse},     {"mean", s.mean}, {"median", s.median},
          {"std", s.std},     {"min", s.min},       {"max", s.max}};
}

void printStats(std::ostream& out, const std::string& label, const ErrorStats& s, const std::string& unit,
                int decimals) {
  out << label << " (" << unit << "): rmse " << fixed(s.rmse, decimals) << "  mean " << fixed(s.mean, decimals)
      << "  median " << fixed(s.median, decimals) << "  std " << fixed(s.std, decimals) << "  min "
      << fixed(s.min, decimals) << "  max " << fixed(s.max, decimals) << "\n";
}

void addFormatOptions(CommandLine& cli, bool withGt) {
  cli.addOption("format", "FORMAT", std::string("Format of every trajectory file: ") + kTrajectoryFormats + ".", "auto");
  if (withGt) cli.addOption("gt-format", "FORMAT", "Format of the ground-truth file (overrides --format).");
  cli.addOption("est-format", "FORMAT", "Format of the estimate file (overrides --format).");
}

Trajectory loadTrajectory(const CommandLine& cli, const std::string& pathOption, const std::string& formatOption) {
  const std::string format = cli.has(formatOption) ? cli.option(formatOption) : cli.option("format");
  TrajectoryFormat f;
  try {
    f = trajectoryFormatFromName(format);
  } catch (const FormatError& e) {
    throw UsageError(std::string("--") + (cli.has(formatOption) ? formatOption : "format") + ": " + e.what());
  }
  return readTrajectory(cli.option(pathOption), f);
}

double positiveOption(const CommandLine& cli, const std::string& name, bool allowZero) {
  const double v = cli.optionDouble(name);
  if (!(allowZero ? v >= 0.0 : v > 0.0)) {
    throw UsageError("--" + name + " must be " + (allowZero ? ">= 0" : "> 0") + ", got " + cli.option(name));
  }
  return v;
}

void requireOption(const CommandLine& cli, const std::string& name) {
  if (!cli.has(name)) throw UsageError("--" + name + " is required");
}

// ---------------------------------------------------------------------------------------------

int ate(int argc, char** argv) {
  CommandLine cli("rtabmap-eval ate",
                  "Absolute trajectory error (Sturm et al. 2012): poses associated by stamp, the estimate "
                  "aligned on the ground truth by the least-squares rigid transform (Horn / Umeyama; "
                  "with --scale a similarity), then statistics of the position errors.");
  cli.addOption("gt", "FILE", "Ground-truth trajectory.");
  cli.addOption("est", "FILE", "Estimated trajectory.");
  addFormatOptions(cli, true);
  cli.addOption("max-dt", "SECONDS", "Largest stamp difference of an associated pair.", "0.02");
  cli.addFlag("scale", "Also estimate a scale (Sim3 alignment, for monocular estimates).");
  cli.addFlag("no-align", "Compare the poses as they are (no alignment).");
  cli.addOption("save-aligned", "FILE", "Write the aligned estimate there (TUM format).");
  cli.addNote("Example: rtabmap-eval ate --gt groundtruth.txt --est poses.txt --json | tail -n 1");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "gt");
  requireOption(cli, "est");
  if (cli.flag("scale") && cli.flag("no-align")) throw UsageError("--scale and --no-align exclude each other");

  const Trajectory gt = loadTrajectory(cli, "gt", "gt-format");
  const Trajectory est = loadTrajectory(cli, "est", "est-format");
  AteOptions options;
  options.maxTimeDifference = positiveOption(cli, "max-dt", true);
  options.alignment = cli.flag("no-align") ? TrajectoryAlignment::kNone
                      : cli.flag("scale")  ? TrajectoryAlignment::kSim3
                                           : TrajectoryAlignment::kSE3;
  const AteResult r = computeAte(gt, est, options);
  if (cli.has("save-aligned")) {
    writeTrajectory(cli.option("save-aligned"), applyAlignment(est, r.alignment, r.scale), TrajectoryFormat::kTum);
  }
  const char* alignName = options.alignment == TrajectoryAlignment::kNone   ? "none"
                          : options.alignment == TrajectoryAlignment::kSim3 ? "sim3"
                                                                            : "se3";
  std::cout << "ATE: " << r.pairs.size() << " poses associated (ground truth " << r.groundTruthPoses
            << ", estimate " << r.estimatedPoses << ", max dt " << options.maxTimeDifference
            << " s), alignment " << alignName;
  if (options.alignment == TrajectoryAlignment::kSim3) std::cout << " (scale " << fixed(r.scale, 6) << ")";
  std::cout << "\n";
  printStats(std::cout, "translation", r.translation, "m", 4);
  if (cli.json()) {
    printJsonLine({{"command", "ate"},
                   {"gt", cli.option("gt")},
                   {"est", cli.option("est")},
                   {"gt_poses", r.groundTruthPoses},
                   {"est_poses", r.estimatedPoses},
                   {"associated", r.pairs.size()},
                   {"max_dt", options.maxTimeDifference},
                   {"alignment", alignName},
                   {"scale", r.scale},
                   {"alignment_transform", r.alignment.toString()},
                   {"translation", statsJson(r.translation)},
                   {"rmse", r.translation.rmse}});
  }
  return kExitSuccess;
}

int rpe(int argc, char** argv) {
  CommandLine cli("rtabmap-eval rpe",
                  "Relative pose error (Sturm et al. 2012): the error of the estimated motion between pose "
                  "i and pose j, j being --delta frames later (--unit frames) or the first pose at least "
                  "--delta metres further along the ground truth (--unit m). Translational (m) and "
                  "rotational (deg) statistics.");
  cli.addOption("gt", "FILE", "Ground-truth trajectory.");
  cli.addOption("est", "FILE", "Estimated trajectory.");
  addFormatOptions(cli, true);
  cli.addOption("max-dt", "SECONDS", "Largest stamp difference of an associated pair.", "0.02");
  cli.addOption("delta", "D", "Frames (whole number) or metres between the compared poses.", "1");
  cli.addOption("unit", "UNIT", "frames or m.", "frames");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "gt");
  requireOption(cli, "est");
  RpeOptions options;
  options.maxTimeDifference = positiveOption(cli, "max-dt", true);
  options.delta = positiveOption(cli, "delta", false);
  const std::string unit = cli.option("unit");
  if (unit == "frames" || unit == "frame") {
    options.unit = RpeOptions::Unit::kFrames;
  } else if (unit == "m" || unit == "metres" || unit == "meters") {
    options.unit = RpeOptions::Unit::kMetres;
  } else {
    throw UsageError("--unit must be frames or m, got " + unit);
  }
  const Trajectory gt = loadTrajectory(cli, "gt", "gt-format");
  const Trajectory est = loadTrajectory(cli, "est", "est-format");
  const RpeResult r = computeRpe(gt, est, options);
  const std::string unitName = options.unit == RpeOptions::Unit::kFrames ? "frames" : "m";
  std::cout << "RPE over " << options.delta << " " << unitName << ": " << r.translation.count << " pairs of "
            << r.associated << " associated poses\n";
  printStats(std::cout, "translation", r.translation, "m", 4);
  printStats(std::cout, "rotation", r.rotation, "deg", 3);
  if (cli.json()) {
    printJsonLine({{"command", "rpe"},
                   {"gt", cli.option("gt")},
                   {"est", cli.option("est")},
                   {"associated", r.associated},
                   {"pairs", r.translation.count},
                   {"delta", options.delta},
                   {"unit", unitName},
                   {"translation", statsJson(r.translation)},
                   {"rotation_deg", statsJson(r.rotation)}});
  }
  return kExitSuccess;
}

int kitti(int argc, char** argv) {
  CommandLine cli("rtabmap-eval kitti",
                  "KITTI odometry error (the devkit's evaluate_odometry): for sub-sequences of 100, 200, "
                  "..., 800 m starting every --step frames, the relative translational (%) and rotational "
                  "(deg/m) error of the estimated motion, averaged over all of them. Poses are paired by "
                  "stamp (KITTI files: by row).");
  cli.addOption("gt", "FILE", "Ground-truth trajectory (e.g. poses/00.txt).");
  cli.addOption("est", "FILE", "Estimated trajectory.");
  addFormatOptions(cli, true);
  cli.addOption("max-dt", "SECONDS", "Largest stamp difference of an associated pair.", "0.02");
  cli.addOption("step", "N", "Frames between the starts of two sub-sequences.", "10");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "gt");
  requireOption(cli, "est");
  const int step = cli.optionInt("step");
  if (step < 1) throw UsageError("--step must be >= 1");
  const Trajectory gt = loadTrajectory(cli, "gt", "gt-format");
  const Trajectory est = loadTrajectory(cli, "est", "est-format");
  const auto pairs = associateByStamp(gt, est, positiveOption(cli, "max-dt", true));
  std::vector<Transform> g, e;
  for (const auto& [i, j] : pairs) {
    g.push_back(gt.poses[i].pose);
    e.push_back(est.poses[j].pose);
  }
  KittiOptions options;
  options.stepSize = static_cast<size_t>(step);
  const KittiResult r = computeKittiError(g, e, options);
  std::cout << "KITTI: " << r.frames << " frames paired (ground truth " << gt.size() << ", estimate "
            << est.size() << "), " << r.segments << " sub-sequences\n";
  std::cout << "translation " << fixed(r.translationPercent, 4) << " %  rotation "
            << fixed(r.rotationDegPerMetre, 6) << " deg/m\n";
  nlohmann::json perLength = nlohmann::json::array();
  for (const auto& l : r.perLength) {
    std::cout << "  " << fixed(l.length, 0) << " m: " << l.segments << " segments, translation "
              << fixed(l.translationPercent, 4) << " %, rotation " << fixed(l.rotationDegPerMetre, 6) << " deg/m\n";
    perLength.push_back({{"length", l.length},
                         {"segments", l.segments},
                         {"translation_percent", l.translationPercent},
                         {"rotation_deg_per_m", l.rotationDegPerMetre}});
  }
  if (cli.json()) {
    printJsonLine({{"command", "kitti"},
                   {"gt", cli.option("gt")},
                   {"est", cli.option("est")},
                   {"frames", r.frames},
                   {"segments", r.segments},
                   {"translation_percent", r.translationPercent},
                   {"rotation_deg_per_m", r.rotationDegPerMetre},
                   {"per_length", perLength}});
  }
  return kExitSuccess;
}

int relations(int argc, char** argv) {
  CommandLine cli("rtabmap-eval relations",
                  "Relation-based error of Kuemmerle et al. 2009 (the metric of the Freiburg / Radish "
                  "datasets, e.g. ACES): for each relation `t1 t2 x y z roll pitch yaw`, the error "
                  "delta*^-1 (x1^-1 x2) between the relation and the estimated poses x1, x2 at t1 and t2; "
                  "mean and std of its translation norm (m) and rotation angle (deg). The estimate needs a "
                  "pose at every relation stamp (one per scan).");
  cli.addOption("relations", "FILE", "Relations file (e.g. data/radish/aces.relations).");
  cli.addOption("est", "FILE", "Estimated trajectory, one pose per scan.");
  cli.addOption("format", "FORMAT", std::string("Format of the estimate: ") + kTrajectoryFormats + ".", "auto");
  cli.addOption("max-dt", "SECONDS", "Largest difference between a relation stamp and a pose stamp.", "0.001");
  cli.addOption("local-span", "SECONDS",
                "Relations at most this long in time are also scored apart as local (odometry, neighbour "
                "links), the longer ones as loop (revisits). 0 = no split.",
                "5");
  cli.addOption("worst", "N",
                "Also list the N relations with the largest translational error (file line, stamps, "
                "span, errors): where a mean comes from, e.g. one missed revisit.",
                "0");
  cli.addNote("Example: rtabmap-eval trajectory --dataset carmen --input data/radish/aces.clf.bz2 "
              "--output odom.txt && rtabmap-eval relations --relations data/radish/aces.relations --est odom.txt");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "relations");
  requireOption(cli, "est");
  const std::vector<Relation> rel = readRelations(cli.option("relations"));
  TrajectoryFormat format;
  try {
    format = trajectoryFormatFromName(cli.option("format"));
  } catch (const FormatError& e) {
    throw UsageError(std::string("--format: ") + e.what());
  }
  const Trajectory est = readTrajectory(cli.option("est"), format);
  RelationOptions options;
  options.maxTimeDifference = positiveOption(cli, "max-dt", true);
  options.localSpan = positiveOption(cli, "local-span", true);
  const int worstCount = cli.optionInt("worst");
  if (worstCount < 0) throw UsageError("--worst must be >= 0, got " + cli.option("worst"));
  const RelationResult r = computeRelationError(est, rel, options);
  std::cout << "relations: " << r.used << " of " << r.relations << " used, " << r.skipped
            << " skipped (no estimated pose within " << options.maxTimeDifference << " s of a stamp)\n";
  std::cout << "translational error: " << fixed(r.translation.mean, 4) << " +/- " << fixed(r.translation.std, 4)
            << " m (squared mean " << fixed(r.translationSquaredMean, 4) << " m^2, max "
            << fixed(r.translation.max, 4) << " m)\n";
  std::cout << "rotational error:    " << fixed(r.rotation.mean, 4) << " +/- " << fixed(r.rotation.std, 4)
            << " deg (squared mean " << fixed(r.rotationSquaredMean, 4) << " deg^2, max "
            << fixed(r.rotation.max, 4) << " deg)\n";
  if (options.localSpan > 0.0) {
    const auto split = [&](const std::string& what, const ErrorStats& t, const ErrorStats& a) {
      std::cout << what << fixed(options.localSpan, 1) << " s, " << t.count << "): " << fixed(t.mean, 4)
                << " +/- " << fixed(t.std, 4) << " m, " << fixed(a.mean, 4) << " +/- " << fixed(a.std, 4)
                << " deg\n";
    };
    split("local relations (at most ", r.localTranslation, r.localRotation);
    split("loop relations (over ", r.loopTranslation, r.loopRotation);
  }
  const std::vector<size_t> worst = worstRelations(r, static_cast<size_t>(worstCount));
  if (!worst.empty()) std::cout << "worst relations (file line: t1 -> t2, span, error):\n";
  for (size_t k : worst) {
    const Relation& w = rel[r.usedRelations[k]];
    std::cout << "  line " << w.line << ": " << fixed(w.stamp1, 3) << " -> " << fixed(w.stamp2, 3) << ", "
              << fixed(w.stamp2 - w.stamp1, 1) << " s, " << fixed(r.translationErrors[k], 4) << " m, "
              << fixed(r.rotationErrors[k], 3) << " deg\n";
  }
  // What the reference itself can resolve: errors near a relation's own are not the estimate's.
  const RelationConsistency c = relationConsistency(rel, options.maxTimeDifference);
  if (c.triangles > 0) {
    std::cout << "reference consistency (" << c.triangles << " triangles a->b->c of the relations): "
              << fixed(c.translation.mean, 4) << " +/- " << fixed(c.translation.std, 4) << " m, "
              << fixed(c.rotation.mean, 4) << " deg; a relation's own error ~" << fixed(c.relationRms, 4)
              << " m RMS\n";
  }
  if (cli.json()) {
    printJsonLine({{"command", "relations"},
                   {"relations_file", cli.option("relations")},
                   {"est", cli.option("est")},
                   {"relations", r.relations},
                   {"used", r.used},
                   {"skipped", r.skipped},
                   {"translation", statsJson(r.translation)},
                   {"rotation_deg", statsJson(r.rotation)},
                   {"translation_squared_mean", r.translationSquaredMean},
                   {"rotation_squared_mean_deg2", r.rotationSquaredMean},
                   {"local_span", options.localSpan},
                   {"local", {{"translation", statsJson(r.localTranslation)},
                              {"rotation_deg", statsJson(r.localRotation)}}},
                   {"loop", {{"translation", statsJson(r.loopTranslation)},
                             {"rotation_deg", statsJson(r.loopRotation)}}},
                   {"reference", {{"triangles", c.triangles},
                                  {"translation", statsJson(c.translation)},
                                  {"rotation_deg", statsJson(c.rotation)},
                                  {"relation_rms", c.relationRms}}}});
  }
  return kExitSuccess;
}

// The estimated poses of the largest deviations, at least `gap` seconds apart (one per stretch).
std::vector<size_t> worstStretches(const PathDeviationResult& r, const Trajectory& est, size_t n, double gap) {
  std::vector<size_t> order(r.deviations.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return r.deviations[a] > r.deviations[b]; });
  std::vector<size_t> picked;
  for (size_t k : order) {
    if (picked.size() >= n) break;
    const double stamp = est[r.estimateIndices[k]].stamp;
    const bool apart = std::all_of(picked.begin(), picked.end(), [&](size_t p) {
      return std::fabs(est[r.estimateIndices[p]].stamp - stamp) >= gap;
    });
    if (apart) picked.push_back(k);
  }
  return picked;
}

int path(int argc, char** argv) {
  CommandLine cli("rtabmap-eval path",
                  "Deviation of an estimated trajectory from a reference path when poses cannot be associated "
                  "by stamp (a benchmark pose graph such as intel.g2o, optimised with rtabmap-g2o first): the "
                  "estimate is aligned rigidly onto the polyline through the reference's positions by ICP "
                  "(trimmed), then each estimated position's distance to that polyline is its deviation. It sees "
                  "errors across the path (a bowed corridor, a doubled pass), not along it: a lower bound of the "
                  "trajectory's error, a check of the map's shape.");
  cli.addOption("ref", "FILE", "Reference trajectory (its poses in travel order).");
  cli.addOption("est", "FILE", "Estimated trajectory.");
  cli.addOption("format", "FORMAT", std::string("Format of both files: ") + kTrajectoryFormats + ".", "auto");
  cli.addOption("ref-format", "FORMAT", "Format of the reference (overrides --format).");
  cli.addOption("est-format", "FORMAT", "Format of the estimate (overrides --format).");
  cli.addOption("init", "METHOD",
                "Initial alignment: first (the reference's first pose on the estimate's first: both start "
                "where the robot did) or identity.",
                "first");
  cli.addOption("trim", "METRES",
                "Pairs farther than this (or than the median distance, whichever is larger) are left out of "
                "each alignment step: a stretch off by more does not drag the rest.",
                "0.5");
  cli.addOption("worst", "N", "Also list the N largest deviations, at least --worst-gap seconds apart.", "0");
  cli.addOption("worst-gap", "SECONDS", "Least time between two listed deviations.", "10");
  cli.addOption("aligned", "FILE", "Write the aligned estimate there (TUM).");
  cli.addNote("Example: rtabmap-g2o ../shared/data/posegraphs/intel.g2o intel_opt.g2o && rtabmap-eval path "
              "--ref intel_opt.g2o --est intel/frames.tum");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "ref");
  requireOption(cli, "est");
  const Trajectory ref = loadTrajectory(cli, "ref", "ref-format");
  const Trajectory est = loadTrajectory(cli, "est", "est-format");
  PathDeviationOptions options;
  const std::string init = cli.option("init");
  if (init != "first" && init != "identity") throw UsageError("--init must be first or identity, got " + init);
  options.initFromFirstPoses = init == "first";
  options.trimDistance = positiveOption(cli, "trim", false);
  const int worstCount = cli.optionInt("worst");
  if (worstCount < 0) throw UsageError("--worst must be >= 0, got " + cli.option("worst"));
  const double gap = positiveOption(cli, "worst-gap", true);
  const PathDeviationResult r = computePathDeviation(ref, est, options);
  std::cout << "reference path: " << r.referencePoses << " poses, " << fixed(r.referenceLength, 1) << " m\n";
  std::cout << "alignment: " << r.iterations << " ICP iterations" << (r.converged ? ", converged" : ", not converged")
            << "\n";
  std::cout << "deviation of " << r.estimatedPoses << " estimated positions from the reference path (m): median "
            << fixed(r.stats.median, 4) << "  mean " << fixed(r.stats.mean, 4) << "  rmse " << fixed(r.stats.rmse, 4)
            << "  p90 " << fixed(r.p90, 4) << "  p99 " << fixed(r.p99, 4) << "  max " << fixed(r.stats.max, 4)
            << "\n";
  const std::vector<size_t> worst = worstStretches(r, est, static_cast<size_t>(worstCount), gap);
  if (!worst.empty()) std::cout << "largest deviations (estimate stamp: m):\n";
  for (size_t k : worst) {
    std::cout << "  " << fixed(est[r.estimateIndices[k]].stamp, 3) << ": " << fixed(r.deviations[k], 4) << "\n";
  }
  if (cli.has("aligned")) {
    writeTrajectory(cli.option("aligned"), applyAlignment(est, r.alignment), TrajectoryFormat::kTum);
  }
  if (cli.json()) {
    printJsonLine({{"command", "path"},
                   {"ref", cli.option("ref")},
                   {"est", cli.option("est")},
                   {"reference_poses", r.referencePoses},
                   {"reference_length", r.referenceLength},
                   {"estimated_poses", r.estimatedPoses},
                   {"iterations", r.iterations},
                   {"converged", r.converged},
                   {"deviation", statsJson(r.stats)},
                   {"p90", r.p90},
                   {"p99", r.p99}});
  }
  return kExitSuccess;
}

bool isImagePath(const std::string& path) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return false;
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png" || ext == ".bmp" || ext == ".pgm" || ext == ".ppm" || ext == ".jpg" ||
         ext == ".jpeg" || ext == ".tif" || ext == ".tiff";
}

// A square text matrix of non-negative integers (0/1), as opposed to a trajectory.
bool looksLikeTextMatrix(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  size_t rows = 0, cols = 0;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t\r")] == '#') continue;
    for (char& c : line) {
      if (c == ',') c = ' ';
    }
    std::istringstream s(line);
    std::string tok;
    size_t n = 0;
    while (s >> tok) {
      if (tok.find_first_not_of("0123456789") != std::string::npos) return false;
      ++n;
    }
    if (rows == 0) cols = n;
    if (n != cols) return false;
    ++rows;
  }
  return rows > 0 && rows == cols;
}

int pr(int argc, char** argv) {
  CommandLine cli(
      "rtabmap-eval pr",
      "Loop-closure precision and recall, and the recall at 100% precision obtained by sweeping the "
      "detector's confidence threshold.");
  cli.addOption("detections", "FILE",
                "Detections: one line per query image, `query_id matched_id confidence` (ids 1-based in "
                "image order, matched_id 0 = no loop closure, confidence: higher = surer; optional, 1 if "
                "absent), blank or comma separated, '#' comments.");
  cli.addOption("gt", "FILE",
                "Ground truth: an N x N matrix, as an image (png, bmp, pgm, ...) or a text file of N rows "
                "of N numbers, where element (i-1, j-1) non-zero means images i and j show the same "
                "place (either triangle may be filled); or a trajectory file with one pose per image in "
                "image order (then --distance, --angle, --min-gap decide the loops).");
  cli.addOption("gt-type", "TYPE", "matrix, poses or auto (images and square 0/1 text: matrix).", "auto");
  cli.addOption("format", "FORMAT", std::string("Format of a poses ground truth: ") + kTrajectoryFormats + ".", "auto");
  cli.addOption("distance", "METRES", "Poses ground truth: largest distance between two views of a place.", "2.0");
  cli.addOption("angle", "DEGREES", "Poses ground truth: largest orientation difference (0 = ignore).", "30");
  cli.addOption("min-gap", "N", "Poses ground truth: smallest id difference of a loop (excludes neighbours).", "10");
  cli.addOption("ambiguous-distance", "METRES",
                "Poses ground truth: pairs that are not loops but within this distance (and --ambiguous-angle) "
                "are neither true nor false: views that may overlap (0 = no such band).",
                "0");
  cli.addOption("ambiguous-angle", "DEGREES", "Poses ground truth: largest orientation difference of the ambiguous "
                "band (0 = ignore).", "0");
  cli.addFlag("viewing-direction", "Poses ground truth: the angles are between the poses' viewing directions "
                                   "(their x axes; a camera rolled about its optical axis still sees the place) "
                                   "instead of their whole relative rotation.");
  cli.addOption("threshold", "C", "Confidence threshold for the precision and recall line.", "0");
  cli.addOption("curve", "FILE", "Write the precision-recall curve there (`threshold precision recall tp fp`).");
  cli.addNote("A detection of query q is accepted when matched_id != 0 and confidence >= threshold; it is "
              "a true positive when the ground truth has a loop between q and matched_id. Recall = "
              "accepted true loop closures / images that close a loop with an earlier image.");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "gt");
  requireOption(cli, "detections");
  const std::string gtPath = cli.option("gt");
  std::string type = cli.option("gt-type");
  if (type == "auto") type = (isImagePath(gtPath) || looksLikeTextMatrix(gtPath)) ? "matrix" : "poses";
  LoopGroundTruth gt;
  if (type == "matrix") {
    gt = LoopGroundTruth::readMatrix(gtPath);
  } else if (type == "poses") {
    TrajectoryFormat format;
    try {
      format = trajectoryFormatFromName(cli.option("format"));
    } catch (const FormatError& e) {
      throw UsageError(std::string("--format: ") + e.what());
    }
    Trajectory t = readTrajectory(gtPath, format);
    try {
      LoopGroundTruth::PoseCriteria criteria;
      criteria.maxDistance = positiveOption(cli, "distance", true);
      criteria.maxAngle = positiveOption(cli, "angle", true) * M_PI / 180.0;
      criteria.minFrameGap = cli.optionInt("min-gap");
      criteria.ambiguousDistance = positiveOption(cli, "ambiguous-distance", true);
      criteria.ambiguousAngle = positiveOption(cli, "ambiguous-angle", true) * M_PI / 180.0;
      criteria.viewingDirectionOnly = cli.flag("viewing-direction");
      gt = LoopGroundTruth::fromPoses(t.transforms(), criteria);
    } catch (const FormatError& e) {
      throw UsageError(std::string("--ambiguous-distance: ") + e.what());
    }
  } else {
    throw UsageError("--gt-type must be matrix, poses or auto, got " + type);
  }
  const std::vector<LoopDetection> detections = readLoopDetections(cli.option("detections"));
  const LoopClosurePR r = computeLoopClosurePR(detections, gt, cli.optionDouble("threshold"));
  if (cli.has("curve")) {
    std::ofstream out(cli.option("curve"));
    if (!out) throw Error("cannot write " + cli.option("curve"));
    out << "# threshold precision recall true_positives false_positives\n";
    out.precision(10);
    for (const auto& p : r.curve) {
      out << p.threshold << " " << p.precision << " " << p.recall << " " << p.truePositives << " "
          << p.falsePositives << "\n";
    }
  }
  const bool any100 = std::isfinite(r.thresholdAt100Precision);
  std::cout << "loop closures: " << gt.size() << " images in the ground truth (" << type << "), "
            << r.positives << " closing a loop with an earlier one; " << r.queries << " queries, "
            << r.detections << " with a match";
  if (r.ignored) std::cout << " (" << r.ignored << " with ids outside the ground truth, ignored)";
  std::cout << "\n";
  std::cout << "at threshold " << r.threshold << ": precision " << fixed(100.0 * r.precision, 2) << " %, recall "
            << fixed(100.0 * r.recall, 2) << " % (TP " << r.truePositives << ", FP " << r.falsePositives
            << ", FN " << r.falseNegatives;
  if (r.ambiguous) std::cout << "; " << r.ambiguous << " in the ambiguous band, neither";
  std::cout << ")\n";
  std::cout << "recall at 100% precision: " << fixed(100.0 * r.recallAt100Precision, 2) << " %";
  if (any100) std::cout << " (threshold " << r.thresholdAt100Precision << ")";
  std::cout << "\n";
  if (cli.json()) {
    printJsonLine({{"command", "pr"},
                   {"gt", gtPath},
                   {"gt_type", type},
                   {"detections_file", cli.option("detections")},
                   {"images", gt.size()},
                   {"positives", r.positives},
                   {"queries", r.queries},
                   {"detections", r.detections},
                   {"ignored", r.ignored},
                   {"threshold", r.threshold},
                   {"true_positives", r.truePositives},
                   {"false_positives", r.falsePositives},
                   {"false_negatives", r.falseNegatives},
                   {"ambiguous", r.ambiguous},
                   {"precision", r.precision},
                   {"recall", r.recall},
                   {"recall_at_100_precision", r.recallAt100Precision},
                   {"threshold_at_100_precision",
                    any100 ? nlohmann::json(r.thresholdAt100Precision) : nlohmann::json(nullptr)},
                   {"curve_points", r.curve.size()}});
  }
  return kExitSuccess;
}

int trajectory(int argc, char** argv) {
  CommandLine cli("rtabmap-eval trajectory",
                  "Writes the odometry or the ground truth of a dataset's frames as a trajectory file, "
                  "e.g. to score a dataset's raw odometry, or to make a ground-truth file from a dataset.");
  cli.addOption("dataset", "FORMAT", "Dataset format (carmen, 7scenes, tum, euroc, kitti, images, sim).");
  cli.addOption("input", "PATH", "Dataset file or folder.");
  cli.addOption("output", "FILE", "Trajectory file to write.");
  cli.addOption("source", "WHAT", "odom (the frames' odometry poses) or gt (their ground truth).", "odom");
  cli.addOption("format", "FORMAT", "Output format: tum, kitti or g2o.", "tum");
  cli.addOption("gt-file", "FILE", "Ground-truth file the reader should use (e.g. EuRoC's TUM file).");
  if (auto code = cli.parse(argc, argv)) return *code;
  requireOption(cli, "dataset");
  requireOption(cli, "input");
  requireOption(cli, "output");
  const std::string source = cli.option("source");
  if (source != "odom" && source != "gt") throw UsageError("--source must be odom or gt, got " + source);
  TrajectoryFormat format;
  try {
    format = trajectoryFormatFromName(cli.option("format"));
  } catch (const FormatError& e) {
    throw UsageError(std::string("--format: ") + e.what());
  }
  if (format == TrajectoryFormat::kAuto || format == TrajectoryFormat::kEuroc) {
    throw UsageError("--format must be tum, kitti or g2o");
  }
  DatasetReaderOptions options;
  options.images = false;
  options.scans = false;
  options.imu = false;
  options.odometry = false;
  if (cli.has("gt-file")) options.groundTruthPath = cli.option("gt-file");
  auto reader = openDatasetReader(cli.option("dataset"), cli.option("input"), options);
  const int total = reader->frameCount();
  ProgressBar progress("reading " + cli.option("input"), total > 0 ? static_cast<size_t>(total) : 0, cli);
  Trajectory t;
  size_t frames = 0, missing = 0;
  DatasetRecord record;
  while (reader->next(record)) {
    if (record.kind != DatasetRecord::Kind::kFrame) continue;
    ++frames;
    progress.increment();
    const Transform& pose = source == "odom" ? record.data.odomPose() : record.data.groundTruth();
    if (pose.isNull()) {
      ++missing;
      continue;
    }
    t.add(record.stamp, pose);
  }
  progress.finish();
  if (t.empty()) {
    throw FormatError(cli.option("input") + ": none of the " + std::to_string(frames) + " frames has " +
                      (source == "odom" ? "an odometry pose" : "a ground-truth pose"));
  }
  writeTrajectory(cli.option("output"), t, format);
  std::cout << "wrote " << t.size() << " poses (" << source << ") of " << frames << " frames to "
            << cli.option("output") << (missing ? " (" + std::to_string(missing) + " frames without one)" : "")
            << "\n";
  if (cli.json()) {
    printJsonLine({{"command", "trajectory"},
                   {"dataset", cli.option("dataset")},
                   {"input", cli.option("input")},
                   {"output", cli.option("output")},
                   {"source", source},
                   {"frames", frames},
                   {"poses", t.size()},
                   {"missing", missing}});
  }
  return kExitSuccess;
}

int wrap(const char* name, int (*body)(int, char**), int argc, char** argv) {
  const std::string tool = std::string("rtabmap-eval ") + name;
  return runTool(tool, [&] { return body(argc, argv); });
}

}  // namespace

int runAte(int argc, char** argv) { return wrap("ate", ate, argc, argv); }
int runRpe(int argc, char** argv) { return wrap("rpe", rpe, argc, argv); }
int runKitti(int argc, char** argv) { return wrap("kitti", kitti, argc, argv); }
int runRelations(int argc, char** argv) { return wrap("relations", relations, argc, argv); }
int runPr(int argc, char** argv) { return wrap("pr", pr, argc, argv); }
int runTrajectory(int argc, char** argv) { return wrap("trajectory", trajectory, argc, argv); }
int runPath(int argc, char** argv) { return wrap("path", path, argc, argv); }

const std::vector<SubCommand>& subCommands() {
  static const std::vector<SubCommand> commands = {
      {"ate", "absolute trajectory error (RMSE, mean, median, max) after Horn/Umeyama alignment", runAte},
      {"rpe", "relative pose error per frame or per metre", runRpe},
      {"kitti", "KITTI odometry error: translational % and rotational deg/m over 100..800 m", runKitti},
      {"relations", "Kuemmerle et al. 2009 relation error (ACES, Intel, ... relations files)", runRelations},
      {"path", "deviation from a reference path without stamps (e.g. an optimised benchmark pose graph)", runPath},
      {"pr", "loop-closure precision, recall and recall at 100% precision", runPr},
      {"trajectory", "write a dataset's odometry or ground truth as a trajectory file", runTrajectory},
  };
  return commands;
}

}  // namespace rtabmap::tools::eval
