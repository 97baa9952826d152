// Round trips through the long-term memory: nodes with every part, words, links, sessions,
// neighbours, statistics, updates.
#include <gtest/gtest.h>

#include "common/TestData.h"
#include "db/DbTestUtil.h"
#include "rtabmap_core/db/Database.h"

namespace rtabmap::test::db {
namespace {

using rtabmap::db::Database;
using rtabmap::db::LoadOptions;
using rtabmap::db::NodeUpdate;
using rtabmap::db::StoredStatistics;

TEST(Database, CreatesVersionedEmptyDatabase) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  EXPECT_TRUE(db.isOpen());
  EXPECT_FALSE(db.isReadOnly());
  EXPECT_EQ(rtabmap::db::kSchemaVersion, db.schemaVersion());
  EXPECT_EQ(0, db.sessionMapId());
  EXPECT_EQ(0, db.lastNodeId());
  EXPECT_EQ(0, db.lastWordId());
  EXPECT_TRUE(db.nodeIds().empty());
  const auto summary = db.summary();
  EXPECT_EQ(rtabmap::db::kRtabmapRosVersion, summary.createdBy);
  EXPECT_EQ(1u, summary.sessions.size());
  EXPECT_EQ(0, summary.nodes);
}

TEST(Database, NodeRoundTripIsBitExact) {
  TempDir dir;
  // Node 40 has a neighbor link (diagonal information) and a loop closure (full information
  // matrix, user data).
  const Signature node = makeNode(40, 0, 60);
  const Signature previous = makeNode(39, 0, 60);
  ASSERT_EQ(2u, node.getLinks().size());
  {
    Database db(dir.file("ltm.db"));
    db.saveNode(previous, wordsOf(39, 60));
    db.saveNode(node, wordsOf(40, 60));
    db.close();
  }
  Database db(dir.file("ltm.db"), [] { Database::Options o; o.readOnly = true; return o; }());
  std::optional<Signature> loaded = db.loadNode(40);
  ASSERT_TRUE(loaded);
  expectSameNode(node, *loaded);
  EXPECT_TRUE(loaded->isSaved());
  EXPECT_FALSE(loaded->isModified());
  // The compressed parts decompress to the original matrices.
  SensorData data = loaded->sensorData();
  data.uncompress();
  EXPECT_TRUE(sameMat(randomMat(24, 32, CV_8UC3, 40), data.imageRaw()));
  EXPECT_TRUE(sameMat(randomMat(24, 32, CV_16UC1, 41), data.depthOrRightRaw()));
  EXPECT_TRUE(sameMat(randomMat(1, 10, CV_8UC1, 43), data.userDataRaw()));
  EXPECT_EQ(60, data.laserScanRaw().size());
  EXPECT_FALSE(db.loadNode(999));
  EXPECT_TRUE(db.checkConsistency(true).ok()) << db.checkConsistency(true).toString();
  EXPECT_EQ(0, db.checkConsistency(true).missingWords);
}

TEST(Database, LoadOptionsSelectParts) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  db.saveNode(makeNode(5, 0, 30));
  db.flush();
  const Signature headerOnly = *db.loadNode(5, LoadOptions::nodeOnly());
  EXPECT_TRUE(headerOnly.getLinks().empty());
  EXPECT_TRUE(headerOnly.getWords().empty());
  EXPECT_TRUE(headerOnly.sensorData().imageCompressed().empty());
  EXPECT_EQ(makeNode(5, 0).getPose(), headerOnly.getPose());

  const Signature noData = *db.loadNode(5, LoadOptions::withoutSensorData());
  EXPECT_EQ(1u, noData.getLinks().size());
  EXPECT_EQ(30u, noData.getWords().size());
  EXPECT_EQ(30, noData.getWordsDescriptors().rows);
  EXPECT_TRUE(noData.sensorData().imageCompressed().empty());
  EXPECT_TRUE(noData.sensorData().localGrid().isEmpty());

