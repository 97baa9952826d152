#pragma once
// Versions recorded in every long-term-memory database.
namespace rtabmap::db {

// Layout version of the database this build writes, and the newest it can read. Each schema
// step (src/db/Schema.cpp) raises it by one; a database is upgraded step by step when opened
// for writing. Stored in the Admin table and in PRAGMA user_version.
inline constexpr int kSchemaVersion = 1;

// The rtabmap_ros release writing the database (the <version> of package.xml; keep in step).
inline constexpr const char* kRtabmapRosVersion = "0.1.0";

// PRAGMA application_id of our databases ("RTAB" in ASCII): tells our files from any other
// SQLite database without reading a table.
inline constexpr int kApplicationId = 0x52544142;

}  // namespace rtabmap::db
