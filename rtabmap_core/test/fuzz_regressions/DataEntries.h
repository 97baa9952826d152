#pragma once
// Fuzz entries of the binary and log inputs: CARMEN logs (eval/DatasetReader.h), database
// files (db/Database.h) and the codec's compressed blobs (codec/Compression.h).
#include <filesystem>

#include "FuzzEntry.h"
#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/eval/DatasetReader.h"

namespace rtabmap::fuzz {

// A CARMEN log, read to its end (at most kMaxRecords: a fuzzed log is small anyway).
inline Outcome fuzzCarmen(const uint8_t* data, size_t size) {
  constexpr int kMaxRecords = 100000;
  const std::string path = writeScratchFile(data, size, ".clf");
  return guarded([&] {
    auto reader = openDatasetReader("carmen", path);
    DatasetRecord record;
    for (int i = 0; i < kMaxRecords && reader->next(record); ++i) {
    }
  });
}

// A (mutated) database file opened read-only, then every read a viewer makes of it: summary,
// sessions and their parameters, the graph, a few full nodes with their data, the checks.
inline Outcome fuzzDatabase(const uint8_t* data, size_t size) {
  constexpr size_t kMaxNodesLoaded = 8;
  const std::string path = writeScratchFile(data, size, ".db");
  for (const char* suffix : {"-wal", "-shm"}) std::filesystem::remove(path + suffix);
  return guarded([&] {
    db::DatabaseOptions options;
    options.readOnly = true;
    db::Database database(path, options);
    database.summary();
    database.sessions();
    database.lastSessionParameters();
    database.loadAllNodeHeaders();
    database.loadAllLinks(true);
    database.labels();
    std::vector<int> ids = database.nodeIds();
    if (ids.size() > kMaxNodesLoaded) ids.resize(kMaxNodesLoaded);
    for (const Signature& node : database.loadNodes(ids)) {
      database.loadLinks(node.id());
      database.loadStatistics(node.id());
    }
    if (!ids.empty()) database.neighborIds(ids.front(), 2);
    database.checkConsistency(true);
    database.close();
  });
}

// One blob through every decoder a stored or received blob may meet.
inline Outcome fuzzCodec(const uint8_t* data, size_t size) {
  const Bytes bytes(data, data + size);
  int accepted = 0;
  auto count = [&](Outcome o) { accepted += o == Outcome::kAccepted; };
  count(guarded([&] {
    const cv::Mat m = codec::uncompressData(bytes);
    // Accepted data must re-encode to bytes that decode to the same matrix.
    const cv::Mat again = codec::uncompressData(codec::compressData(m));
    if (again.size() != m.size() || again.type() != m.type()) __builtin_trap();
  }));
  count(guarded([&] { codec::uncompressAny(bytes); }));
  count(guarded([&] { codec::uncompressDepth(bytes); }));
  count(guarded([&] { codec::uncompressImage(bytes); }));
  count(guarded([&] { codec::uncompressBytes(bytes); }));
  return accepted > 0 ? Outcome::kAccepted : Outcome::kRejected;
}

}  // namespace rtabmap::fuzz