  LoadOptions scanOnly = LoadOptions::withoutSensorData();
  scanOnly.scan = true;
  scanOnly.wordDescriptors = false;
  const Signature scan = *db.loadNode(5, scanOnly);
  EXPECT_FALSE(scan.sensorData().laserScanCompressed().empty());
  EXPECT_TRUE(scan.sensorData().imageCompressed().empty());
  EXPECT_TRUE(scan.sensorData().depthOrRightCompressed().empty());
  EXPECT_EQ(30u, scan.getWordsKpts().size());
  EXPECT_TRUE(scan.getWordsDescriptors().empty());
  EXPECT_EQ(1u, scan.sensorData().cameraModels().size());
}

TEST(Database, RawSensorDataIsCompressedByTheWriter) {
  TempDir dir;
  Database::Options options;
  options.imageFormat = ".png";  // lossless, to compare
  Database db(dir.file("ltm.db"), options);
  const cv::Mat image = randomMat(24, 32, CV_8UC3, 7);
  const cv::Mat depth = randomMat(24, 32, CV_16UC1, 8);
  Signature node(3, 0, 0, 1.0, "", Transform::Identity());
  node.setSensorData(SensorData(image, depth, CameraModel(500, 500, 16, 12), 3, 1.0));
  db.saveNode(node);
  db.flush();
  Signature loaded = *db.loadNode(3);
  ASSERT_FALSE(loaded.sensorData().imageCompressed().empty());
  loaded.sensorData().uncompress();
  EXPECT_TRUE(sameMat(image, loaded.sensorData().imageRaw()));
  EXPECT_TRUE(sameMat(depth, loaded.sensorData().depthOrRightRaw()));
}

namespace {

void expectSameStereoModels(const std::vector<StereoCameraModel>& expected,
                            const std::vector<StereoCameraModel>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE("stereo camera " + std::to_string(i));
    EXPECT_DOUBLE_EQ(expected[i].left().fx(), actual[i].left().fx());
    EXPECT_DOUBLE_EQ(expected[i].left().cx(), actual[i].left().cx());
    EXPECT_DOUBLE_EQ(expected[i].left().cy(), actual[i].left().cy());
    EXPECT_NEAR(expected[i].baseline(), actual[i].baseline(), 1e-12);
    EXPECT_EQ(expected[i].left().imageSize(), actual[i].left().imageSize());
    EXPECT_TRUE((expected[i].localTransform().inverse() * actual[i].localTransform()).isIdentity(1e-6))
        << actual[i].localTransform().prettyPrint();
  }
}

}  // namespace

TEST(Database, SeveralStereoCamerasRoundTrip) {
  TempDir dir;
  Database::Options options;
  options.imageFormat = ".png";  // lossless, to compare
  Database db(dir.file("ltm.db"), options);
  // Two stereo cameras of 24x24 side by side, different baselines and mountings.
  const Transform front = Transform(0.1, 0.0, 1.0, 0.0, 0.0, 0.0) * CameraModel::opticalRotation();
  const Transform left = Transform(0.0, 0.1, 1.0, 0.0, 0.0, M_PI / 2) * CameraModel::opticalRotation();
  const std::vector<StereoCameraModel> models = {StereoCameraModel(30.0, 30.0, 11.5, 11.5, 0.12, front, cv::Size(24, 24)),
                                                 StereoCameraModel(32.0, 32.0, 12.0, 11.0, 0.2, left, cv::Size(24, 24))};
  const cv::Mat leftImages = randomMat(24, 48, CV_8UC3, 9);
  const cv::Mat rightImages = randomMat(24, 48, CV_8UC1, 10);
  Signature node(7, 0, 0, 1.0, "", Transform::Identity());
  node.setSensorData(SensorData(leftImages, rightImages, models, 7, 1.0));
  db.saveNode(node);
  // Before the writer ran (the queued node), images without the right ones, then from the file.
  LoadOptions leftOnly;
  leftOnly.depthOrRight = false;
  const Signature queued = *db.loadNode(7, leftOnly);
  expectSameStereoModels(models, queued.sensorData().stereoCameraModels());
  db.flush();
  Signature loaded = *db.loadNode(7);
  expectSameStereoModels(models, loaded.sensorData().stereoCameraModels());
  loaded.sensorData().uncompress();
  EXPECT_TRUE(sameMat(leftImages, loaded.sensorData().imageRaw()));
  EXPECT_TRUE(sameMat(rightImages, loaded.sensorData().depthOrRightRaw()));
  expectSameStereoModels(models, db.loadNode(7, leftOnly)->sensorData().stereoCameraModels());
}

