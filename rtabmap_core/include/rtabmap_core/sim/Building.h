#pragma once
// Procedural indoor buildings for the simulator: a grid of corridors around blocks of rooms,
// optionally ringed by a band of rooms along the facade, like an office or university floor.
//
//   +--------------------------------------+   outer band rooms (optional)
//   | room | room |  room  | room | room   |
//   |------+------+--------+------+--------|
//   |   corridor ring / grid               |
//   |   +---------+   +---------+          |
//   |   |room|room|   |room|room|  blocks  |
//   |   |----+----|   |----+----|  of rooms|
//   |   |room|room|   |room|room|          |
//   |   +---------+   +---------+          |
//   |                                      |
//   +--------------------------------------+
//
// Every room has a door (an opening in its wall) onto a corridor. Walls, floors, ceilings and
// furniture get materials from a palette generated per building (so materials recur from room
// to room, as in a real building) and unique decals (posters, doors, signs, windows...). Some
// walls are left as plain paint, deliberately textureless.
//
// The building also carries a navigation graph for the route planner: corridor junctions,
// points on corridor centre lines in front of each door, and a visit point inside each room.
#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rtabmap_core/sim/World.h"

namespace rtabmap::sim {

struct BuildingSpec {
  int blocksX = 1;              // blocks of rooms along x and y, with corridors between and
  int blocksY = 1;              //   around them
  double blockMinWidth = 11.0;  // x size of a column of blocks, drawn in [min, max]
  double blockMaxWidth = 14.0;
  double blockMinDepth = 8.0;   // y size of a row of blocks
  double blockMaxDepth = 10.0;
  double corridorWidth = 2.2;
  double outerRoomDepth = 5.0;  // depth of the band of rooms along the facade (0: none)
  double roomMinWidth = 3.2;
  double roomMaxWidth = 6.0;
  double doorMinWidth = 1.1;    // openings are a little wider than real doors: the robot goes
  double doorMaxWidth = 1.3;    //   through them on a planned path, without local avoidance
  double wallThickness = 0.12;
  double ceilingHeight = 2.7;
  // Share of room walls left as plain paint (textureless); corridors follow plainCorridors.
  double plainWallShare = 0.3;
  // Corridor walls as plain paint with almost no decals (the "corridor" scenario).
  bool plainCorridors = false;
  double furnitureDensity = 1.0;  // 0: empty rooms
  double decalDensity = 1.0;      // 0: no posters, signs, doors...
  // Texture quality: tile size (power of two) and texels per metre of materials, and decal
  // texels per metre. Lower values make worlds faster to generate (tests).
  int materialSize = 512;
  float materialTexelsPerMetre = 128.0f;
  float decalTexelsPerMetre = 256.0f;
  // Tile variants of the materials that cover large surfaces (variesPerTile in Materials.h):
  // each tile of a floor, ceiling or brick wall shows one of them, picked by a hash of its
  // position, so the building does not repeat itself exactly every tile period (4 m). 1: plain
  // periodic tiles. Costs that many times the generation time and memory of those materials.
  int materialVariants = 4;
};

struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  Eigen::Vector2d centre() const { return {0.5 * (x0 + x1), 0.5 * (y0 + y1)}; }
  bool contains(const Eigen::Vector2d& p, double margin = 0.0) const {
    return p.x() >= x0 + margin && p.x() <= x1 - margin && p.y() >= y0 + margin && p.y() <= y1 - margin;
  }
};

enum class AreaKind { kCorridor, kRoom };

struct Area {
  int id = 0;
  AreaKind kind = AreaKind::kRoom;
  Rect rect;                 // between wall centre lines
  std::string name;          // "corridor 2", "room 114"
  std::vector<int> doors;    // indices into Building::doors
  Eigen::Vector2d visitPoint{0, 0};  // where a robot visiting the room goes (rooms only)
  bool plain = false;        // all walls plain paint
};

struct Door {
  Eigen::Vector2d centre{0, 0};   // on the wall's centre line
  Eigen::Vector2d inward{0, 0};   // unit, from the corridor into the room
  double width = 1.0;
  int room = -1;
  int corridor = -1;
  Eigen::Vector2d front{0, 0};    // on the corridor's centre line, in front of the door
  Eigen::Vector2d inside{0, 0};   // 0.9 m into the room, straight through the door
};

struct NavEdge {
  int to = -1;
  double length = 0.0;
  std::vector<Eigen::Vector2d> via;  // waypoints between the two nodes (through a door)
};

enum class NavNodeKind { kJunction, kDoorFront, kRoom };

struct NavNode {
  Eigen::Vector2d position{0, 0};
  NavNodeKind kind = NavNodeKind::kJunction;
  int area = -1;  // room of a kRoom node, corridor of the others
  int door = -1;  // door of kDoorFront and kRoom nodes
  int gridX = -1, gridY = -1;  // junction indices (kJunction only)
};

class NavGraph {
 public:
  int addNode(const NavNode& node);
  void addEdge(int a, int b, const std::vector<Eigen::Vector2d>& viaFromA = {});
  const std::vector<NavNode>& nodes() const { return nodes_; }
  const std::vector<NavEdge>& edges(int node) const { return edges_[static_cast<size_t>(node)]; }
  const NavEdge* edge(int a, int b) const;
  // Shortest node sequence from a to b (Dijkstra, both included); empty if unreachable.
  std::vector<int> shortestPath(int a, int b) const;
  // The junction at grid indices (i, j), or -1.
  int junction(int i, int j) const;
  // The waypoints of a node sequence: node positions with the via points of the edges between.
  std::vector<Eigen::Vector2d> waypoints(const std::vector<int>& nodes) const;

 private:
  std::vector<NavNode> nodes_;
  std::vector<std::vector<NavEdge>> edges_;
};

struct Building {
  BuildingSpec spec;
  uint64_t seed = 0;
  std::unique_ptr<World> world;
  std::vector<Area> areas;
  std::vector<Door> doors;
  NavGraph nav;
  int junctionsX = 0;  // junction grid size: blocksX + 1 by blocksY + 1
  int junctionsY = 0;
  double width = 0.0;  // outer walls at x = 0 and width, y = 0 and depth
  double depth = 0.0;
  // The block (i, j) rectangle, between wall centre lines.
  std::vector<Rect> blocks;
  int roomCount() const;
};

// Generates a building from the spec and seed (deterministic). Throws std::invalid_argument for
// a spec that cannot give a building (no blocks, rooms narrower than a door...).
Building generateBuilding(const BuildingSpec& spec, uint64_t seed);

}  // namespace rtabmap::sim
