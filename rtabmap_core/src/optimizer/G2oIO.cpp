// g2o pose-graph files (see GraphIO.h).
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "GraphText.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/optimizer/Chi2.h"
#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap::graph {

namespace oi = optimizer_internal;

namespace {

Transform quaternionPose(const oi::GraphTextBuilder& builder, const oi::TextRecord& record,
                         const double* v) {
  try {
    return Transform(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
  } catch (const std::invalid_argument&) {
    builder.fail(record.line, record.tokens[0] + ": the quaternion is zero");
  }
}

}  // namespace

PoseGraphFile parseG2o(std::istream& in, const std::string& sourceName) {
  oi::GraphTextBuilder builder(sourceName);
  std::string line;
  int lineNumber = 0;
  oi::TextRecord record;
  double v[30];
  while (std::getline(in, line)) {
    ++lineNumber;
    record.line = lineNumber;
    record.tokens = oi::tokenize(line);
    if (record.tokens.empty()) continue;
    const std::string& tag = record.tokens[0];
    if (tag == "VERTEX_SE2") {
      builder.expectValues(record, 4);
      builder.dimension(record, true);
      builder.numbers(record, 2, 3, v);
      builder.addVertex(record, builder.id(record, 1), Transform(v[0], v[1], v[2]));
    } else if (tag == "EDGE_SE2") {
      builder.expectValues(record, 11);
      builder.dimension(record, true);
      const int from = builder.id(record, 1), to = builder.id(record, 2);
      builder.numbers(record, 3, 9, v);
      const Eigen::MatrixXd info = oi::symmetricFromUpper(v + 3, 3);
      builder.addEdge(record, from, to, Transform(v[0], v[1], v[2]),
                      linkInformationFromSE2(Eigen::Matrix3d(info)), info);
    } else if (tag == "VERTEX_SE3:QUAT") {
      builder.expectValues(record, 8);
      builder.dimension(record, false);
      builder.numbers(record, 2, 7, v);
      builder.addVertex(record, builder.id(record, 1), quaternionPose(builder, record, v));
    } else if (tag == "EDGE_SE3:QUAT") {
      builder.expectValues(record, 30);
      builder.dimension(record, false);
      const int from = builder.id(record, 1), to = builder.id(record, 2);
      builder.numbers(record, 3, 28, v);
      const Eigen::MatrixXd info = oi::symmetricFromUpper(v + 7, 6);
      builder.addEdge(record, from, to, quaternionPose(builder, record, v),
                      informationSE3FromG2o(Matrix6(info)), info);
    } else if (tag == "FIX") {
      if (record.tokens.size() < 2) builder.fail(lineNumber, "FIX needs at least one node id");
      for (std::size_t k = 1; k < record.tokens.size(); ++k) builder.addFixed(builder.id(record, k));
    } else {
      builder.fail(lineNumber, "unknown tag '" + tag +
                                   "' (this reader knows VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, "
                                   "EDGE_SE3:QUAT and FIX)");
    }
  }
  return builder.finish(lineNumber);
}

PoseGraphFile readG2o(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FormatError(path + ": cannot open the file for reading");
  return parseG2o(in, path);
}

int formatG2o(std::ostream& out, const std::map<int, Transform>& poses,
              const std::multimap<int, Link>& links, bool is2D) {
  using oi::formatNumber;
  for (const auto& [id, pose] : poses) {
    if (pose.isNull()) continue;
    if (is2D) {
      out << "VERTEX_SE2 " << id << ' ' << formatNumber(pose.x()) << ' ' << formatNumber(pose.y())
          << ' ' << formatNumber(pose.yaw()) << '\n';
    } else {
      const Eigen::Vector3d t = pose.translation();
      const Eigen::Quaterniond q = pose.quaternion().normalized();
      out << "VERTEX_SE3:QUAT " << id;
      for (double value : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
        out << ' ' << formatNumber(value);
      }
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
    const Transform& z = link.transform();
    if (is2D) {
      out << "EDGE_SE2 " << link.from() << ' ' << link.to() << ' ' << formatNumber(z.x()) << ' '
          << formatNumber(z.y()) << ' ' << formatNumber(z.yaw());
      const Eigen::Matrix3d info = informationSE2(link.infMatrix());
      for (int r = 0; r < 3; ++r) {
        for (int c = r; c < 3; ++c) out << ' ' << formatNumber(info(r, c));
      }
    } else {
      const Eigen::Vector3d t = z.translation();
      const Eigen::Quaterniond q = z.quaternion().normalized();
      out << "EDGE_SE3:QUAT " << link.from() << ' ' << link.to();
      for (double value : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
        out << ' ' << formatNumber(value);
      }
      const Matrix6 info = informationSE3ToG2o(link.infMatrix());
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) out << ' ' << formatNumber(info(r, c));
      }
    }
    out << '\n';
  }
  return skipped;
}

int writeG2o(const std::string& path, const std::map<int, Transform>& poses,
             const std::multimap<int, Link>& links, bool is2D) {
  std::ofstream out(path);
  if (!out) throw FormatError(path + ": cannot open the file for writing");
  const int skipped = formatG2o(out, poses, links, is2D);
  out.flush();
  if (!out) throw FormatError(path + ": write failed (disk full?)");
  return skipped;
}

}  // namespace rtabmap::graph