TEST(Database, ResavingWithoutDataKeepsStoredData) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  const Signature full = makeNode(8, 0, 25);
  db.saveNode(full);
  db.flush();
  // A node back from the LTM without its data, with a new weight, goes back to the LTM.
  Signature light = *db.loadNode(8, LoadOptions::nodeOnly());
  light.setWeight(42);
  db.saveNode(light);
  db.flush();
  Signature reloaded = *db.loadNode(8);
  EXPECT_EQ(42, reloaded.weight());
  EXPECT_EQ(full.sensorData().imageCompressed(), reloaded.sensorData().imageCompressed());
  EXPECT_EQ(25u, reloaded.getWords().size());
  EXPECT_TRUE(reloaded.getLinks().empty());  // links are what the node holds: none now
  EXPECT_TRUE(db.checkConsistency().ok());
  EXPECT_EQ(25, db.summary().features);
}

TEST(Database, WordsRoundTrip) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  std::vector<rtabmap::db::StoredWord> words;
  for (int id = 1; id <= 100; ++id) words.push_back({id, randomMat(1, 32, CV_8UC1, id)});
  words.push_back({500, randomMat(1, 128, CV_32FC1, 500)});  // SIFT-like descriptor
  db.saveWords(words);
  // Visible before the writer writes them, and after.
  std::vector<rtabmap::db::StoredWord> early = db.loadWords({500, 3});
  ASSERT_EQ(2u, early.size());
  db.flush();
  const std::vector<rtabmap::db::StoredWord> loaded = db.loadWords({3, 999, 500, 100});
  ASSERT_EQ(3u, loaded.size());  // 999 does not exist
  EXPECT_EQ(3, loaded[0].id);
  EXPECT_TRUE(sameMat(words[2].descriptor, loaded[0].descriptor));
  EXPECT_EQ(500, loaded[1].id);
  EXPECT_TRUE(sameMat(words[100].descriptor, loaded[1].descriptor));
  EXPECT_EQ(100, loaded[2].id);
  EXPECT_EQ(500, db.lastWordId());
  EXPECT_EQ(101, db.summary().words);
}

