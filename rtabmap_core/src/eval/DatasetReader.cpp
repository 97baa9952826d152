#include "rtabmap_core/eval/DatasetReader.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap {

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, DatasetReaderFactory> factories;
};

// Function-local static: constructed on first use, so a reader registering itself from a
// namespace-scope initialiser of another translation unit finds it ready whatever the order
// in which the library's static initialisers run.
Registry& registry() {
  static Registry instance;
  return instance;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "(none)" : out;
}

}  // namespace

bool registerDatasetFormat(const std::string& name, DatasetReaderFactory factory) {
  if (name.empty() || !factory) {
    throw std::logic_error("registerDatasetFormat: empty name or factory");
  }
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (!r.factories.emplace(name, std::move(factory)).second) {
    throw std::logic_error("registerDatasetFormat: format \"" + name + "\" registered twice");
  }
  return true;
}

std::vector<std::string> datasetFormats() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, factory] : r.factories) names.push_back(name);
  return names;  // std::map keeps them sorted
}

std::unique_ptr<DatasetReader> openDatasetReader(const std::string& format, const std::string& path,
                                                 const DatasetReaderOptions& options) {
  DatasetReaderFactory factory;
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    auto it = r.factories.find(format);
    if (it != r.factories.end()) factory = it->second;
  }
  if (!factory) {
    throw FormatError("unknown dataset format \"" + format + "\" (known: " +
                      joined(datasetFormats()) + ")");
  }
  if (options.startFrame < 0 || options.maxFrames < 0) {
    throw FormatError("dataset options: startFrame and maxFrames must be >= 0 (got " +
                      std::to_string(options.startFrame) + ", " +
                      std::to_string(options.maxFrames) + ")");
  }
  std::unique_ptr<DatasetReader> reader = factory(path, options);
  if (!reader) throw FormatError("dataset format \"" + format + "\": cannot open " + path);
  return reader;
}

}  // namespace rtabmap
