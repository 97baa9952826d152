// The "carmen" reader on hand-written CLF lines (plain and bzip2) and on the shipped Radish logs.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>

#include "common/TestData.h"
#include "eval/EvalTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/RelationError.h"

using rtabmap::DatasetReaderOptions;
using rtabmap::DatasetRecord;
using rtabmap::FormatError;
using rtabmap::Transform;
using rtabmap::test::readAll;
using rtabmap::test::TempDir;
using rtabmap::test::writeText;
using Kind = rtabmap::DatasetRecord::Kind;

namespace {

std::string flaser(const std::vector<double>& ranges, double ox, double oy, double oth, const std::string& ts) {
  std::ostringstream s;
  s << "FLASER " << ranges.size();
  for (double r : ranges) s << " " << r;
  s << " " << ox << " " << oy << " " << oth << " " << ox << " " << oy << " " << oth << " " << ts << " nohost 0.5\n";
  return s.str();
}

std::vector<double> ranges(double value, size_t n = 180) { return std::vector<double>(n, value); }

// Two scans out of order (1.15 is logged before 1.12), odometry between, a PARAM offset.
std::string sampleLog() {
  std::vector<double> first = ranges(2.0);
  first[0] = 0.0;    // invalid reading
  first[1] = 100.0;  // beyond 80 m: no return
  std::string log =
      "# message_name [message contents] ipc_timestamp ipc_hostname logger_timestamp\n"
      "PARAM robot_frontlaser_offset 0.1 nohost 0\n"
      "ODOM 0.0 0.0 0.0 0.0 0.0 0.0 1.0 nohost 0.0\n";
  log += flaser(first, 0.5, 0.25, 0.1, "1.05");
  log += "ODOM 1.0 2.0 0.3 0.0 0.0 0.0 1.1 nohost 0.1\n";
  log += flaser(ranges(3.0), 1.5, 2.5, 0.4, "1.15");
  log += "SYNC tag 1.13 nohost 0.1\n";
  log += flaser(ranges(4.0), 1.2, 2.2, 0.35, "1.12");
  return log;
}

void expectSampleRecords(const std::vector<DatasetRecord>& records) {
  ASSERT_EQ(records.size(), 5u);
  const Kind kinds[5] = {Kind::kOdometry, Kind::kFrame, Kind::kOdometry, Kind::kFrame, Kind::kFrame};
  const double stamps[5] = {1.0, 1.05, 1.1, 1.12, 1.15};
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(records[i].kind, kinds[i]) << i;
    EXPECT_DOUBLE_EQ(records[i].stamp, stamps[i]) << i;
    EXPECT_DOUBLE_EQ(records[i].data.stamp(), stamps[i]) << i;
  }
  // Frame ids follow time order.
  EXPECT_EQ(records[1].data.id(), 1);
  EXPECT_EQ(records[3].data.id(), 2);
  EXPECT_EQ(records[4].data.id(), 3);
  // Odometry of ODOM and FLASER.
  EXPECT_NEAR(records[2].data.odomPose().x(), 1.0, 1e-12);
  EXPECT_NEAR(records[2].data.odomPose().y(), 2.0, 1e-12);
  EXPECT_NEAR(records[2].data.odomPose().theta(), 0.3, 1e-12);
  EXPECT_NEAR(records[1].data.odomPose().x(), 0.5, 1e-12);
  EXPECT_NEAR(records[1].data.odomPose().y(), 0.25, 1e-12);
  EXPECT_NEAR(records[1].data.odomPose().theta(), 0.1, 1e-12);
  EXPECT_NEAR(records[3].data.odomPose().x(), 1.2, 1e-12);
  // Scan: 180 beams, the 0 m and 100 m readings dropped; first kept beam is beam 2 at -88 deg.
  const rtabmap::LaserScan& scan = records[1].data.laserScanRaw();
  EXPECT_EQ(scan.maxPoints(), 180);
  EXPECT_EQ(scan.size(), 178);
  EXPECT_TRUE(scan.is2d());
  EXPECT_DOUBLE_EQ(scan.rangeMax(), 80.0);
  const Eigen::Vector3f p = scan.point(0);
  const double a = -M_PI / 2 + 2 * M_PI / 180;
  EXPECT_NEAR(p.x(), 2.0 * std::cos(a), 1e-5);
  EXPECT_NEAR(p.y(), 2.0 * std::sin(a), 1e-5);
  // Last beam at +89 deg (180 beams 1 degree apart from -90).
  const Eigen::Vector3f last = scan.point(scan.size() - 1);
  EXPECT_NEAR(std::atan2(last.y(), last.x()), 89.0 * M_PI / 180.0, 1e-5);
  // Laser 0.1 m ahead of the robot (PARAM robot_frontlaser_offset).
  EXPECT_NEAR(scan.localTransform().x(), 0.1, 1e-12);
  EXPECT_NEAR(scan.localTransform().y(), 0.0, 1e-12);
  EXPECT_EQ(records[3].data.laserScanRaw().size(), 180);
  EXPECT_NEAR(records[3].data.laserScanRaw().point(0).norm(), 4.0, 1e-5);
}

}  // namespace

