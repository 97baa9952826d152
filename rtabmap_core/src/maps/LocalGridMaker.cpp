// createLocalGrid: the local grid pipeline, chaining the stages of LocalGridStages.h.
#include "rtabmap_core/maps/LocalGridMaker.h"

#include <chrono>
#include <sstream>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/LocalGridStages.h"

namespace rtabmap {

namespace {

using Clock = std::chrono::steady_clock;

class StageTimer {
 public:
  explicit StageTimer(LocalGridStats& stats) : stats_(stats), start_(Clock::now()) {}
  void lap(const char* stage) {
    const Clock::time_point now = Clock::now();
    stats_.stageMs[stage] += std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
  }

 private:
  LocalGridStats& stats_;
  Clock::time_point start_;
};

int cellCount(const cv::Mat& m) { return m.empty() ? 0 : static_cast<int>(m.total()); }

void countCells(LocalGridResult& r) {
  r.stats.groundCells = cellCount(r.grid.ground);
  r.stats.obstacleCells = cellCount(r.grid.obstacles);
  r.stats.emptyCells = cellCount(r.grid.empty);
}

// Rotation levelling the cloud with the odometry's roll and pitch (Grid/MapFrameProjection), so
// that "up" is gravity's up when the sensor is tilted.
Transform levelling(const SensorData& data) {
  if (data.odomPose().isNull()) return Transform::Identity();
  double roll, pitch, yaw;
  data.odomPose().getEulerAngles(roll, pitch, yaw);
  return Transform(0, 0, 0, roll, pitch, 0);
}

// 2D scan path.
void scanGrid(const LaserScan& scan, const LocalGridOptions& o, LocalGridResult& r) {
  StageTimer timer(r.stats);
  ScanRayTracingStats s;
  r.source = "scan 2D";
  r.grid = rayTraceScan2D(scan, o, &s);
  timer.lap("ray tracing 2D");
  r.stats.inputPoints = s.beams;
  r.stats.invalidPoints = s.invalid;
  r.stats.outOfRange = s.belowRangeMin;
  if (s.invalid > 0) {
    r.warnings.push_back(std::to_string(s.invalid) + " of " + std::to_string(s.beams) +
                         " scan points are NaN, infinite or at zero range (dropped)");
  }
  if (r.grid.isEmpty()) {
    std::ostringstream why;
    if (s.beams == 0) why << "the laser scan has no point (every beam was a no-return)";
    else if (s.invalid == s.beams) why << "all " << s.beams << " scan points are NaN, infinite or at zero range";
    else why << "no usable scan point: " << s.invalid << " invalid, " << s.belowRangeMin
             << " closer than Grid/RangeMin (" << o.rangeMin << " m) out of " << s.beams;
    r.why = why.str();
  }
}

// Cloud path (depth, stereo, 3D scan, or both with a scan).
void cloudGrid(const SensorData& data, bool useDepth, bool useScan, const LocalGridOptions& o,
               LocalGridResult& r) {
  StageTimer timer(r.stats);
  Cloud cloud;
  Eigen::Vector3f viewPoint = Eigen::Vector3f::Zero();
  std::ostringstream source;
  int depthPixels = 0, depthValid = 0;
  if (useDepth) {
    std::vector<CameraModel> models;
    const cv::Mat depth = depthOfFrame(data, o.stereo, &models);
    if (data.isStereo()) {
      timer.lap("stereo block matching");
      source << "stereo";
    } else {
      source << "depth";
    }
    DepthCloudStats s;
    cloud = cloudFromDepth(depth, data.imageRaw(), models, o, &s);
    depthPixels = s.pixels;
    depthValid = s.valid;
    r.stats.inputPoints += s.pixels;
    r.stats.invalidPoints += s.pixels - s.valid;
    r.stats.outOfRange += s.outOfRange;
    viewPoint = models.front().localTransform().toEigen().translation().cast<float>();
    timer.lap("depth to cloud");
  }
  Cloud scanCloud;
  if (useScan) {
    const LaserScan& scan = data.laserScanRaw();
    int invalid = 0;
    scanCloud = cloudFromScan(scan, o, &invalid);
    r.stats.inputPoints += scan.size();
    r.stats.invalidPoints += invalid;
    if (invalid > 0) {
      r.warnings.push_back(std::to_string(invalid) + " of " + std::to_string(scan.size()) +
                           " scan points are NaN or infinite (dropped)");
    }
    if (!useDepth) viewPoint = scan.localTransform().toEigen().translation().cast<float>();
    source << (useDepth ? "+scan" : "scan 3D");
    timer.lap("scan to cloud");
  }
  r.source = source.str();
  // A planar scan has no usable normals: with a depth image, its points join the obstacles after
  // segmentation instead of going through it.
  // Otherwise (a 3D scan alone) the scan IS the cloud: moved, not copied, or its raw points
  // would also join the obstacles below and make every floor voxel an obstacle.
  const bool scanAsObstacles = useDepth && useScan;
  if (!scanAsObstacles) {
    cloud.append(scanCloud);
    scanCloud = Cloud();
  }
  r.stats.cloudPoints = static_cast<int>(cloud.size() + scanCloud.size());

  if (cloud.empty() && scanCloud.empty()) {
    std::ostringstream why;
    if (useDepth && depthValid == 0) {
      why << "the depth image has no valid pixel (" << depthPixels
          << " pixels read, all zero, NaN or marked invalid)";
    } else {
      why << "every point is outside Grid/RangeMin..Grid/RangeMax (" << o.rangeMin << ".."
          << o.rangeMax << " m) or invalid";
    }
    r.why = why.str();
    return;
  }

  const Transform level = o.mapFrameProjection ? levelling(data) : Transform::Identity();
  if (!level.isIdentity()) {
    cloud = transformCloud(cloud, level);
    scanCloud = transformCloud(scanCloud, level);
    viewPoint = (level.toEigen().cast<float>() * viewPoint);
  }
  if (o.preVoxelFiltering) {
    cloud = voxelFilter(cloud, o.cellSize);
    timer.lap("voxel filter");
  }
  r.stats.voxelPoints = static_cast<int>(cloud.size());
  const size_t beforeCrop = cloud.size() + scanCloud.size();
  cloud = cropHeights(cloud, 0.0f, o.maxObstacleHeight);
  scanCloud = cropHeights(scanCloud, 0.0f, o.maxObstacleHeight);
  r.stats.heightCropped = static_cast<int>(beforeCrop - cloud.size() - scanCloud.size());
  int removed = 0, removedScan = 0;
  cloud = removeFootprint(cloud, o, &removed);
  scanCloud = removeFootprint(scanCloud, o, &removedScan);
  r.stats.footprintRemoved = removed + removedScan;
  timer.lap("height and footprint");

  GroundObstacles seg;
  if (o.groundIsObstacle && o.grid3D) {
    seg.obstacles = cloud;
  } else if (o.normalsSegmentation) {
    seg = segmentGroundByNormals(cloud, viewPoint, o);
    r.stats.flatObstacleClusters = seg.flatObstacleClusters;
    timer.lap("segmentation");
    ClusterStats cs;
    seg.obstacles = clusterObstacles(seg.obstacles, o.clusterRadius, o.minClusterSize, &cs);
    r.stats.clustersKept = cs.kept;
    r.stats.clustersDropped = cs.dropped;
    timer.lap("obstacle clustering");
  } else {
    seg = segmentGroundByHeight(cloud, o);
    timer.lap("segmentation");
  }
  // A laser has no colour: with a coloured depth cloud, its points are painted white (as
  // RTAB-Map does) so the camera's colours survive the merge instead of the whole cloud losing
  // them (Cloud::append keeps colours only when both sides have them).
  if (scanAsObstacles && !scanCloud.hasColors() && (seg.obstacles.hasColors() || seg.ground.hasColors())) {
    scanCloud.colors.assign(scanCloud.size(), cv::Vec3b(255, 255, 255));
  }
  seg.obstacles.append(scanCloud);
  if (o.noiseFilteringRadius > 0.0f) {
    int g = 0, ob = 0;
    seg.ground = filterNoise(seg.ground, o.noiseFilteringRadius, o.noiseFilteringMinNeighbors, &g);
    seg.obstacles = filterNoise(seg.obstacles, o.noiseFilteringRadius, o.noiseFilteringMinNeighbors, &ob);
    r.stats.noiseRemoved = g + ob;
    timer.lap("noise filter");
  }
  if (!level.isIdentity()) {
    const Transform back = level.inverse();
    seg.ground = transformCloud(seg.ground, back);
    seg.obstacles = transformCloud(seg.obstacles, back);
    viewPoint = back.toEigen().cast<float>() * viewPoint;
  }
  r.stats.groundPoints = static_cast<int>(seg.ground.size());
  r.stats.obstaclePoints = static_cast<int>(seg.obstacles.size());

  if (seg.ground.empty() && seg.obstacles.empty()) {
    std::ostringstream why;
    why << "every point was removed by the filters (" << r.stats.heightCropped
        << " above Grid/MaxObstacleHeight, " << r.stats.footprintRemoved << " in the footprint, "
        << r.stats.clustersDropped << " clusters smaller than Grid/MinClusterSize, "
        << r.stats.noiseRemoved << " noise)";
    r.why = why.str();
    return;
  }
  if (o.grid3D) {
    r.grid = keep3D(seg.ground, seg.obstacles, o.cellSize);
    r.grid.viewPoint = viewPoint;
    timer.lap("3D grid");
    if (o.rayTracing) {
      rayTrace3D(r.grid, o.rangeMax);
      timer.lap("ray tracing 3D");
    }
  } else {
    r.grid = projectTo2D(seg.ground, seg.obstacles, o.cellSize);
    r.grid.viewPoint = viewPoint;
    timer.lap("projection 2D");
    if (o.rayTracing) {
      rayTrace2D(r.grid, o.rangeMax);
      timer.lap("ray tracing 2D");
    }
  }
}

bool hasDepth(const SensorData& d) {
  return !d.depthOrRightRaw().empty() && (!d.cameraModels().empty() || d.isStereo());
}

std::string missing(const char* what, bool compressedOnly) {
  std::string s = std::string("the data has no ") + what;
  if (compressedOnly) s += " in raw form (it is compressed: call SensorData::uncompress() first)";
  return s;
}

}  // namespace

LocalGridResult createLocalGrid(const SensorData& data, const LocalGridOptions& options) {
  options.validate();
  LocalGridResult r;
  const Clock::time_point start = Clock::now();
  const bool scan = !data.laserScanRaw().empty();
  const bool depth = hasDepth(data);
  const bool scanCompressedOnly = !scan && !data.laserScanCompressed().empty();
  const bool depthCompressedOnly = !depth && !data.depthOrRightCompressed().empty();
  try {
    switch (options.sensor) {
      case LocalGridOptions::Sensor::kScan:
        if (!scan) r.why = missing("laser scan", scanCompressedOnly) + " but Grid/Sensor is 0 (laser scan)";
        else if (data.laserScanRaw().is2d()) scanGrid(data.laserScanRaw(), options, r);
        else cloudGrid(data, false, true, options, r);
        break;
      case LocalGridOptions::Sensor::kDepth:
        if (!depth) r.why = missing("depth image (or stereo pair) with its camera model", depthCompressedOnly) +
                            " but Grid/Sensor is 1 (depth image)";
        else cloudGrid(data, true, false, options, r);
        break;
      case LocalGridOptions::Sensor::kBoth:
        if (!scan && !depth) {
          r.why = "the data has neither a laser scan nor a depth image but Grid/Sensor is 2 (both)";
          if (scanCompressedOnly || depthCompressedOnly) r.why += " (they are compressed: call SensorData::uncompress() first)";
        } else if (!depth && data.laserScanRaw().is2d()) {
          r.warnings.push_back("Grid/Sensor is 2 (both) but the data has no depth image: scan only");
          scanGrid(data.laserScanRaw(), options, r);
        } else {
          if (!scan) r.warnings.push_back("Grid/Sensor is 2 (both) but the data has no laser scan: depth only");
          cloudGrid(data, depth, scan, options, r);
        }
        break;
    }
  } catch (const FormatError& e) {
    r.grid = LocalGrid();
    r.why = e.what();
  }
  if (r.why.empty() && r.grid.isEmpty()) r.why = "no cell was produced";
  r.success = r.why.empty();
  if (!r.success) r.grid = LocalGrid();
  r.grid.cellSize = r.success ? options.cellSize : 0.0f;
  countCells(r);
  r.stats.totalMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return r;
}

LocalGridBytes localGridBytes(const LocalGrid& grid) {
  LocalGridBytes b;
  for (const cv::Mat* m : {&grid.ground, &grid.obstacles, &grid.empty}) {
    if (m->empty()) continue;
    b.raw += m->total() * m->elemSize();
    b.compressed += codec::compressData(*m).size();
  }
  return b;
}

}  // namespace rtabmap
