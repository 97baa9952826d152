// The long-term memory's RAM does not grow with the database (issue 10, the soak's memory goal):
// SQLite keeps every page a connection touched in its page cache, up to DbSqlite3/CacheSize
// pages, and gives nothing back while the database is open. With the former default (10000
// pages of 16 KB, 160 MB per connection, two connections) the soak's node grew with its 860 MB
// database for its first half hour (the writer's cache filling), 160 MB in all. This test
// writes and reads back several times the bound it sets, and reads SQLite's own count of the
// bytes it holds: the setting must reach every connection, and bound it.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <opencv2/core.hpp>

#include <string>

#include "../common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

// A node whose image is `bytes` of noise (stored as given: noise does not compress).
Signature bulkyNode(int id, int bytes) {
  Signature node(id, 0, 0, 1000.0 + id, "", Transform(0.5 * id, 0.0, 0.0, 0.0, 0.0, 0.0), Transform());
  cv::Mat noise(1, bytes, CV_8UC1);
  cv::RNG(id).fill(noise, cv::RNG::UNIFORM, 0, 256);
  SensorData data;
  data.setCompressed(Bytes(noise.data, noise.data + bytes), Bytes(), Bytes(), Bytes());
  node.setSensorData(data);
  return node;
}

TEST(LtmCache, PageCacheDoesNotGrowWithTheDatabase) {
  test::TempDir dir;
  ParametersMap parameters = Parameters::defaults();
  parameters[Parameters::kDbSqlite3CacheSize()] = "1000";  // 16 MB of 16 KB pages
  const db::DatabaseOptions options = db::DatabaseOptions::fromParameters(parameters);
  const sqlite3_int64 before = sqlite3_memory_used();
  constexpr int kNodes = 400, kBytes = 200 * 1024;  // 80 MB of blobs
  {
    db::Database database(dir.file("ltm.db"), options);
    for (int id = 1; id <= kNodes; ++id) database.saveNode(bulkyNode(id, kBytes));
    database.flush();
    // Reads too: a retrieval must not keep what it loaded either.
    for (int id = 1; id <= kNodes; id += 3) ASSERT_TRUE(database.loadNode(id).has_value());
    const sqlite3_int64 held = sqlite3_memory_used() - before;
    // Both connections at most full, plus SQLite's own bookkeeping (schema, statements).
    const sqlite3_int64 bound = 2LL * options.cacheSize * options.pageSize + 4 * 1024 * 1024;
    EXPECT_LT(held, bound) << "SQLite holds " << held / 1024 << " KB after writing " << kNodes * kBytes / 1024
                           << " KB of nodes (page cache: " << options.cacheSize << " pages of "
                           << options.pageSize << " bytes per connection)";
    // The bound itself is well below what was written: otherwise this test could not fail.
    EXPECT_LT(bound, static_cast<sqlite3_int64>(kNodes) * kBytes / 2);
  }
  EXPECT_LT(sqlite3_memory_used() - before, 1024 * 1024) << "closing the database gives its caches back";
}

}  // namespace
}  // namespace rtabmap
