#pragma once
// The stages of local occupancy grid creation (JFR 2019, 4.3.3, Figure 4.7), each a function
// of its inputs and the options, so they can be tested and timed alone. createLocalGrid()
// (LocalGridMaker.h) chains them:
//
//   2D laser scan -> rayTraceScan2D ------------------------------------------> 2D local grid
//   depth image (or stereo pair -> depthFromStereo) -> cloudFromDepth --+
//   3D scan -> cloudFromScan -------------------------------------------+-> voxelFilter
//     -> cropHeights -> removeFootprint -> segmentGroundByNormals | segmentGroundByHeight
//     -> clusterObstacles -> filterNoise
//     -> projectTo2D [-> rayTrace2D]  (Grid/3D false)   or   keep 3D [-> rayTrace3D]
//
// Frames: clouds are in the robot base frame (x forward, y left, z up) unless said otherwise.
// Cells lie on the lattice floor(coordinate / cellSize) of the base frame, the same lattice as
// the global maps' (cell centres at (i + 0.5) * cellSize).
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include <vector>

#include "rtabmap_core/geometry/CameraModel.h"
#include "rtabmap_core/geometry/LaserScan.h"
#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/StereoCameraModel.h"
#include "rtabmap_core/maps/Cloud.h"
#include "rtabmap_core/maps/LocalGridOptions.h"

