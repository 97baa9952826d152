// The folder readers: 7scenes, tum, euroc, kitti, images, and the format registry.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

#include "common/TestData.h"
#include "eval/EvalTestUtil.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/eval/Trajectory.h"
#include "rtabmap_core/geometry/CameraModel.h"

using rtabmap::CameraModel;
using rtabmap::DatasetReaderOptions;
using rtabmap::DatasetRecord;
using rtabmap::FormatError;
using rtabmap::Transform;
using rtabmap::test::readAll;
using rtabmap::test::TempDir;
using rtabmap::test::writeText;
using Kind = rtabmap::DatasetRecord::Kind;

namespace {

// Median distance from each point of `a` to its nearest point of `b` (brute force).
double medianNearest(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  std::vector<double> d;
  d.reserve(a.size());
  for (const auto& p : a) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& q : b) best = std::min(best, (p - q).squaredNorm());
    d.push_back(std::sqrt(best));
  }
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

// Depth pixels of a frame back-projected and moved to the world with groundTruth * local.
std::vector<Eigen::Vector3d> worldPoints(const rtabmap::SensorData& data, const Transform& pose, int step) {
  const CameraModel& m = data.cameraModels().at(0);
  const Transform cam = pose * m.localTransform();
  std::vector<Eigen::Vector3d> pts;
  const cv::Mat& depth = data.depthOrRightRaw();
  for (int v = 0; v < depth.rows; v += step) {
    for (int u = 0; u < depth.cols; u += step) {
      const float z = rtabmap::SensorData::depthAt(depth, u, v);
      double x, y, zz;
      if (z > 0 && m.project(u, v, z, x, y, zz)) pts.push_back(cam * Eigen::Vector3d(x, y, zz));
    }
  }
  return pts;
}

}  // namespace

TEST(DatasetRegistry, KnowsEveryReaderAndRefusesDuplicates) {
  const auto formats = rtabmap::datasetFormats();
  for (const char* f : {"7scenes", "carmen", "euroc", "images", "kitti", "tum"}) {
    EXPECT_NE(std::find(formats.begin(), formats.end(), f), formats.end()) << f;
  }
  EXPECT_TRUE(std::is_sorted(formats.begin(), formats.end()));
  EXPECT_THROW(rtabmap::registerDatasetFormat("carmen", [](const std::string&, const DatasetReaderOptions&) {
                 return std::unique_ptr<rtabmap::DatasetReader>();
               }),
               std::logic_error);
  try {
    rtabmap::openDatasetReader("nosuchformat", "/tmp");
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("carmen"), std::string::npos) << e.what();
  }
  DatasetReaderOptions bad;
  bad.startFrame = -1;
  EXPECT_THROW(rtabmap::openDatasetReader("images", "/tmp", bad), FormatError);
}