TEST(Database, MultiSessionContinuesIdsAndMaps) {
  TempDir dir;
  const std::string path = dir.file("ltm.db");
  {
    Database::Options options;
    options.sessionParameters = "Mem/STMSize=10";
    Database db(path, options);
    EXPECT_EQ(0, db.sessionMapId());
    for (int id = 1; id <= 10; ++id) db.saveNode(makeNode(id, db.sessionMapId(), 10), wordsOf(id, 10));
  }
  {
    Database::Options options;
    options.sessionParameters = "Mem/STMSize=20";
    Database db(path, options);
    EXPECT_EQ(1, db.sessionMapId());
    EXPECT_EQ(10, db.lastNodeId());  // the new session continues after node 10
    const int first = db.lastNodeId() + 1;
    for (int id = first; id < first + 5; ++id) {
      Signature node = makeNode(id, db.sessionMapId(), 10);
      if (id == first) node.removeLinks();  // a new map starts unlinked...
      db.saveNode(node, wordsOf(id, 10));
    }
    // ...until a loop closure joins it to the first session's map.
    db.saveLink(Link(13, 4, Link::kGlobalClosure, Transform(0.1, 0.0, 0.0, 0.0, 0.0, 0.0)));
  }
  Database::Options readOnly;
  readOnly.readOnly = true;
  Database db(path, readOnly);
  const auto sessions = db.sessions();
  ASSERT_EQ(2u, sessions.size());
  EXPECT_EQ(0, sessions[0].mapId);
  EXPECT_EQ(1, sessions[1].mapId);
  EXPECT_EQ("Mem/STMSize=10", sessions[0].parameters);
  EXPECT_EQ("Mem/STMSize=20", db.lastSessionParameters());
  EXPECT_GT(sessions[0].endTime, 0.0);
  const auto summary = db.summary();
  ASSERT_EQ(2u, summary.sessions.size());
  EXPECT_EQ(10, summary.sessions[0].nodes);
  EXPECT_EQ(5, summary.sessions[1].nodes);
  EXPECT_EQ(15, summary.nodes);
  // Neighbours: 9 in session 0 (2..10) + 4 in session 1 (12..15); one global closure.
  EXPECT_EQ(13, summary.linksPerType.at(Link::kNeighbor));
  EXPECT_EQ(1, summary.linksPerType.at(Link::kGlobalClosure));
  // The loop closure is seen from both ends, the other end with the inverse transform.
  const auto from13 = db.loadLinks(13);
  const auto from4 = db.loadLinks(4);
  ASSERT_EQ(1u, from4.count(13));
  EXPECT_EQ(Link::kGlobalClosure, from4.find(13)->second.type());
  EXPECT_TRUE(from4.find(13)->second.transform().getDistance(Transform(-0.1, 0, 0, 0, 0, 0)) < 1e-12);
  bool closure = false;
  for (const auto& [to, link] : from13) closure |= (to == 4 && link.type() == Link::kGlobalClosure);
  EXPECT_TRUE(closure);
  // All links once each, across sessions.
  const auto all = db.loadAllLinks();
  EXPECT_EQ(14u, all.size());
  EXPECT_EQ(15u, db.loadAllLinks(true).size());  // the closure from both ends
  const auto headers = db.loadAllNodeHeaders();
  EXPECT_EQ(15u, headers.size());
  EXPECT_EQ(1, headers.at(12).mapId());
}

TEST(Database, NeighborsUpToDepth) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  // A chain 1-2-...-30 (neighbor links), closure 20 -> 1.
  for (int id = 1; id <= 30; ++id) {
    Signature node = makeNode(id, 0, 5);
    db.saveNode(node);
    if (id > 1) db.saveLink(Link(id - 1, id, Link::kNeighbor, Transform(0.5, 0, 0, 0, 0, 0)));
  }
  // Before and after the writer catches up: the same answer.
  const std::map<int, int> queued = db.neighborIds(10, 2);
  db.flush();
  const std::map<int, int> written = db.neighborIds(10, 2);
  EXPECT_EQ(queued, written);
  EXPECT_EQ((std::map<int, int>{{8, 2}, {9, 1}, {10, 0}, {11, 1}, {12, 2}}), written);
  // Node 20 has a loop closure to 1 (makeNode): 1 is one hop away.
  const std::map<int, int> around20 = db.neighborIds(20, 1);
  EXPECT_EQ((std::map<int, int>{{1, 1}, {19, 1}, {20, 0}, {21, 1}}), around20);
  EXPECT_EQ((std::map<int, int>{{10, 0}}), db.neighborIds(10, 0));
  EXPECT_TRUE(db.neighborIds(99, 3).empty());
  const std::vector<Signature> nodes = db.loadNeighbors(20, 1, LoadOptions::withoutSensorData());
  ASSERT_EQ(4u, nodes.size());
  EXPECT_EQ(1, nodes[0].id());
  EXPECT_EQ(21, nodes[3].id());
}