namespace rtabmap {

// ------------------------------------------------------------------ 2D laser scans
struct ScanRayTracingStats {
  int beams = 0;             // points read (after Grid/ScanDecimation)
  int invalid = 0;           // NaN or infinite points, dropped
  int belowRangeMin = 0;     // closer than Grid/RangeMin to the sensor, dropped
  int beyondRangeMax = 0;    // farther than Grid/RangeMax: free up to RangeMax, no obstacle
  int unknownRaysFilled = 0; // rays added where no return came back (Grid/Scan2dUnknownSpaceFilled)
};
// 2D ray tracing (Bresenham) from the sensor position to each hit, in the base frame: the
// cells crossed are free (LocalGrid::empty), the hit cell is an obstacle (its point is the
// mean of the hits in it, not the cell centre, so the global map keeps the scan's accuracy).
// An obstacle is never cleared by a ray of the same scan. Beams without return are not in a
// LaserScan (dropped when it was made); with Grid/Scan2dUnknownSpaceFilled their directions are
// found from the gaps between the angles of the returned beams (field of view assumed symmetric
// about the sensor's x axis, as for every planar lidar we know) and traced free, without
// obstacle, up to Grid/RangeMax (or the scan's own range max). Throws FormatError for a 3D
// scan.
LocalGrid rayTraceScan2D(const LaserScan& scan, const LocalGridOptions& options,
                         ScanRayTracingStats* stats = nullptr);

// ------------------------------------------------------------------ depth and stereo
struct DepthCloudStats {
  int pixels = 0;       // pixels visited (after decimation and region of interest)
  int valid = 0;        // with a valid depth (see SensorData::depthAt)
  int outOfRange = 0;   // valid, but outside [Grid/RangeMin, Grid/RangeMax] from the camera
};
// Back-projects a depth image (CV_16UC1 mm or CV_32FC1 m; several cameras side by side, one
// model each) into the base frame, one pixel out of Grid/DepthDecimation in each direction,
// inside Grid/DepthRoiRatios. Colours come from `rgb` when given (BGR or grey, same size as the
// depth or an integer multiple of it). Throws FormatError when the image width is not a
// multiple of the number of models or a model cannot project.
Cloud cloudFromDepth(const cv::Mat& depth, const cv::Mat& rgb, const std::vector<CameraModel>& models,
                     const LocalGridOptions& options, DepthCloudStats* stats = nullptr);
// Dense depth (CV_32FC1, metres, 0 = unknown) of the left image of a rectified pair by OpenCV
// block matching: depth = fx * baseline / disparity. Images may be colour or grey (converted).
// Throws FormatError for images of different sizes or an unusable model, ParameterError for
// invalid StereoBM options.
cv::Mat depthFromStereo(const cv::Mat& left, const cv::Mat& right, const StereoCameraModel& model,
                        const StereoBMOptions& options);
// Several stereo cameras side by side (left images, and right images the same way, one model
// each): each camera's depth by depthFromStereo on its own left and right sub-images (block
// matching never crosses a camera boundary), side by side as for several RGB-D cameras, so
// cloudFromDepth with the left models puts each camera's points through its local transform.
// Throws FormatError when the width is not a multiple of the number of cameras, and as
// depthFromStereo.
cv::Mat depthFromStereoCameras(const cv::Mat& left, const cv::Mat& right, const std::vector<StereoCameraModel>& models,
                               const StereoBMOptions& options);

// The depth image of a frame (its own, or its stereo pairs' by depthFromStereoCameras) and, in
// *models, the models that back-project it (the left cameras' for stereo).
cv::Mat depthOfFrame(const SensorData& data, const StereoBMOptions& options, std::vector<CameraModel>* models);

// ------------------------------------------------------------------ 3D scans
// The points of a 3D scan in the base frame, Grid/ScanDecimation and range limits applied;
// colours when the scan has RGB. NaN/inf points are dropped and counted in *invalid.
Cloud cloudFromScan(const LaserScan& scan, const LocalGridOptions& options, int* invalid = nullptr);

// ------------------------------------------------------------------ cloud filtering
// One point per occupied voxel of this size: the centroid of its points (and mean colour).
Cloud voxelFilter(const Cloud& cloud, float voxelSize);
// Keeps minZ <= z <= maxZ; a bound of 0 disables it (Grid/MaxObstacleHeight convention).
Cloud cropHeights(const Cloud& cloud, float minZ, float maxZ);
// Removes the points of the robot itself: |x| <= L/2 and |y| <= W/2 (W = L when only the length
// is set) and, when Grid/FootprintHeight > 0, z <= H. No footprint: returns the cloud.
Cloud removeFootprint(const Cloud& cloud, const LocalGridOptions& options, int* removed = nullptr);

// ------------------------------------------------------------------ ground / obstacles
struct GroundObstacles {
  Cloud ground;
  Cloud obstacles;
  int flatClusters = 0;        // normals: flat surfaces found (the floor and e.g. table tops)
  int flatObstacleClusters = 0;// normals: flat surfaces found above the floor (obstacles)
  float floorHeight = 0.0f;    // normals without MaxGroundHeight: mean z of the floor cluster
};
// Ground = points whose normal (from Grid/NormalK neighbours, oriented to the view point) is
// within Grid/MaxGroundAngle of the up axis and that belong to the floor. The floor is: with
// Grid/MaxGroundHeight set, the flat points below it; otherwise the lowest large flat cluster
// (clusters of Grid/ClusterRadius, large = at least a tenth of the biggest one), together with
// the flat clusters whose mean height is within Grid/ClusterRadius of it. Other flat surfaces
// (a table top) are obstacles with Grid/FlatObstacleDetected, ground otherwise. Every other
// point is an obstacle. Grid/MinGroundHeight then drops ground points below it.
GroundObstacles segmentGroundByNormals(const Cloud& cloud, const Eigen::Vector3f& viewPoint,
                                       const LocalGridOptions& options);
// Ground = points below Grid/MaxGroundHeight (and above Grid/MinGroundHeight when set), obstacles
// the rest: a pass-through filter, for robots on flat floors.
GroundObstacles segmentGroundByHeight(const Cloud& cloud, const LocalGridOptions& options);

struct ClusterStats {
  int kept = 0;           // clusters kept
  int dropped = 0;        // clusters smaller than the minimum size
  int droppedPoints = 0;  // their points
};
// Euclidean clustering (points closer than `radius` are in one cluster); clusters with fewer than
// minClusterSize points are dropped as noise. minClusterSize <= 1 keeps everything.
Cloud clusterObstacles(const Cloud& obstacles, float radius, int minClusterSize,
                       ClusterStats* stats = nullptr);
// Drops points with fewer than minNeighbors other points within radius (radius 0: unchanged).
Cloud filterNoise(const Cloud& cloud, float radius, int minNeighbors, int* removed = nullptr);

// ------------------------------------------------------------------ 2D / 3D grids
// 2D grid of the segmented cloud: obstacle cells (mean x y of their points) and ground cells
// (centres; a cell holding an obstacle is not ground).
LocalGrid projectTo2D(const Cloud& ground, const Cloud& obstacles, float cellSize);
// Adds to grid.empty the cells crossed by 2D rays from the view point to every obstacle cell of a
// 2D grid, each ray ending at the first obstacle cell on its way (a projected cell behind an
// obstacle was not seen empty). Cells already ground or obstacle are not repeated. rangeMax > 0
// truncates the rays.
void rayTrace2D(LocalGrid& grid, float rangeMax);
// 3D grid of the segmented cloud: one point per voxel (centroid, colour kept).
LocalGrid keep3D(const Cloud& ground, const Cloud& obstacles, float cellSize);
// Fills grid.empty of a 3D grid with the voxels crossed by 3D rays (OctoMap's ray casting) from
// the view point to every ground and obstacle voxel, except those voxels themselves.
// rangeMax > 0 truncates the rays.
void rayTrace3D(LocalGrid& grid, float rangeMax);

}  // namespace rtabmap
