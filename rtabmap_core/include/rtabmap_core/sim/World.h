#pragma once
// The simulated world: a 2.5D indoor building. Everything stands on a flat floor (z = 0) under a
// flat ceiling: walls and furniture are vertical extrusions of floor-plan polygons ("solids"),
// each with a height. That structure is what makes rendering fast (Renderer.h): a camera with
// no roll or pitch sees every vertical face as a run of pixels in one column, so one ray per
// image column in the floor plan finds everything a column shows.
//
// A solid's polygon edges are its faces. Each face has its own material (a wrapping texture and
// where the face sits on it) and its own decals (posters, doors, ... as clamped textures placed
// on the face). Floor and ceiling materials come from a raster of region ids over the floor
// plan (rooms and corridors), so a carpeted office can sit beside a tiled corridor.
//
// Face coordinates: s in metres from the face's first vertex a towards b (to the right for a
// viewer facing the face), h the height above the floor. Texture coordinates on a face are
// ((s + offsetS) * tpm, (offsetT - h) * tpm): texture rows go down as heights go up.
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/sim/Texture.h"

namespace rtabmap::sim {

struct SurfaceMaterial {
  int texture = -1;           // index into World::textures(); -1 = untextured grey
  float offsetS = 0.0f;       // metres: which part of the repeating texture shows
  float offsetT = 0.0f;
  float shade = 1.0f;         // light falling on the surface (1 = full)
  float reflectivity = 0.6f;  // laser return strength scale, 0..1
  // Which tile variant of the texture shows where (Texture::variantAt): faces that continue one
  // another (the pieces of a straight wall) share a key; floors and ceilings use 0, their tiles
  // being indexed in world coordinates.
  uint32_t variantKey = 0;
};

// A picture on a face: [s0, s1] along the face, [h0, h1] in height.
struct Decal {
  int texture = -1;
  float s0 = 0, s1 = 0, h0 = 0, h1 = 0;
};

struct Face {
  Eigen::Vector2d a, b;
  Eigen::Vector2d dir;     // unit vector a -> b
  Eigen::Vector2d normal;  // unit outward normal (the right of a -> b: polygons are kept CCW)
  double length = 0.0;
  float height = 0.0f;     // the solid's height
  int solid = -1;
  SurfaceMaterial material;
  int firstDecal = 0;  // this face's decals: World::decals()[firstDecal, firstDecal + decalCount),
  int decalCount = 0;  // sorted by s0, not overlapping
};

enum class SolidKind { kWall, kFurniture, kPillar };

struct Solid {
  std::vector<Eigen::Vector2d> polygon;  // counter-clockwise, simple
  float height = 0.0f;
  SolidKind kind = SolidKind::kWall;
  SurfaceMaterial top;  // the horizontal top (seen when lower than the viewer)
  int firstFace = 0;
  int faceCount = 0;
  std::string label;  // what it is ("wall", "desk", "bookshelf", ...), for debugging and tests
};

// A crossing of a face by a ray in the floor plan.
struct RayHit {
  double t = 0.0;       // ray parameter: the point is origin + t * dir
  int face = -1;
  bool entering = false;  // the ray goes into the solid here (it sees the face's outer side)
  double s = 0.0;       // metres along the face from its vertex a
};

class World {
 public:
  explicit World(double ceilingHeight);

  // ---- construction (then finalize()) ----
  int addTexture(const Texture& texture);
  // Adds an extruded polygon (any orientation: it is made counter-clockwise). `sides` gives
  // each edge's material (edge i runs from vertex i to i+1 of the polygon *as given*); a single
  // entry applies to every edge. Returns the solid's index.
  int addSolid(const std::vector<Eigen::Vector2d>& polygon, float height, SolidKind kind,
               const std::vector<SurfaceMaterial>& sides, const SurfaceMaterial& top,
               const std::string& label);
  // A decal on a face (face index from solid(i).firstFace + edge). Decals of a face must not
  // overlap in s (the renderer shows the first one that covers a column).
  void addDecal(int face, const Decal& decal);
  // Floor and ceiling materials: regions is CV_16UC1, cell (row j, col i) covering
  // [originX + i*cell, +cell) x [originY + j*cell, +cell); outside the raster, region 0.
  void setRegions(const cv::Mat& regions, double originX, double originY, double cell,
                  const std::vector<SurfaceMaterial>& floors, const std::vector<SurfaceMaterial>& ceilings);
  // Sorts decals and builds the ray-casting grid. Required before any query.
  void finalize();

  // ---- queries ----
  double ceilingHeight() const { return ceilingHeight_; }
  const std::vector<Texture>& textures() const { return textures_; }
  const std::vector<Solid>& solids() const { return solids_; }
  const std::vector<Face>& faces() const { return faces_; }
  const std::vector<Decal>& decals() const { return decals_; }
  Eigen::Vector2d boundsMin() const { return boundsMin_; }
  Eigen::Vector2d boundsMax() const { return boundsMax_; }

  // Casts a ray in the floor plan from `origin` along `dir` (any non-zero length: t is in units
  // of |dir|) for t in (0, tMax]. Appends to `hits` (cleared first) every face crossing in
  // increasing t, and stops after the first face the ray *enters* whose solid is at least
  // `stopHeight` tall; returns true if it stopped there, false if it left the world or reached
  // tMax first.
  bool castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir, double tMax, float stopHeight,
               std::vector<RayHit>& hits) const;

  int regionAt(double x, double y) const {
    const int i = static_cast<int>((x - regionOriginX_) * regionInvCell_);
    const int j = static_cast<int>((y - regionOriginY_) * regionInvCell_);
    if (x < regionOriginX_ || y < regionOriginY_ || i >= regions_.cols || j >= regions_.rows) return 0;
    return regions_.at<uint16_t>(j, i);
  }
  const SurfaceMaterial& floorAt(double x, double y) const { return floors_[static_cast<size_t>(regionAt(x, y))]; }
  const SurfaceMaterial& ceilingAt(double x, double y) const { return ceilings_[static_cast<size_t>(regionAt(x, y))]; }

  // Distance from a floor point to the nearest face of a solid at least minHeight tall
  // (brute force: for tests and planning, not for rendering).
  double clearance(const Eigen::Vector2d& p, float minHeight = 0.0f) const;
  // True if the point is inside a solid (at least minHeight tall).
  bool insideSolid(const Eigen::Vector2d& p, float minHeight = 0.0f) const;

 private:
  double ceilingHeight_;
  std::vector<Texture> textures_;
  std::vector<Solid> solids_;
  std::vector<Face> faces_;
  std::vector<Decal> decals_;
  std::vector<std::pair<int, Decal>> pendingDecals_;
  cv::Mat regions_ = cv::Mat::zeros(1, 1, CV_16UC1);
  double regionOriginX_ = 0.0, regionOriginY_ = 0.0, regionInvCell_ = 1.0;
  std::vector<SurfaceMaterial> floors_{SurfaceMaterial()};
  std::vector<SurfaceMaterial> ceilings_{SurfaceMaterial()};

  // Uniform grid over the faces' bounding box: cell -> faces that touch it.
  double cellSize_ = 1.0;
  int gridW_ = 0, gridH_ = 0;
  Eigen::Vector2d boundsMin_{0, 0}, boundsMax_{0, 0};
  std::vector<int> cellStart_;  // CSR layout: faces of cell c are cellFaces_[cellStart_[c] .. cellStart_[c+1])
  std::vector<int> cellFaces_;
  bool finalized_ = false;
};

}  // namespace rtabmap::sim