TEST(SevenScenesReader, FramesIntrinsicsStampsAndGroundTruth) {
  RTABMAP_REQUIRE_DATA(dir, "rgbd_7scenes");
  DatasetReaderOptions options;
  options.startFrame = 0;
  options.maxFrames = 21;
  auto reader = rtabmap::openDatasetReader("7scenes", dir, options);
  EXPECT_EQ(reader->frameCount(), 21);
  const auto records = readAll(*reader);
  ASSERT_EQ(records.size(), 21u);
  const auto& f0 = records[0].data;
  EXPECT_EQ(f0.id(), 1);
  EXPECT_EQ(f0.imageRaw().type(), CV_8UC3);
  EXPECT_EQ(f0.imageRaw().size(), cv::Size(640, 480));
  ASSERT_EQ(f0.depthOrRightRaw().type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(f0.depthOrRightRaw() == 65535), 0);
  ASSERT_EQ(f0.cameraModels().size(), 1u);
  EXPECT_DOUBLE_EQ(f0.cameraModels()[0].fx(), 585.0);
  EXPECT_DOUBLE_EQ(f0.cameraModels()[0].cx(), 320.0);
  EXPECT_TRUE(f0.cameraModels()[0].localTransform() == CameraModel::opticalRotation());
  // 30 Hz synthesised stamps.
  EXPECT_DOUBLE_EQ(records[5].stamp, 5.0 / 30.0);
  // groundTruth * localTransform is the file's camera-to-world matrix.
  const Transform file(0.9093128999999999795, 0.2726222899999999894, -0.3142243299999999961, -0.3404563400000000239,
                       -0.2724861800000000223, 0.9610497999999999541, 0.04527962600000000337, 0.01646981800000000065,
                       0.3143392500000000145, 0.04444964600000000238, 0.9482093499999999509, 0.2965691699999999931);
  const Transform camera = f0.groundTruth() * f0.cameraModels()[0].localTransform();
  EXPECT_LT((camera.toMatrix4d() - file.toMatrix4d()).cwiseAbs().maxCoeff(), 1e-9);
  {
    // Registered to the colour camera: its model, and its pose 2.56 cm beside the file's (the
    // depth camera's).
    DatasetReaderOptions registered = options;
    registered.registerDepth = true;
    registered.maxFrames = 1;
    auto registeredReader = rtabmap::openDatasetReader("7scenes", dir, registered);
    DatasetRecord r;
    ASSERT_TRUE(registeredReader->next(r));
    EXPECT_DOUBLE_EQ(r.data.cameraModels()[0].fx(), 525.0);
    EXPECT_EQ(r.data.depthOrRightRaw().size(), cv::Size(640, 480));
    const Transform colour = r.data.groundTruth() * r.data.cameraModels()[0].localTransform();
    const Transform colourToDepth = colour.inverse() * file;
    EXPECT_NEAR(colourToDepth.x(), -0.0256, 0.0005);
    EXPECT_NEAR(colourToDepth.translation().norm(), 0.0256, 0.0005);
    // The registered frame lands on the same surfaces as the recorded one.
    const auto recorded = worldPoints(f0, f0.groundTruth(), 16);
    const auto moved = worldPoints(r.data, r.data.groundTruth(), 4);
    EXPECT_LT(medianNearest(recorded, moved), 0.01);
  }
  // The convention holds geometrically: frames 0 and 20 land on the same surfaces.
  const auto a = worldPoints(f0, f0.groundTruth(), 16);
  const auto b = worldPoints(records[20].data, records[20].data.groundTruth(), 4);
  ASSERT_GT(a.size(), 300u);
  const double aligned = medianNearest(a, b);
  const auto wrong = worldPoints(records[20].data, records[20].data.groundTruth() * CameraModel::opticalRotation(), 4);
  const double misaligned = medianNearest(a, wrong);
  std::cout << "7-Scenes frames 0/20 in the world: median nearest distance " << aligned
            << " m (wrong convention: " << misaligned << " m)\n";
  EXPECT_LT(aligned, 0.02);
  EXPECT_GT(misaligned, 5 * aligned);

  // Start frame: stamps and ids stay those of the dataset.
  options.startFrame = 590;
  options.maxFrames = 0;
  auto tail = rtabmap::openDatasetReader("7scenes", dir, options);
  EXPECT_EQ(tail->frameCount(), 10);
  DatasetRecord r;
  ASSERT_TRUE(tail->next(r));
  EXPECT_EQ(r.data.id(), 591);
  EXPECT_DOUBLE_EQ(r.stamp, 590.0 / 30.0);
}

