#include "Conversion.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "common/ProgressBar.h"

namespace rtabmap_bag {

ConversionResult convert(const ConversionRequest& request, bool showProgress, bool live) {
  const auto start = std::chrono::steady_clock::now();
  // Both ends are opened before any progress is shown, so a wrong input or an unwritable
  // output fails at once.
  std::unique_ptr<rtabmap::DatasetReader> reader =
      rtabmap::openDatasetReader(request.format, request.input, request.reader);
  auto writer = std::make_unique<rtabmap_conversions::DatasetBagWriter>(request.output, request.writer);
  const int total = reader->frameCount();
  std::optional<rtabmap::tools::ProgressBar> progress;
  if (showProgress) progress.emplace("writing " + request.output, total > 0 ? size_t(total) : 0, live, std::cerr);
  ConversionResult result;
  try {
    rtabmap::DatasetRecord record;
    while (reader->next(record)) {
      writer->add(record);
      if (progress) progress->update(writer->summary().frames);
    }
    result.summary = writer->close();
  } catch (...) {
    // A bag cut short by bad data would replay as if it were the whole dataset: remove it.
    writer.reset();
    std::error_code ec;
    std::filesystem::remove(request.output, ec);
    throw;
  }
  if (progress) progress->finish();
  result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

nlohmann::json toJson(const ConversionRequest& request, const ConversionResult& result) {
  const rtabmap_conversions::BagSummary& s = result.summary;
  nlohmann::json topics = nlohmann::json::object();
  for (const auto& [topic, count] : s.messagesPerTopic) topics[topic] = count;
  return {{"format", request.format},
          {"input", request.input},
          {"output", request.output},
          {"messages", s.messages},
          {"topics", topics},
          {"frames", s.frames},
          {"records", s.records},
          {"out_of_order_records", s.outOfOrder},
          {"start", s.startTime},
          {"end", s.endTime},
          {"duration", s.duration()},
          {"time_offset", s.timeOffset},
          {"bytes", s.bytes},
          {"wall_seconds", result.wallSeconds},
          {"messages_per_second", result.messagesPerSecond()}};
}

std::string toText(const ConversionRequest& request, const ConversionResult& result) {
  const rtabmap_conversions::BagSummary& s = result.summary;
  std::ostringstream out;
  char line[256];
  out << "bag:      " << request.output << "\n";
  std::snprintf(line, sizeof(line), "from:     %s dataset %s (%llu records, %llu sensor frames)\n",
                request.format.c_str(), request.input.c_str(), (unsigned long long)s.records,
                (unsigned long long)s.frames);
  out << line;
  std::snprintf(line, sizeof(line), "time:     %.6f .. %.6f (%.1f s)%s\n", s.startTime, s.endTime, s.duration(),
                s.timeOffset != 0.0 ? (" = dataset time + " + std::to_string(s.timeOffset) + " s").c_str() : "");
  out << line;
  std::snprintf(line, sizeof(line), "size:     %.1f MiB\n", s.bytes / 1048576.0);
  out << line;
  out << "topics:\n";
  for (const auto& [topic, count] : s.messagesPerTopic) {
    std::snprintf(line, sizeof(line), "  %-40s %8llu msgs\n", topic.c_str(), (unsigned long long)count);
    out << line;
  }
  if (s.outOfOrder > 0) {
    out << "warning:  " << s.outOfOrder << " records came older than an earlier one (rosbag plays them in time order)\n";
  }
  std::snprintf(line, sizeof(line), "written:  %llu messages in %.2f s (%.0f messages/s)\n",
                (unsigned long long)s.messages, result.wallSeconds, result.messagesPerSecond());
  out << line;
  return out.str();
}

}  // namespace rtabmap_bag