TEST(CarmenReader, ReadsFramesOdometryInTimeOrder) {
  TempDir dir;
  writeText(dir.file("log.clf"), sampleLog());
  auto reader = rtabmap::openDatasetReader("carmen", dir.file("log.clf"));
  EXPECT_EQ(reader->format(), "carmen");
  EXPECT_EQ(reader->frameCount(), 3);
  expectSampleRecords(readAll(*reader));
}

TEST(CarmenReader, Bzip2IsDecompressedAsAStream) {
  TempDir dir;
  // Whatever the extension: the magic bytes decide.
  writeText(dir.file("log.clf.bz2"), rtabmap::test::bz2Compress(sampleLog()));
  expectSampleRecords(readAll("carmen", dir.file("log.clf.bz2")));
  // Two concatenated streams (as pbzip2 writes) read as one file.
  const std::string log = sampleLog();
  const size_t cut = log.find("ODOM 1.0");
  writeText(dir.file("two.bz2"), rtabmap::test::bz2Compress(log.substr(0, cut)) +
                                     rtabmap::test::bz2Compress(log.substr(cut)));
  expectSampleRecords(readAll("carmen", dir.file("two.bz2")));
}

TEST(CarmenReader, CorruptOrTruncatedBzip2IsAFormatError) {
  TempDir dir;
  std::string big;
  for (int i = 0; i < 400; ++i) big += flaser(ranges(1.0 + i * 0.001), i, 0, 0, std::to_string(10 + i));
  const std::string z = rtabmap::test::bz2Compress(big);
  writeText(dir.file("cut.bz2"), z.substr(0, z.size() / 2));
  EXPECT_THROW(readAll("carmen", dir.file("cut.bz2")), FormatError);
  std::string corrupt = z;
  for (size_t i = z.size() / 3; i < z.size() / 3 + 64; ++i) corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
  writeText(dir.file("corrupt.bz2"), corrupt);
  EXPECT_THROW(readAll("carmen", dir.file("corrupt.bz2")), FormatError);
}

TEST(CarmenReader, WindowKeepsOdometryLeadingToTheFirstFrame) {
  TempDir dir;
  writeText(dir.file("log.clf"), sampleLog());
  DatasetReaderOptions options;
  options.startFrame = 1;
  options.maxFrames = 1;
  auto reader = rtabmap::openDatasetReader("carmen", dir.file("log.clf"), options);
  EXPECT_EQ(reader->frameCount(), 1);
  const auto records = readAll(*reader);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].kind, Kind::kOdometry);
  EXPECT_DOUBLE_EQ(records[0].stamp, 1.1);
  EXPECT_EQ(records[1].kind, Kind::kFrame);
  EXPECT_DOUBLE_EQ(records[1].stamp, 1.12);
  EXPECT_EQ(records[1].data.id(), 2);

  options = DatasetReaderOptions();
  options.odometry = false;
  options.scans = false;
  const auto frames = readAll("carmen", dir.file("log.clf"), options);
  ASSERT_EQ(frames.size(), 3u);
  for (const auto& r : frames) {
    EXPECT_EQ(r.kind, Kind::kFrame);
    EXPECT_TRUE(r.data.laserScanRaw().empty());
    EXPECT_FALSE(r.data.odomPose().isNull());
  }
}

