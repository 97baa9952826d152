#pragma once
// What the g2o and TORO readers share (internal header): line splitting, strict number parsing
// and the checks that make a PoseGraphFile consistent, each error naming "<source>:<line>".
#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

#include "rtabmap_core/optimizer/GraphIO.h"

namespace rtabmap::optimizer_internal {

// One record: its tokens (the tag first), without comments.
struct TextRecord {
  int line = 0;
  std::vector<std::string> tokens;
};

class GraphTextBuilder {
 public:
  explicit GraphTextBuilder(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(int line, const std::string& what) const;

  // Checks the record has `count` values after the tag.
  void expectValues(const TextRecord& record, std::size_t count) const;
  int id(const TextRecord& record, std::size_t index) const;
  double number(const TextRecord& record, std::size_t index) const;
  // Fills `count` numbers starting at token `index`.
  void numbers(const TextRecord& record, std::size_t index, std::size_t count, double* out) const;

  // All records of a file must be 2D or all 3D.
  void dimension(const TextRecord& record, bool is2D);
  void addVertex(const TextRecord& record, int id, const Transform& pose);
  // `information` is in the Link convention; `fileInformation` (the matrix as written in the
  // file, any size) is what is checked for positive definiteness.
  void addEdge(const TextRecord& record, int from, int to, const Transform& z,
               const Link::InfMatrix& information, const Eigen::MatrixXd& fileInformation);
  void addFixed(int id) { file_.fixedIds.push_back(id); }

  // Final checks (edges to missing vertices, empty file); lineCount is the number of lines read.
  graph::PoseGraphFile finish(int lineCount);

 private:
  std::string source_;
  graph::PoseGraphFile file_;
  int dimensionLine_ = 0;
  std::vector<std::pair<int, std::pair<int, int>>> edgeEnds_;  // line, (from, to)
};

// Splits a line into tokens, dropping a '#' comment. Empty when blank.
std::vector<std::string> tokenize(const std::string& line);

// Upper-triangle values (row by row) into a symmetric n x n matrix.
Eigen::MatrixXd symmetricFromUpper(const double* values, int n);

// Number formatting for the writers: the shortest text that reads back to the same double.
std::string formatNumber(double value);

}  // namespace rtabmap::optimizer_internal
