#pragma once
// One dataset -> bag conversion as rtabmap-bag runs it: open the reader, write the bag with a
// progress bar, and describe the result (for the human report, --json and --bench).
#include <nlohmann/json.hpp>

#include <string>

#include "rtabmap_conversions/DatasetBag.h"
#include "rtabmap_core/eval/DatasetReader.h"

namespace rtabmap_bag {

struct ConversionRequest {
  std::string format;
  std::string input;
  std::string output;
  rtabmap::DatasetReaderOptions reader;
  rtabmap_conversions::BagWriterOptions writer;
};

struct ConversionResult {
  rtabmap_conversions::BagSummary summary;
  double wallSeconds = 0.0;  // reading + writing
  double messagesPerSecond() const { return wallSeconds > 0.0 ? summary.messages / wallSeconds : 0.0; }
};

// showProgress: a progress bar on stderr (live on a terminal, else one final line).
ConversionResult convert(const ConversionRequest& request, bool showProgress, bool live);

nlohmann::json toJson(const ConversionRequest& request, const ConversionResult& result);
// Human report: topics with counts, time span, size, throughput.
std::string toText(const ConversionRequest& request, const ConversionResult& result);

}  // namespace rtabmap_bag
