#include "GraphText.h"

#include <Eigen/Cholesky>

#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::optimizer_internal {

void GraphTextBuilder::fail(int line, const std::string& what) const {
  std::ostringstream s;
  s << source_ << ":" << line << ": " << what;
  throw FormatError(s.str());
}

void GraphTextBuilder::expectValues(const TextRecord& record, std::size_t count) const {
  const std::size_t got = record.tokens.size() - 1;
  if (got != count) {
    std::ostringstream s;
    s << record.tokens[0] << " needs " << count << " values after the tag, found " << got;
    fail(record.line, s.str());
  }
}

int GraphTextBuilder::id(const TextRecord& record, std::size_t index) const {
  const std::string& text = record.tokens.at(index);
  int value = 0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(begin, end, value);
  if (result.ec != std::errc() || result.ptr != end) {
    fail(record.line, record.tokens[0] + ": '" + text + "' is not a node id (an integer)");
  }
  return value;
}

double GraphTextBuilder::number(const TextRecord& record, std::size_t index) const {
  const std::string& text = record.tokens.at(index);
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;
  double value = 0.0;
  const auto result = std::from_chars(begin, end, value);
  if (result.ec != std::errc() || result.ptr != end || begin == end) {
    fail(record.line, record.tokens[0] + ": '" + text + "' is not a number");
  }
  if (!std::isfinite(value)) {
    fail(record.line, record.tokens[0] + ": value '" + text + "' is NaN or infinite");
  }
  return value;
}

void GraphTextBuilder::numbers(const TextRecord& record, std::size_t index, std::size_t count,
                               double* out) const {
  for (std::size_t k = 0; k < count; ++k) out[k] = number(record, index + k);
}

void GraphTextBuilder::dimension(const TextRecord& record, bool is2D) {
  if (dimensionLine_ == 0) {
    dimensionLine_ = record.line;
    file_.is2D = is2D;
  } else if (file_.is2D != is2D) {
    std::ostringstream s;
    s << record.tokens[0] << " is a " << (is2D ? "2D" : "3D") << " record but line "
      << dimensionLine_ << " made this a " << (file_.is2D ? "2D" : "3D")
      << " graph: 2D and 3D records cannot be mixed";
    fail(record.line, s.str());
  }
}

void GraphTextBuilder::addVertex(const TextRecord& record, int id, const Transform& pose) {
  if (!file_.poses.emplace(id, pose).second) {
    fail(record.line, record.tokens[0] + ": vertex " + std::to_string(id) + " is given twice");
  }
  file_.hasVertices = true;
}

void GraphTextBuilder::addEdge(const TextRecord& record, int from, int to, const Transform& z,
                               const Link::InfMatrix& information,
                               const Eigen::MatrixXd& fileInformation) {
  if (from == to) {
    fail(record.line, record.tokens[0] + ": edge from node " + std::to_string(from) +
                          " to itself");
  }
  Eigen::LLT<Eigen::MatrixXd> llt(fileInformation);
  if (llt.info() != Eigen::Success) {
    fail(record.line, record.tokens[0] + " " + std::to_string(from) + " " + std::to_string(to) +
                          ": the information matrix is not positive definite");
  }
  const Link::Type type = (from - to == 1 || to - from == 1) ? Link::kNeighbor
                                                             : Link::kGlobalClosure;
  file_.links.emplace(from, Link(from, to, type, z, information));
  edgeEnds_.push_back({record.line, {from, to}});
}

graph::PoseGraphFile GraphTextBuilder::finish(int lineCount) {
  if (file_.poses.empty() && file_.links.empty()) {
    std::ostringstream s;
    s << source_ << ":" << lineCount << ": empty graph: no vertex or edge in " << lineCount
      << (lineCount == 1 ? " line" : " lines");
    throw FormatError(s.str());
  }
  if (file_.hasVertices) {
    for (const auto& [line, ends] : edgeEnds_) {
      for (int id : {ends.first, ends.second}) {
        if (!file_.poses.count(id)) {
          std::ostringstream s;
          s << "edge " << ends.first << " -> " << ends.second << " refers to node " << id
            << ", which has no vertex";
          fail(line, s.str());
        }
      }
    }
  } else {
    for (const auto& [line, ends] : edgeEnds_) {
      (void)line;
      file_.poses.emplace(ends.first, Transform());
      file_.poses.emplace(ends.second, Transform());
    }
  }
  return std::move(file_);
}

std::vector<std::string> tokenize(const std::string& line) {
  std::vector<std::string> tokens;
  const std::string::size_type hash = line.find('#');
  std::istringstream in(hash == std::string::npos ? line : line.substr(0, hash));
  std::string token;
  while (in >> token) tokens.push_back(token);
  return tokens;
}

Eigen::MatrixXd symmetricFromUpper(const double* values, int n) {
  Eigen::MatrixXd m(n, n);
  int k = 0;
  for (int r = 0; r < n; ++r) {
    for (int c = r; c < n; ++c) {
      m(r, c) = m(c, r) = values[k++];
    }
  }
  return m;
}

std::string formatNumber(double value) {
  // Shortest text that reads back to the same double, whatever the C locale.
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

}  // namespace rtabmap::optimizer_internal