TEST(CarmenReader, MalformedLinesNameFileAndLine) {
  TempDir dir;
  const std::string head = "PARAM robot_frontlaser_offset 0.0 nohost 0\nODOM 0 0 0 0 0 0 1.0 nohost 0\n";
  // Declares 180 readings, holds 170 of them.
  std::string shortLine = flaser(ranges(2.0, 170), 0, 0, 0, "1.1");
  shortLine.replace(0, 10, "FLASER 180");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"short.clf", head + shortLine},
      {"badnum.clf", head + "ODOM 0 0 0.x 0 0 0 1.3 nohost 0\n"},
      {"odomfields.clf", head + "ODOM 0 0 0 0 0 1.3 nohost 0\n"},
      {"count.clf", head + "FLASER many 1 2 3\n"},
      {"stamp.clf", head + flaser(ranges(2.0), 0, 0, 0, "nan")},
  };
  for (const auto& [name, text] : cases) {
    writeText(dir.file(name), text);
    try {
      readAll("carmen", dir.file(name));
      ADD_FAILURE() << name << ": no error";
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(name + ":3:"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(readAll("carmen", dir.file("missing.clf")), FormatError);
  EXPECT_THROW(readAll("carmen", dir.path()), FormatError);
}

TEST(CarmenReader, RangeMaxFromParamSaturationOrOption) {
  TempDir dir;
  // A reading that repeats at the log's maximum is the no-return value.
  std::string saturated;
  for (int i = 0; i < 12; ++i) {
    std::vector<double> r = ranges(3.0);
    r[i] = 50.0;
    saturated += flaser(r, 0, 0, 0, std::to_string(1.0 + 0.1 * i));
  }
  writeText(dir.file("sat.clf"), saturated);
  auto records = readAll("carmen", dir.file("sat.clf"));
  ASSERT_EQ(records.size(), 12u);
  EXPECT_EQ(records[0].data.laserScanRaw().size(), 179);
  EXPECT_DOUBLE_EQ(records[0].data.laserScanRaw().rangeMax(), 50.0);
  // The same maximum seen only a few times is a real reading: kept, range max 80 m.
  std::string rare;
  for (int i = 0; i < 3; ++i) {
    std::vector<double> r = ranges(3.0);
    r[i] = 50.0;
    rare += flaser(r, 0, 0, 0, std::to_string(1.0 + 0.1 * i));
  }
  writeText(dir.file("rare.clf"), rare);
  records = readAll("carmen", dir.file("rare.clf"));
  EXPECT_EQ(records[0].data.laserScanRaw().size(), 180);
  EXPECT_DOUBLE_EQ(records[0].data.laserScanRaw().rangeMax(), 80.0);
  // A PARAM gives the max range.
  writeText(dir.file("param.clf"), "PARAM robot_front_laser_max 10.0 nohost 0\n" + rare);
  records = readAll("carmen", dir.file("param.clf"));
  EXPECT_EQ(records[0].data.laserScanRaw().size(), 179);
  EXPECT_DOUBLE_EQ(records[0].data.laserScanRaw().rangeMax(), 10.0);
  // And the option overrides everything.
  DatasetReaderOptions options;
  options.scanRangeMax = 2.5;
  records = readAll("carmen", dir.file("param.clf"), options);
  EXPECT_EQ(records[0].data.laserScanRaw().size(), 0);
  EXPECT_EQ(records[0].data.laserScanRaw().maxPoints(), 180);
}

TEST(CarmenReader, RobotLaser1CarriesItsGeometry) {
  TempDir dir;
  // 5 beams from -0.2 rad every 0.1 rad, max 8 m; laser 0.2 m ahead of the robot heading 0.5.
  const double th = 0.5;
  std::ostringstream line;
  line.precision(12);
  line << "ROBOTLASER1 0 -0.2 0.4 0.1 8.0 0.01 0 5 1.0 2.0 8.0 3.0 4.0 5 10 20 30 40 50 "
       << 1.0 + 0.2 * std::cos(th) << " " << 2.0 + 0.2 * std::sin(th) << " " << th << " 1.0 2.0 " << th
       << " 0 0 0 0 0 12.5 nohost 0.1\n";
  writeText(dir.file("rl.clf"), line.str());
  const auto records = readAll("carmen", dir.file("rl.clf"));
  ASSERT_EQ(records.size(), 1u);
  const auto& scan = records[0].data.laserScanRaw();
  EXPECT_DOUBLE_EQ(records[0].stamp, 12.5);
  EXPECT_EQ(scan.maxPoints(), 5);
  EXPECT_EQ(scan.size(), 4);  // 8.0 is at the maximum range: no return
  EXPECT_TRUE(scan.hasIntensity());
  EXPECT_NEAR(scan.localTransform().x(), 0.2, 1e-9);
  EXPECT_NEAR(scan.localTransform().y(), 0.0, 1e-9);
  EXPECT_NEAR(scan.localTransform().theta(), 0.0, 1e-9);
  const Eigen::Vector3f p = scan.point(1);  // beam 1 at -0.1 rad, 2 m
  EXPECT_NEAR(p.x(), 2.0 * std::cos(-0.1), 1e-5);
  EXPECT_NEAR(p.y(), 2.0 * std::sin(-0.1), 1e-5);
  EXPECT_NEAR(records[0].data.odomPose().theta(), th, 1e-12);
}

// End to end on the shipped ACES log: 7,374 scans, every relation stamp among them, and the
// raw odometry's relation error (0.549 m mean translational error, README of ../shared/data).
TEST(CarmenReader, AcesScansAndOdometryRelationError) {
  const std::string log = rtabmap::test::shippedDataPath("radish/aces.clf.bz2");
  const std::string rel = rtabmap::test::shippedDataPath("radish/aces.relations");
  if (log.empty() || rel.empty()) GTEST_SKIP() << "data/radish/aces.* absent";
  auto reader = rtabmap::openDatasetReader("carmen", log);
  EXPECT_EQ(reader->frameCount(), 7374);
  rtabmap::Trajectory odom;
  size_t frames = 0, odometry = 0;
  long long points = 0;
  double previous = -1.0;
  bool ordered = true;
  DatasetRecord r;
  while (reader->next(r)) {
    ordered = ordered && r.stamp >= previous;
    previous = r.stamp;
    if (r.kind == Kind::kFrame) {
      ++frames;
      points += r.data.laserScanRaw().size();
      EXPECT_EQ(r.data.laserScanRaw().maxPoints(), 180);
      odom.add(r.stamp, r.data.odomPose());
    } else if (r.kind == Kind::kOdometry) {
      ++odometry;
    }
  }
  EXPECT_TRUE(ordered);
  EXPECT_EQ(frames, 7374u);
  EXPECT_EQ(odometry, 7375u);
  // The log's 11,139 readings of 50.00 m are its no-returns; every other reading is kept.
  EXPECT_EQ(points, 7374LL * 180 - 11139);

  const std::vector<rtabmap::Relation> relations = rtabmap::readRelations(rel);
  ASSERT_EQ(relations.size(), 1279u);
  std::set<double> stamps;
  for (const auto& x : relations) {
    stamps.insert(x.stamp1);
    stamps.insert(x.stamp2);
  }
  EXPECT_EQ(stamps.size(), 1218u);
  for (double s : stamps) EXPECT_GE(odom.nearest(s, 1e-6), 0) << "relation stamp " << s << " is no scan stamp";

  const rtabmap::RelationResult e = rtabmap::computeRelationError(odom, relations);
  EXPECT_EQ(e.used, 1279u);
  EXPECT_EQ(e.skipped, 0u);
  EXPECT_NEAR(e.translation.mean, 0.549, 0.549 * 0.01);
  RecordProperty("aces_odometry_relation_error_m", std::to_string(e.translation.mean));
  std::cout << "ACES raw odometry relation error: " << e.translation.mean << " +/- " << e.translation.std
            << " m, " << e.rotation.mean << " +/- " << e.rotation.std << " deg\n";
}

// Intel's scans and odometry arrive up to 0.9 s late in the file: the stream is still ordered.
TEST(CarmenReader, IntelIsReorderedInTime) {
  const std::string log = rtabmap::test::shippedDataPath("radish/intel.clf.bz2");
  if (log.empty()) GTEST_SKIP() << "data/radish/intel.clf.bz2 absent";
  DatasetReaderOptions options;
  options.scans = false;
  auto reader = rtabmap::openDatasetReader("carmen", log, options);
  size_t frames = 0, odometry = 0;
  double previous = -1.0;
  size_t disorder = 0;
  DatasetRecord r;
  while (reader->next(r)) {
    if (r.stamp < previous) ++disorder;
    previous = r.stamp;
    (r.kind == Kind::kFrame ? frames : odometry)++;
  }
  EXPECT_EQ(disorder, 0u);
  EXPECT_EQ(frames, 13631u);
  EXPECT_EQ(odometry, 26915u);
}
