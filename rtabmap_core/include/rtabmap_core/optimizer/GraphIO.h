#pragma once
// Pose graphs to and from the text formats of other tools.
//
// g2o: VERTEX_SE2 id x y theta
//      EDGE_SE2 i j x y theta  I11 I12 I13 I22 I23 I33          (upper triangle, x y theta)
//      VERTEX_SE3:QUAT id x y z qx qy qz qw
//      EDGE_SE3:QUAT i j x y z qx qy qz qw  21 values           (upper triangle, x y z qx qy qz)
//      FIX id [id ...]                                          (nodes g2o holds fixed)
// TORO: VERTEX2 id x y theta          EDGE2 i j x y theta  Ixx Ixy Iyy Itt Ixt Iyt
//       VERTEX3 id x y z roll pitch yaw
//       EDGE3 i j x y z roll pitch yaw  21 values (upper triangle, x y z roll pitch yaw)
//       (VERTEX and EDGE are read as VERTEX2 and EDGE2.)
// Blank lines and '#' comments are skipped.
//
// Information conversions (see Chi2.h): g2o SE3 matrices are per quaternion-vector unit and
// become per-radian Link matrices (rotation rows and columns halved), and back when writing.
// 2D matrices (x y theta) fill rows/columns x, y, yaw of the Link matrix; z, roll and pitch get
// 1 (ignored in 3DoF, needed for a positive-definite Link).
//
// Link types: an edge between consecutive ids (|i - j| = 1) becomes kNeighbor (odometry), any
// other kGlobalClosure, so odometry initialisation, robust losses and the max-error check treat
// them as such. Writers write every relative link whatever its type; priors and gravity links
// (from == to) have no g2o / TORO form here and are skipped (counted in the result).
//
// Reading errors throw FormatError "<path>:<line>: <what>" for: an unknown tag, a wrong number
// of values, a value that is not a number, NaN or infinity, a zero quaternion, a vertex id given
// twice, an edge from a node to itself, an information matrix that is not symmetric positive
// definite, 2D and 3D records mixed, an edge to a node that has no vertex (when the file has
// vertices), and a file without any vertex or edge (the error then names the line count).
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap::graph {

struct PoseGraphFile {
  // Every node of the file. With vertices: their poses. Edges only: every id met in an edge,
  // with a null pose (the optimiser initialises it).
  std::map<int, Transform> poses;
  std::multimap<int, Link> links;  // keyed by `from`
  bool is2D = false;
  bool hasVertices = false;
  std::vector<int> fixedIds;  // g2o FIX records, in file order
};

enum class GraphFormat { kG2o, kToro };
// By extension: ".g2o" -> g2o, ".graph" / ".toro" -> TORO; throws FormatError otherwise.
GraphFormat graphFormatFromPath(const std::string& path);

PoseGraphFile readG2o(const std::string& path);
// The same on text already read; sourceName is used in error messages.
PoseGraphFile parseG2o(std::istream& in, const std::string& sourceName);
PoseGraphFile readToro(const std::string& path);
PoseGraphFile parseToro(std::istream& in, const std::string& sourceName);
// readG2o or readToro by extension.
PoseGraphFile readGraph(const std::string& path);

// Writes the non-null poses as vertices (increasing ids), then the relative links as edges, each
// number in the shortest form that reads back to the same double. Returns the number of links
// skipped (priors, gravity). is2D writes the 3DoF records (x, y, yaw of each transform).
// Throws FormatError if the file cannot be written.
int writeG2o(const std::string& path, const std::map<int, Transform>& poses,
             const std::multimap<int, Link>& links, bool is2D);
int formatG2o(std::ostream& out, const std::map<int, Transform>& poses,
              const std::multimap<int, Link>& links, bool is2D);
int writeToro(const std::string& path, const std::map<int, Transform>& poses,
              const std::multimap<int, Link>& links, bool is2D);
int formatToro(std::ostream& out, const std::map<int, Transform>& poses,
               const std::multimap<int, Link>& links, bool is2D);
// writeG2o or writeToro by extension.
int writeGraph(const std::string& path, const std::map<int, Transform>& poses,
               const std::multimap<int, Link>& links, bool is2D);

}  // namespace rtabmap::graph
