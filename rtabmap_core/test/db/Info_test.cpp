// rtabmap-info on a database built here: the --json line holds the right numbers, a bad file
// gives the DatabaseError message and exit code 1.
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "common/TestData.h"
#include "db/DbTestUtil.h"
#include "rtabmap_core/db/Database.h"

namespace rtabmap::test::db {
namespace {

using rtabmap::db::Database;

struct ToolRun {
  int exitCode = -1;
  std::string output;  // stdout and stderr
};

ToolRun runTool(const std::string& arguments) {
  const std::string command = toolPath("info") + " " + arguments + " 2>&1";
  ToolRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string lastLine(const std::string& text) {
  std::istringstream lines(text);
  std::string line, last;
  while (std::getline(lines, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

// Two sessions: 6 nodes in map 0, 4 in map 1; one loop closure and one user link across.
void buildDatabase(const std::string& path) {
  {
    Database::Options options;
    options.sessionParameters = "Kp/MaxFeatures=400;Mem/STMSize=10";
    Database db(path, options);
    for (int id = 1; id <= 6; ++id) db.saveNode(makeNode(id, 0, 12), wordsOf(id, 12));
  }
  Database::Options options;
  options.sessionParameters = "Kp/MaxFeatures=500";
  Database db(path, options);
  for (int id = 7; id <= 10; ++id) db.saveNode(makeNode(id, db.sessionMapId(), 12), wordsOf(id, 12));
  db.saveLink(Link(9, 2, Link::kGlobalClosure, Transform(0.1, 0, 0, 0, 0, 0)));
  db.saveLink(Link(10, 3, Link::kUserClosure, Transform(0.2, 0, 0, 0, 0, 0)));
}

TEST(RtabmapInfo, JsonSummaryOfADatabase) {
  TempDir dir;
  const std::string path = dir.file("two_sessions.db");
  buildDatabase(path);
  const ToolRun run = runTool("--json --params-db --check " + path);
  ASSERT_EQ(0, run.exitCode) << run.output;
  const nlohmann::json j = nlohmann::json::parse(lastLine(run.output));
  EXPECT_EQ(rtabmap::db::kSchemaVersion, j.at("version").get<int>());
  EXPECT_EQ(rtabmap::db::kRtabmapRosVersion, j.at("rtabmap_ros_version").get<std::string>());
  EXPECT_EQ(10, j.at("nodes").get<int>());
  ASSERT_EQ(2u, j.at("sessions").size());
  EXPECT_EQ(0, j.at("sessions")[0].at("map_id").get<int>());
  EXPECT_EQ(6, j.at("sessions")[0].at("nodes").get<int>());
  EXPECT_EQ(1, j.at("sessions")[1].at("map_id").get<int>());
  EXPECT_EQ(4, j.at("sessions")[1].at("nodes").get<int>());
  // makeNode links each node to the previous one: 9 neighbors (2..10).
  EXPECT_EQ(9, j.at("links").at("Neighbor").get<int>());
  EXPECT_EQ(1, j.at("links").at("GlobalClosure").get<int>());
  EXPECT_EQ(1, j.at("links").at("UserClosure").get<int>());
  EXPECT_EQ(11, j.at("links_total").get<int>());
  EXPECT_EQ(120, j.at("features").get<int>());
  // Distinct word ids of the 10 nodes (wordIdOf may map two nodes' keypoints to one word).
  std::set<int> words;
  for (int id = 1; id <= 10; ++id)
    for (int i = 0; i < 12; ++i) words.insert(wordIdOf(id, i));
  EXPECT_EQ(static_cast<int>(words.size()), j.at("words").get<int>());
  EXPECT_EQ(static_cast<long long>(std::filesystem::file_size(path)), j.at("size_bytes").get<long long>());
  EXPECT_TRUE(j.at("consistency").at("ok").get<bool>());
  EXPECT_EQ("Kp/MaxFeatures=500", j.at("parameters").get<std::string>());  // the last session's
}

TEST(RtabmapInfo, HumanSummary) {
  TempDir dir;
  const std::string path = dir.file("ltm.db");
  buildDatabase(path);
  const ToolRun run = runTool(path);
  ASSERT_EQ(0, run.exitCode) << run.output;
  EXPECT_NE(std::string::npos, run.output.find("Nodes:           10")) << run.output;
  EXPECT_NE(std::string::npos, run.output.find("session 2: map 1, 4 nodes")) << run.output;
  EXPECT_NE(std::string::npos, run.output.find("GlobalClosure")) << run.output;
}

TEST(RtabmapInfo, BadFileFailsWithTheDatabaseError) {
  TempDir dir;
  const std::string path = dir.file("random.db");
  writeFile(path, std::vector<char>(4096, 'x'));
  ToolRun run = runTool("--json " + path);
  EXPECT_EQ(1, run.exitCode) << run.output;
  EXPECT_NE(std::string::npos, run.output.find("rtabmap-info: error: cannot open database " + path)) << run.output;
  EXPECT_NE(std::string::npos, run.output.find("not an SQLite database")) << run.output;
  run = runTool(dir.file("missing.db"));
  EXPECT_EQ(1, run.exitCode) << run.output;
  EXPECT_NE(std::string::npos, run.output.find("does not exist")) << run.output;
  run = runTool("");
  EXPECT_EQ(2, run.exitCode) << run.output;  // usage error: no database given
}

}  // namespace
}  // namespace rtabmap::test::db
