// TORO pose-graph files (see GraphIO.h), and the choice of format by extension.
#include <cctype>
#include <fstream>
#include <sstream>

#include "GraphText.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap::graph {

namespace oi = optimizer_internal;

namespace {

// TORO 2D information order: xx, xy, yy, tt, xt, yt.
Eigen::Matrix3d toroInformation2D(const double* v) {
  Eigen::Matrix3d m;
  m << v[0], v[1], v[4],
       v[1], v[2], v[5],
       v[4], v[5], v[3];
  return m;
}

std::string extensionOf(const std::string& path) {
  const std::string::size_type dot = path.find_last_of('.');
  const std::string::size_type slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

PoseGraphFile parseToro(std::istream& in, const std::string& sourceName) {
  oi::GraphTextBuilder builder(sourceName);
  std::string line;
  int lineNumber = 0;
  oi::TextRecord record;
  double v[27];
  while (std::getline(in, line)) {
    ++lineNumber;
    record.line = lineNumber;
    record.tokens = oi::tokenize(line);
    if (record.tokens.empty()) continue;
    const std::string& tag = record.tokens[0];
    if (tag == "VERTEX2" || tag == "VERTEX") {
      builder.expectValues(record, 4);
      builder.dimension(record, true);
      builder.numbers(record, 2, 3, v);
      builder.addVertex(record, builder.id(record, 1), Transform(v[0], v[1], v[2]));
    } else if (tag == "EDGE2" || tag == "EDGE") {
      builder.expectValues(record, 11);
      builder.dimension(record, true);
      const int from = builder.id(record, 1), to = builder.id(record, 2);
      builder.numbers(record, 3, 9, v);
      const Eigen::Matrix3d info = toroInformation2D(v + 3);
      builder.addEdge(record, from, to, Transform(v[0], v[1], v[2]),
                      linkInformationFromSE2(info), Eigen::MatrixXd(info));
    } else if (tag == "VERTEX3") {
      builder.expectValues(record, 7);
      builder.dimension(record, false);
      builder.numbers(record, 2, 6, v);
      builder.addVertex(record, builder.id(record, 1), Transform(v[0], v[1], v[2], v[3], v[4], v[5]));
    } else if (tag == "EDGE3") {
      builder.expectValues(record, 29);
      builder.dimension(record, false);
      const int from = builder.id(record, 1), to = builder.id(record, 2);
      builder.numbers(record, 3, 27, v);
      const Eigen::MatrixXd info = oi::symmetricFromUpper(v + 6, 6);
      builder.addEdge(record, from, to, Transform(v[0], v[1], v[2], v[3], v[4], v[5]),
                      Link::InfMatrix(info), info);
    } else {
      builder.fail(lineNumber, "unknown tag '" + tag +
                                   "' (this reader knows VERTEX2, EDGE2, VERTEX3, EDGE3, VERTEX "
                                   "and EDGE)");
    }
  }
  return builder.finish(lineNumber);
}

PoseGraphFile readToro(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FormatError(path + ": cannot open the file for reading");
  return parseToro(in, path);
}

int formatToro(std::ostream& out, const std::map<int, Transform>& poses,
               const std::multimap<int, Link>& links, bool is2D) {
  using oi::formatNumber;
  for (const auto& [id, pose] : poses) {
    if (pose.isNull()) continue;
    if (is2D) {
      out << "VERTEX2 " << id << ' ' << formatNumber(pose.x()) << ' ' << formatNumber(pose.y())
          << ' ' << formatNumber(pose.yaw()) << '\n';
    } else {
      double x, y, z, roll, pitch, yaw;
      pose.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
      out << "VERTEX3 " << id;
      for (double value : {x, y, z, roll, pitch, yaw}) out << ' ' << formatNumber(value);
      out << '\n';
    }
  }
  int skipped = 0;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to() || link.type() == Link::kPosePrior ||
        link.type() == Link::kGravity || link.transform().isNull()) {
      ++skipped;
      continue;
    }
    const Transform& t = link.transform();
    const Link::InfMatrix& info = link.infMatrix();
    if (is2D) {
      const Eigen::Matrix3d m = informationSE2(info);
      out << "EDGE2 " << link.from() << ' ' << link.to() << ' ' << formatNumber(t.x()) << ' '
          << formatNumber(t.y()) << ' ' << formatNumber(t.yaw());
      for (double value : {m(0, 0), m(0, 1), m(1, 1), m(2, 2), m(0, 2), m(1, 2)}) {
        out << ' ' << formatNumber(value);
      }
    } else {
      double x, y, z, roll, pitch, yaw;
      t.getTranslationAndEulerAngles(x, y, z, roll, pitch, yaw);
      out << "EDGE3 " << link.from() << ' ' << link.to();
      for (double value : {x, y, z, roll, pitch, yaw}) out << ' ' << formatNumber(value);
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) out << ' ' << formatNumber(info(r, c));
      }
    }
    out << '\n';
  }
  return skipped;
}

int writeToro(const std::string& path, const std::map<int, Transform>& poses,
              const std::multimap<int, Link>& links, bool is2D) {
  std::ofstream out(path);
  if (!out) throw FormatError(path + ": cannot open the file for writing");
  const int skipped = formatToro(out, poses, links, is2D);
  out.flush();
  if (!out) throw FormatError(path + ": write failed (disk full?)");
  return skipped;
}

GraphFormat graphFormatFromPath(const std::string& path) {
  const std::string ext = extensionOf(path);
  if (ext == ".g2o") return GraphFormat::kG2o;
  if (ext == ".graph" || ext == ".toro") return GraphFormat::kToro;
  throw FormatError(path + ": unknown pose-graph format (expected a .g2o, .graph or .toro file)");
}

PoseGraphFile readGraph(const std::string& path) {
  return graphFormatFromPath(path) == GraphFormat::kG2o ? readG2o(path) : readToro(path);
}

int writeGraph(const std::string& path, const std::map<int, Transform>& poses,
               const std::multimap<int, Link>& links, bool is2D) {
  return graphFormatFromPath(path) == GraphFormat::kG2o ? writeG2o(path, poses, links, is2D)
                                                        : writeToro(path, poses, links, is2D);
}

}  // namespace rtabmap::graph