namespace {

// Median gradient magnitude of the grey image at the depth image's discontinuities (neighbours
// both measured and more than 10 cm apart): high where depth edges lie on colour edges.
double colourGradientAtDepthEdges(const rtabmap::SensorData& data) {
  cv::Mat grey, gx, gy, magnitude;
  cv::cvtColor(data.imageRaw(), grey, cv::COLOR_BGR2GRAY);
  grey.convertTo(grey, CV_32F);
  cv::Sobel(grey, gx, CV_32F, 1, 0);
  cv::Sobel(grey, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, magnitude);
  cv::GaussianBlur(magnitude, magnitude, cv::Size(3, 3), 0);
  const cv::Mat& depth = data.depthOrRightRaw();
  std::vector<float> atEdges;
  for (int v = 1; v < depth.rows; ++v) {
    for (int u = 1; u < depth.cols; ++u) {
      const int d = depth.at<uint16_t>(v, u);
      const int left = depth.at<uint16_t>(v, u - 1);
      const int up = depth.at<uint16_t>(v - 1, u);
      const bool edge = d > 0 && ((left > 0 && std::abs(d - left) > 100) || (up > 0 && std::abs(d - up) > 100));
      if (edge) atEdges.push_back(magnitude.at<float>(v, u));
    }
  }
  if (atEdges.empty()) return 0.0;
  std::nth_element(atEdges.begin(), atEdges.begin() + static_cast<long>(atEdges.size() / 2), atEdges.end());
  return atEdges[atEdges.size() / 2];
}

}  // namespace

// What the registration is for, on the real images: 7-Scenes' depth edges lie beside the colour
// edges as recorded (the colour gradient there is no higher than the image's median) and on
// them once registered. Measured: 1.08-1.84 times higher registered, median 1.6.
TEST(SevenScenesReader, RegisteredDepthEdgesLieOnColourEdges) {
  RTABMAP_REQUIRE_DATA(dir, "rgbd_7scenes");
  std::vector<double> ratios;
  for (int frame = 0; frame < 600; frame += 100) {
    double gradient[2] = {0.0, 0.0};
    for (int registered = 0; registered < 2; ++registered) {
      DatasetReaderOptions options;
      options.startFrame = frame;
      options.maxFrames = 1;
      options.registerDepth = registered == 1;
      auto reader = rtabmap::openDatasetReader("7scenes", dir, options);
      DatasetRecord r;
      ASSERT_TRUE(reader->next(r));
      gradient[registered] = colourGradientAtDepthEdges(r.data);
    }
    std::cout << "7-Scenes frame " << frame << ": colour gradient at depth edges " << gradient[0]
              << " as recorded, " << gradient[1] << " registered\n";
    EXPECT_GT(gradient[1], gradient[0]) << "frame " << frame;
    ratios.push_back(gradient[1] / std::max(gradient[0], 1e-6));
  }
  std::nth_element(ratios.begin(), ratios.begin() + 3, ratios.end());
  EXPECT_GT(ratios[3], 1.3);
}

