#pragma once
// The run of rtabmap-console, apart from its command line (tested directly).
#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "rtabmap_core/eval/LoopClosureEval.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::tools::console {

struct ConsoleOptions {
  // Datasets processed one after the other by the same memory (several sessions of one map).
  std::vector<std::string> inputs;
  std::string format = "images";  // any dataset format (rtabmap-eval's readers): its camera images are used
  std::string outputDir = ".";
  std::string groundTruthPath;  // "" = no scoring
  int maxImages = 0;
  ParametersMap parameters;
  bool progress = true;
};

struct ConsoleReport {
  int images = 0;
  int loopClosures = 0;           // accepted
  int rehearsalMerges = 0;
  double meanUpdateMs = 0.0, maxUpdateMs = 0.0;
  int maxWmSize = 0, maxVocabularySize = 0;
  int transferred = 0, retrieved = 0;
  std::string databasePath, logPath, detectionsPath;
  std::string groundTruthPath;  // written when the dataset has ground truth ("" otherwise)
  std::optional<LoopClosurePR> pr;  // with a ground truth: at Rtabmap/LoopThr, and the sweep
};

ConsoleReport run(const ConsoleOptions& options);
void printReport(const ConsoleReport& report, std::ostream& out);
nlohmann::json toJson(const ConsoleReport& report);

}  // namespace rtabmap::tools::console