TEST(Database, UpdatesAndLinkRemoval) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  for (int id = 1; id <= 3; ++id) db.saveNode(makeNode(id, 0, 5));
  db.saveLink(Link(1, 2, Link::kNeighbor, Transform(0.5, 0, 0, 0, 0, 0)));
  NodeUpdate update;
  update.id = 2;
  update.weight = 9;
  update.label = "kitchen";
  update.pose = Transform(1, 2, 3, 0, 0, 0);
  db.updateNode(update);
  // Seen before being written...
  Signature queued = *db.loadNode(2);
  EXPECT_EQ(9, queued.weight());
  EXPECT_EQ("kitchen", queued.label());
  db.flush();
  // ...and after.
  Signature written = *db.loadNode(2);
  EXPECT_EQ(9, written.weight());
  EXPECT_EQ("kitchen", written.label());
  EXPECT_EQ(Transform(1, 2, 3, 0, 0, 0), written.getPose());
  EXPECT_EQ((std::map<int, std::string>{{2, "kitchen"}}), db.labels());
  EXPECT_TRUE(written.hasLink(1, Link::kNeighbor));

  db.removeLink(2, 1, Link::kNeighbor);
  EXPECT_FALSE(db.loadNode(2)->hasLink(1));
  EXPECT_FALSE(db.loadNode(1)->hasLink(2));
  db.flush();
  EXPECT_FALSE(db.loadNode(2)->hasLink(1));
  EXPECT_FALSE(db.loadNode(1)->hasLink(2));
  update = NodeUpdate();
  update.id = 2;
  update.label = "";
  db.updateNode(update);
  EXPECT_TRUE(db.labels().empty());
  EXPECT_THROW(db.saveLink(Link(1, 3, Link::kTemporary, Transform::Identity())), std::invalid_argument);
}

TEST(Database, TemporaryLinksAreNeverSaved) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  Signature node = makeNode(2, 0, 5);
  node.addLink(Link(2, 1, Link::kTemporary, Transform::Identity()));
  db.saveNode(node);
  EXPECT_FALSE(db.loadNode(2)->hasLink(1, Link::kTemporary));
  db.flush();
  EXPECT_FALSE(db.loadNode(2)->hasLink(1, Link::kTemporary));
  EXPECT_TRUE(db.loadNode(2)->hasLink(1, Link::kNeighbor));
}

TEST(Database, StatisticsRoundTrip) {
  TempDir dir;
  Database db(dir.file("ltm.db"));
  StoredStatistics stats;
  stats.nodeId = 4;
  stats.stamp = 12.5;
  stats.data = {{"Timing/Total/ms", 12.345678f}, {"Loop/Highest_hypothesis_id/", 3.0f},
                {"Custom/Name with space/ms", -1e-7f}};
  stats.wmState = {1, 2, 3, 4};
  db.saveStatistics(stats);
  db.flush();
  const auto loaded = db.loadStatistics(4);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(stats.stamp, loaded->stamp);
  EXPECT_EQ(stats.data, loaded->data);
  EXPECT_EQ(stats.wmState, loaded->wmState);
  EXPECT_FALSE(db.loadStatistics(5));
  EXPECT_EQ(1, db.summary().statistics);
}

TEST(Database, OptionsValidation) {
  Database::Options options;
  std::string why;
  EXPECT_TRUE(options.IsValid(&why)) << why;
  options.maxBatchNodes = 0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_NE(std::string::npos, why.find("maxBatchNodes")) << why;
  TempDir dir;
  Database db;
  EXPECT_THROW(db.open(dir.file("x.db"), options), std::invalid_argument);
  EXPECT_FALSE(db.isOpen());

  const Database::Options fromParams = Database::Options::fromParameters(
      {{"DbSqlite3/JournalMode", "2"}, {"DbSqlite3/Synchronous", "2"}, {"DbSqlite3/CacheSize", "500"}});
  EXPECT_EQ(Database::Options::JournalMode::kPersist, fromParams.journalMode);
  EXPECT_EQ(Database::Options::Synchronous::kFull, fromParams.synchronous);
  EXPECT_EQ(500, fromParams.cacheSize);
  EXPECT_THROW(Database::Options::fromParameters({{"DbSqlite3/InMemory", "true"}}), ParameterError);
}

TEST(Database, OtherJournalModesWork) {
  TempDir dir;
  Database::Options options;
  options.journalMode = Database::Options::JournalMode::kDelete;
  options.synchronous = Database::Options::Synchronous::kFull;
  {
    Database db(dir.file("ltm.db"), options);
    for (int id = 1; id <= 5; ++id) db.saveNode(makeNode(id, 0, 10));
    db.flush();
    EXPECT_EQ(5u, db.nodeIds().size());
  }
  Database db(dir.file("ltm.db"));
  expectSameNode(makeNode(5, 0, 10), *db.loadNode(5));
}

}  // namespace
}  // namespace rtabmap::test::db