TEST(TumReader, AssociatesDepthConvertsAndInterpolatesGroundTruth) {
  TempDir root;
  const std::string dir = root.file("rgbd_dataset_freiburg2_tiny");
  std::filesystem::create_directories(dir + "/rgb");
  std::filesystem::create_directories(dir + "/depth");
  cv::Mat rgb(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  cv::Mat depth(48, 64, CV_16UC1, cv::Scalar(5000));  // 1 m
  depth.at<uint16_t>(0, 0) = 0;
  std::ostringstream rgbList, depthList;
  rgbList << "# color images\n";
  depthList << "# depth maps\n";
  const double rgbStamps[4] = {1.05, 1.15, 1.25, 1.35};
  const double depthStamps[3] = {1.06, 1.14, 1.34};  // 1.25 has no depth within 20 ms
  for (double s : rgbStamps) {
    const std::string name = "rgb/" + std::to_string(s) + ".png";
    cv::imwrite(dir + "/" + name, rgb);
    rgbList << s << " " << name << "\n";
  }
  for (double s : depthStamps) {
    const std::string name = "depth/" + std::to_string(s) + ".png";
    cv::imwrite(dir + "/" + name, depth);
    depthList << s << " " << name << "\n";
  }
  writeText(dir + "/rgb.txt", rgbList.str());
  writeText(dir + "/depth.txt", depthList.str());
  // Camera moving along the world x axis at 10 m/s, orientation fixed.
  writeText(dir + "/groundtruth.txt",
            "# timestamp tx ty tz qx qy qz qw\n1.0 0 0 0 0 0 0 1\n1.1 1 0 0 0 0 0 1\n1.2 2 0 0 0 0 0 1\n"
            "1.3 3 0 0 0 0 0 1\n");
  auto reader = rtabmap::openDatasetReader("tum", dir);
  EXPECT_EQ(reader->frameCount(), 3);
  const auto records = readAll(*reader);
  ASSERT_EQ(records.size(), 3u);
  EXPECT_DOUBLE_EQ(records[0].stamp, 1.05);
  EXPECT_DOUBLE_EQ(records[1].stamp, 1.15);
  EXPECT_DOUBLE_EQ(records[2].stamp, 1.35);
  const auto& d = records[0].data;
  ASSERT_EQ(d.depthOrRightRaw().type(), CV_16UC1);
  EXPECT_EQ(d.depthOrRightRaw().at<uint16_t>(1, 1), 1000);  // mm
  EXPECT_EQ(d.depthOrRightRaw().at<uint16_t>(0, 0), 0);
  ASSERT_EQ(d.cameraModels().size(), 1u);
  EXPECT_DOUBLE_EQ(d.cameraModels()[0].fx(), 520.9);  // freiburg2 from the folder name
  EXPECT_DOUBLE_EQ(d.cameraModels()[0].cy(), 249.7);
  // Ground truth interpolated at 1.05 s (x = 0.5), expressed for the base frame.
  const Transform camera = d.groundTruth() * d.cameraModels()[0].localTransform();
  EXPECT_NEAR(camera.x(), 0.5, 1e-9);
  EXPECT_NEAR((camera.rotationMatrix() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(d.groundTruth().x(), 0.5, 1e-9);
  // 1.35 s is after the last ground-truth sample: none.
  EXPECT_TRUE(records[2].data.groundTruth().isNull());

  // Unknown folder names get the default intrinsics; malformed lists name file and line.
  std::filesystem::rename(dir, root.file("plain"));
  const auto plain = readAll("tum", root.file("plain"));
  EXPECT_DOUBLE_EQ(plain[0].data.cameraModels()[0].fx(), 525.0);
  writeText(root.file("plain/depth.txt"), "# x\n1.06 depth/a.png extra\n");
  try {
    readAll("tum", root.file("plain"));
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("depth.txt:2:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readAll("tum", root.path()), FormatError);
}

TEST(EurocReader, RectifiedStereoImuAndBodyGroundTruth) {
  RTABMAP_REQUIRE_DATA(dir, "euroc_v1_01_micro");
  DatasetReaderOptions options;
  options.images = false;
  auto all = rtabmap::openDatasetReader("euroc", dir, options);
  const int total = all->frameCount();
  EXPECT_GE(total, 90);
  size_t frames = 0, imu = 0;
  double previous = 0.0;
  bool ordered = true;
  for (const auto& r : readAll(*all)) {
    ordered = ordered && r.stamp >= previous;
    previous = r.stamp;
    if (r.kind == Kind::kFrame) {
      ++frames;
      EXPECT_FALSE(r.data.groundTruth().isNull()) << r.stamp;
    } else {
      ++imu;
    }
  }
  EXPECT_TRUE(ordered);
  EXPECT_EQ(frames, static_cast<size_t>(total));
  // 200 Hz IMU over ~4.7 s of frames, up to the last frame.
  EXPECT_GT(imu, 900u);

  options.images = true;
  options.maxFrames = 2;
  const auto records = readAll("euroc", dir, options);
  // IMU sample at the first frame's stamp first, then the frame, 10 IMU samples, the frame.
  ASSERT_GE(records.size(), 3u);
  EXPECT_EQ(records[0].kind, Kind::kImu);
  EXPECT_EQ(records[1].kind, Kind::kFrame);
  EXPECT_DOUBLE_EQ(records[0].stamp, records[1].stamp);
  EXPECT_EQ(records.back().kind, Kind::kFrame);
  // Between the frames (50 ms apart), the 10 samples of 200 Hz stamped up to the second frame.
  const double t1 = records[1].stamp, t2 = records.back().stamp;
  EXPECT_EQ(records.size(), 13u);
  for (size_t i = 2; i + 1 < records.size(); ++i) {
    EXPECT_EQ(records[i].kind, Kind::kImu);
    EXPECT_GT(records[i].stamp, t1);
    EXPECT_LE(records[i].stamp, t2);
  }
  const auto& imuData = records[0].data.imu();
  EXPECT_NEAR(imuData.linearAcceleration.x(), 9.0874956666666655, 1e-12);
  EXPECT_NEAR(imuData.angularVelocity.z(), 0.07749261878854824, 1e-12);

  const auto& f = records[1].data;
  EXPECT_DOUBLE_EQ(records[1].stamp, 1403715273.262142976);
  ASSERT_TRUE(f.isStereo());
  EXPECT_EQ(f.imageRaw().type(), CV_8UC1);
  EXPECT_EQ(f.imageRaw().size(), cv::Size(752, 480));
  EXPECT_EQ(f.depthOrRightRaw().size(), cv::Size(752, 480));
  EXPECT_NEAR(f.stereoCameraModels()[0].baseline(), 0.110, 0.002);
  // Local transform: body -> rectified left camera, near T_BS of cam0.
  const Transform tbs(0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
                      0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
                      -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949);
  EXPECT_LT((f.stereoCameraModels()[0].localTransform().translation() - tbs.translation()).norm(), 1e-9);
  EXPECT_LT((tbs.inverse() * f.stereoCameraModels()[0].localTransform()).getAngle(), 0.05);
  // Ground truth: the body pose of the TUM file, interpolated 3 us after its first sample.
  const Transform& gt = f.groundTruth();
  ASSERT_FALSE(gt.isNull());
  EXPECT_NEAR(gt.x(), 0.878895, 1e-5);
  EXPECT_NEAR(gt.y(), 2.183400, 1e-5);
  EXPECT_NEAR(gt.z(), 0.948427, 1e-5);
  const Eigen::Quaterniond q = gt.quaternion();
  EXPECT_NEAR(std::abs(q.dot(Eigen::Quaterniond(0.069433, -0.824237, -0.106942, -0.551702).normalized())), 1.0, 1e-6);
}

TEST(KittiReader, VelodyneScansWithPosesAndCalibration) {
  RTABMAP_REQUIRE_DATA(dir, "kitti00_velodyne");
  TempDir tmp;
  // calib.txt of KITTI odometry sequences 00-02 (published with the dataset); only Tr matters
  // for a scans-only folder.
  writeText(tmp.file("calib.txt"),
            "P0: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 0.000000000000e+00 "
            "7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 0.000000000000e+00 "
            "1.000000000000e+00 0.000000000000e+00\n"
            "P1: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 -3.861448000000e+02 "
            "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 "
            "0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n"
            "Tr: 4.276802385584e-04 -9.999672484946e-01 -8.084491683471e-03 -1.198459927713e-02 "
            "-7.210626507497e-03 8.081198471645e-03 -9.999413164504e-01 -5.403984729748e-02 "
            "9.999738645903e-01 4.859485810390e-04 -7.206933692422e-03 -2.921968648686e-01\n");
  DatasetReaderOptions options;
  options.calibrationPath = tmp.file("calib.txt");
  auto reader = rtabmap::openDatasetReader("kitti", dir, options);
  EXPECT_EQ(reader->frameCount(), 4);
  const auto records = readAll(*reader);
  ASSERT_EQ(records.size(), 4u);
  const int ids[4] = {95, 96, 199, 200};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(records[i].data.id(), ids[i]);
    EXPECT_DOUBLE_EQ(records[i].stamp, (ids[i] - 1) / 10.0);
    const auto& scan = records[i].data.laserScanRaw();
    EXPECT_EQ(scan.format(), rtabmap::LaserScan::kXYZI);
    EXPECT_GT(scan.size(), 100000);
    EXPECT_EQ(scan.maxPoints(), scan.size());
    EXPECT_FALSE(records[i].data.groundTruth().isNull());
  }
  // File size / 16 points.
  EXPECT_EQ(records[0].data.laserScanRaw().size(), 1945888 / 16);
  // Frame 94 is row 95 of the poses file (1-based): its translation. The ground truth is the
  // base's pose in the base frame of frame 0: optical * pose * optical^-1.
  const Transform optical = CameraModel::opticalRotation();
  const Transform cam94 = optical.inverse() * records[0].data.groundTruth() * optical;
  EXPECT_NEAR(cam94.x(), -5.248892, 1e-6);
  EXPECT_NEAR(cam94.y(), -2.822088, 1e-6);
  EXPECT_NEAR(cam94.z(), 81.62286, 1e-5);
  // The base moves forward (x) along the road: z of the camera frame.
  const Transform motion = records[0].data.groundTruth().inverse() * records[1].data.groundTruth();
  EXPECT_GT(motion.x(), 0.4);
  EXPECT_LT(std::abs(motion.y()), 0.05);

  // Consecutive scans moved to the world with their ground truth (and the base -> velodyne
  // transform) overlap; placed with a slightly wrong pose they do not.
  auto world = [](const DatasetRecord& r, const Transform& pose, int stride) {
    const rtabmap::LaserScan base = r.data.laserScanRaw().transformedToBase();
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < base.size(); i += stride) {
      const Eigen::Vector3f p = base.point(i);
      const double range = p.head<2>().norm();
      if (range > 3.0 && range < 20.0) pts.push_back(pose * p.cast<double>());
    }
    return pts;
  };
  const auto a = world(records[0], records[0].data.groundTruth(), 97);
  const auto b = world(records[1], records[1].data.groundTruth(), 1);
  const auto c = world(records[1], records[1].data.groundTruth() * Transform(0, 0, 0, 0, 0, 0.1), 1);
  ASSERT_GT(a.size(), 300u);
  const double aligned = medianNearest(a, b);
  const double misaligned = medianNearest(a, c);
  std::cout << "KITTI scans 94/95 in the world: median nearest distance " << aligned
            << " m (pose off by 0.1 rad: " << misaligned << " m)\n";
  EXPECT_LT(aligned, 0.10);
  EXPECT_GT(misaligned, 3 * aligned);

  // Without calibration: the nominal mounting, still a usable scan.
  const auto nominal = readAll("kitti", dir);
  ASSERT_EQ(nominal.size(), 4u);
  EXPECT_NEAR(nominal[0].data.laserScanRaw().localTransform().x(), -0.27, 1e-12);
}

TEST(KittiReader, StandardLayoutWithImagesTimesAndPoses) {
  TempDir root;
  const std::string seq = root.file("sequences/07");
  for (const char* sub : {"image_0", "image_1", "velodyne"}) std::filesystem::create_directories(seq + "/" + sub);
  std::filesystem::create_directories(root.file("poses"));
  const cv::Mat img(24, 40, CV_8UC1, cv::Scalar(77));
  for (int i = 0; i < 3; ++i) {
    char name[16];
    std::snprintf(name, sizeof(name), "%06d", i);
    cv::imwrite(seq + "/image_0/" + name + ".png", img);
    cv::imwrite(seq + "/image_1/" + name + ".png", img);
  }
  // One scan, for frame 1: two points.
  const float pts[8] = {1, 2, 3, 0.5f, 4, 5, 6, 0.25f};
  writeText(seq + "/velodyne/000001.bin", std::string(reinterpret_cast<const char*>(pts), sizeof(pts)));
  writeText(seq + "/times.txt", "0.000000e+00\n1.036000e-01\n2.072000e-01\n");
  writeText(seq + "/calib.txt",
            "P0: 700 0 300 0 0 700 100 0 0 0 1 0\nP1: 700 0 300 -350 0 700 100 0 0 0 1 0\n"
            "P2: 700 0 300 40 0 700 100 0 0 0 1 0\nP3: 700 0 300 -300 0 700 100 0 0 0 1 0\n"
            "Tr: 0 -1 0 0 0 0 -1 0 1 0 0 -0.3\n");
  writeText(root.file("poses/07.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n1 0 0 0 0 1 0 0 0 0 1 2\n");
  const auto records = readAll("kitti", seq);
  ASSERT_EQ(records.size(), 3u);
  EXPECT_DOUBLE_EQ(records[1].stamp, 0.1036);
  const auto& f = records[1].data;
  ASSERT_TRUE(f.isStereo());
  EXPECT_DOUBLE_EQ(f.stereoCameraModels()[0].baseline(), 0.5);
  EXPECT_DOUBLE_EQ(f.stereoCameraModels()[0].left().fx(), 700.0);
  EXPECT_EQ(f.imageRaw().size(), cv::Size(40, 24));
  ASSERT_EQ(f.laserScanRaw().size(), 2);
  // Tr here is exactly the optical rotation with the velodyne 0.3 m behind: base -> velodyne
  // is a pure translation of -0.3 m along x.
  const Transform velo = f.laserScanRaw().localTransform();
  EXPECT_NEAR(velo.x(), -0.3, 1e-12);
  EXPECT_NEAR(velo.getAngle(), 0.0, 1e-12);
  EXPECT_NEAR(f.laserScanRaw().point(1).z(), 6.0f, 1e-6);
  EXPECT_NEAR(f.laserScanRaw().data().ptr<float>(0)[3], 0.5f, 1e-6);  // intensity
  EXPECT_TRUE(records[0].data.laserScanRaw().empty());
  // Camera moved 1 m along its optical axis: the base moved 1 m forward, from the identity.
  EXPECT_TRUE(records[0].data.groundTruth().isIdentity(1e-12));
  EXPECT_NEAR(f.groundTruth().x(), 1.0, 1e-12);
  EXPECT_NEAR(f.groundTruth().y(), 0.0, 1e-12);
  EXPECT_NEAR(f.groundTruth().z(), 0.0, 1e-12);

  writeText(seq + "/calib.txt", "P0: 700 0 300\n");
  try {
    readAll("kitti", seq);
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("calib.txt:1:"), std::string::npos) << e.what();
  }
}

TEST(ImageFolderReader, NaturalOrderAndSynthesisedStamps) {
  TempDir dir;
  const cv::Mat grey(8, 8, CV_8UC1, cv::Scalar(1));
  const cv::Mat colour(8, 8, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::imwrite(dir.file("10.png"), grey * 10);
  cv::imwrite(dir.file("2.png"), grey * 2);
  cv::imwrite(dir.file("1.jpg"), colour);
  writeText(dir.file("notes.txt"), "not an image");
  auto records = readAll("images", dir.path());
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0].data.imageRaw().type(), CV_8UC3);
  EXPECT_EQ(records[1].data.imageRaw().at<uint8_t>(0, 0), 2);
  EXPECT_EQ(records[2].data.imageRaw().at<uint8_t>(0, 0), 10);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(records[i].data.id(), i + 1);
    EXPECT_DOUBLE_EQ(records[i].stamp, i * 1.0);
    EXPECT_TRUE(records[i].data.cameraModels().empty());
  }
  DatasetReaderOptions options;
  options.frameRate = 4.0;
  options.startFrame = 1;
  records = readAll("images", dir.path(), options);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_DOUBLE_EQ(records[0].stamp, 0.25);
  EXPECT_EQ(records[0].data.id(), 2);
  // A corrupt image names its file.
  writeText(dir.file("3.png"), "garbage");
  try {
    readAll("images", dir.path());
    ADD_FAILURE();
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("3.png"), std::string::npos) << e.what();
  }
  TempDir empty;
  EXPECT_THROW(readAll("images", empty.path()), FormatError);
}
