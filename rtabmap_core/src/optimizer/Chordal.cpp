// Chordal relaxation initialisation of a pose graph (see Initialization.h).
//
// Both stages solve the same kind of problem: unknowns x_k (D x K blocks, one per node but the
// root, whose value is fixed) and, for every link i -> j, a residual x_j - M x_i - c weighted by
// a D x D matrix W. Rotations: D = 3 (2 in 2D), x_k = R_k' (the rows of R_k) so R_j = R_i R_ij
// reads x_j = R_ij' x_i, K = 3 right-hand sides (K = 1 in 2D where x_k = (cos, sin) and
// x_j = Rot(theta_ij) x_i), c = 0. Positions: D = 3 (2), x_k = t_k, M = I, c = R_i t_ij, K = 1.
// The normal equations are sparse and symmetric positive definite on a connected graph, solved
// by CHOLMOD (SparseCholesky.h). Both stages have the same block pattern (full D x D blocks are
// stored, explicit zeros included), so one symbolic analysis serves the two factorisations.
#include <Eigen/OrderingMethods>
#include <Eigen/SVD>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_map>
#include <vector>

#include "PoseMath.h"
#include "SparseCholesky.h"
#include "rtabmap_core/optimizer/Initialization.h"

namespace rtabmap::graph {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

template <int D, int K>
struct Term {
  int i, j;
  Eigen::Matrix<double, D, D> m;
  Eigen::Matrix<double, D, D> w;
  Eigen::Matrix<double, D, K> c;
};

// A fill-reducing ordering of the unknowns: minimum degree (Eigen's AMD) on the graph of the
// free nodes, each node then expanded to its D unknowns. Computed on a graph D^2 times smaller
// than the scalar matrix's, and the same for both stages.
template <int D, int K>
std::vector<int> blockOrdering(int n, int root, const std::vector<Term<D, K>>& terms) {
  auto freeIndex = [&](int node) { return node < root ? node : node - 1; };
  const int nodes = n - 1;
  std::vector<Eigen::Triplet<double>> pattern;
  pattern.reserve(2 * terms.size() + nodes);
  for (int k = 0; k < nodes; ++k) pattern.emplace_back(k, k, 1.0);
  for (const auto& t : terms) {
    if (t.i == root || t.j == root || t.i == t.j) continue;
    pattern.emplace_back(freeIndex(t.i), freeIndex(t.j), 1.0);
    pattern.emplace_back(freeIndex(t.j), freeIndex(t.i), 1.0);
  }
  SparseMatrix graph(nodes, nodes);
  graph.setFromTriplets(pattern.begin(), pattern.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
  Eigen::AMDOrdering<int>()(graph, perm);
  std::vector<int> ordering(static_cast<std::size_t>(nodes) * D);
  for (int k = 0; k < nodes; ++k) {
    for (int d = 0; d < D; ++d) ordering[k * D + d] = perm.indices()[k] * D + d;
  }
  return ordering;
}

// Solves min sum (x_j - M x_i - c)' W (x_j - M x_i - c) with x_root = rootValue; full D x D
// blocks are stored (explicit zeros included) so both stages share one pattern. The solver is
// analysed on the first call (analysed = false) and reused. Fills the n * D x K solution (root
// rows: rootValue).
template <int D, int K>
bool solveBlocks(int n, int root, const Eigen::Matrix<double, D, K>& rootValue,
                 const std::vector<Term<D, K>>& terms, optimizer_internal::SparseCholesky& solver,
                 bool analysed, Eigen::MatrixXd* x, std::string* why) {
  auto freeIndex = [&](int node) { return node < root ? node : node - 1; };
  const int unknowns = (n - 1) * D;
  x->resize(static_cast<Eigen::Index>(n) * D, K);
  x->template block<D, K>(static_cast<Eigen::Index>(root) * D, 0) = rootValue;
  if (unknowns == 0) return true;

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(terms.size() * 4 * D * D);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(unknowns, K);
  auto addBlock = [&](int rowNode, int colNode, const Eigen::Matrix<double, D, D>& block) {
    const int r0 = freeIndex(rowNode) * D, c0 = freeIndex(colNode) * D;
    for (int c = 0; c < D; ++c) {
      for (int r = 0; r < D; ++r) triplets.emplace_back(r0 + r, c0 + c, block(r, c));
    }
  };
  for (const Term<D, K>& t : terms) {
    if (t.i == t.j) continue;
    const bool iFree = t.i != root, jFree = t.j != root;
    // Constant part of the residual: -c, plus the fixed root's contribution.
    Eigen::Matrix<double, D, K> constant = -t.c;
    if (!iFree) constant -= t.m * rootValue;
    if (!jFree) constant += rootValue;
    if (jFree) {
      addBlock(t.j, t.j, t.w);
      b.template block<D, K>(freeIndex(t.j) * D, 0) -= t.w * constant;
    }
    if (iFree) {
      const Eigen::Matrix<double, D, D> mtw = t.m.transpose() * t.w;
      addBlock(t.i, t.i, mtw * t.m);
      b.template block<D, K>(freeIndex(t.i) * D, 0) += mtw * constant;
      if (jFree) {
        addBlock(t.i, t.j, -mtw);
        addBlock(t.j, t.i, -mtw.transpose());
      }
    }
  }
  SparseMatrix h(unknowns, unknowns);
  h.setFromTriplets(triplets.begin(), triplets.end());
  std::string reason;
  Eigen::MatrixXd solution;
  std::vector<int> ordering;
  if (!analysed) ordering = blockOrdering(n, root, terms);
  if ((!analysed && !solver.analyze(h, &ordering, &reason)) || !solver.factorize(h, &reason) ||
      !solver.solve(b, &solution, &reason)) {
    if (why) *why = "chordal initialisation: " + reason;
    return false;
  }
  for (int node = 0; node < n; ++node) {
    if (node == root) continue;
    x->template block<D, K>(static_cast<Eigen::Index>(node) * D, 0) =
        solution.template block<D, K>(freeIndex(node) * D, 0);
  }
  return true;
}

Eigen::Matrix3d projectToSO3(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  Eigen::Matrix3d r = u * svd.matrixV().transpose();
  if (r.determinant() < 0.0) {
    u.col(2) = -u.col(2);
    r = u * svd.matrixV().transpose();
  }
  return r;
}

struct Edge {
  int i, j;  // node indices
  const Link* link;
};

// The root's component: node ids (index order = increasing id) and the links inside it.
void componentOf(int root, const std::multimap<int, Link>& links, std::vector<int>* ids,
                 std::vector<Edge>* edges, int* rootIndex) {
  std::unordered_map<int, std::vector<int>> adj;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to() || link.transform().isNull()) continue;
    adj[link.from()].push_back(link.to());
    adj[link.to()].push_back(link.from());
  }
  std::unordered_map<int, int> index{{root, 0}};
  std::deque<int> queue{root};
  while (!queue.empty()) {
    const int id = queue.front();
    queue.pop_front();
    const auto it = adj.find(id);
    if (it == adj.end()) continue;
    for (int other : it->second) {
      if (index.emplace(other, 0).second) queue.push_back(other);
    }
  }
  ids->clear();
  for (const auto& entry : index) ids->push_back(entry.first);
  std::sort(ids->begin(), ids->end());
  for (std::size_t k = 0; k < ids->size(); ++k) index[(*ids)[k]] = static_cast<int>(k);
  *rootIndex = index.at(root);
  edges->clear();
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.from() == link.to() || link.transform().isNull()) continue;
    const auto a = index.find(link.from());
    if (a == index.end()) continue;
    edges->push_back({a->second, index.at(link.to()), &link});
  }
}

// D = 2 (SE2) or 3 (SE3); KR = right-hand sides of the rotation stage (1 or 3).
template <int D, int KR>
std::map<int, Transform> chordal(int root, const Transform& start,
                                 const std::multimap<int, Link>& links, bool identityInformation,
                                 std::string* why) {
  constexpr bool is2D = D == 2;
  std::vector<int> ids;
  std::vector<Edge> edges;
  int r = 0;
  componentOf(root, links, &ids, &edges, &r);
  const int n = static_cast<int>(ids.size());
  std::map<int, Transform> out;

  // ---- Rotations.
  std::vector<Term<D, KR>> rotationTerms;
  rotationTerms.reserve(edges.size());
  for (const Edge& e : edges) {
    const Link::InfMatrix& info = e.link->infMatrix();
    const double w = identityInformation ? 1.0
                     : is2D ? info(5, 5)
                            : (info(3, 3) + info(4, 4) + info(5, 5)) / 3.0;
    Term<D, KR> t;
    t.i = e.i;
    t.j = e.j;
    if constexpr (is2D) {
      const double a = e.link->transform().yaw();
      t.m << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    } else {
      t.m = e.link->transform().rotationMatrix().transpose();
    }
    t.w = w * Eigen::Matrix<double, D, D>::Identity();
    t.c.setZero();
    rotationTerms.push_back(t);
  }
  Eigen::Matrix<double, D, KR> rootRotation;
  if constexpr (is2D) {
    rootRotation << std::cos(start.yaw()), std::sin(start.yaw());
  } else {
    rootRotation = start.rotationMatrix().transpose();
  }
  optimizer_internal::SparseCholesky solver;
  Eigen::MatrixXd x;
  if (!solveBlocks<D, KR>(n, r, rootRotation, rotationTerms, solver, false, &x, why)) return out;
  std::vector<Eigen::Matrix3d> rotations(n);
  std::vector<double> yaws(n);
  for (int k = 0; k < n; ++k) {
    if constexpr (is2D) {
      yaws[k] = k == r ? start.yaw() : std::atan2(x(2 * k + 1, 0), x(2 * k, 0));
      rotations[k] = Eigen::AngleAxisd(yaws[k], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    } else {
      rotations[k] = k == r ? start.rotationMatrix()
                            : projectToSO3(x.block<3, 3>(3 * k, 0).transpose());
    }
  }

  // ---- Positions.
  std::vector<Term<D, 1>> positionTerms;
  positionTerms.reserve(edges.size());
  for (const Edge& e : edges) {
    const Eigen::Matrix<double, D, D> ri = rotations[e.i].topLeftCorner<D, D>();
    const Eigen::Matrix<double, D, D> omega =
        identityInformation ? Eigen::Matrix<double, D, D>::Identity()
                            : Eigen::Matrix<double, D, D>(e.link->infMatrix().topLeftCorner<D, D>());
    Term<D, 1> t;
    t.i = e.i;
    t.j = e.j;
    t.m.setIdentity();
    t.w = ri * omega * ri.transpose();
    t.c = ri * e.link->transform().translation().head<D>();
    positionTerms.push_back(t);
  }
  const Eigen::Matrix<double, D, 1> rootPosition = start.translation().head<D>();
  if (!solveBlocks<D, 1>(n, r, rootPosition, positionTerms, solver, true, &x, why)) return out;

  for (int k = 0; k < n; ++k) {
    if constexpr (is2D) {
      out.emplace_hint(out.end(), ids[k], Transform(x(2 * k, 0), x(2 * k + 1, 0), yaws[k]));
    } else {
      Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
      iso.linear() = rotations[k];
      iso.translation() = x.block<3, 1>(3 * k, 0);
      out.emplace_hint(out.end(), ids[k], Transform(iso));
    }
  }
  return out;
}

}  // namespace

std::map<int, Transform> chordalInitialization(int root, const Transform& rootPose,
                                               const std::multimap<int, Link>& links, bool is2D,
                                               bool identityInformation, std::string* why) {
  const Transform start = rootPose.isNull() ? Transform::Identity()
                                            : (is2D ? rootPose.to3DoF() : rootPose);
  return is2D ? chordal<2, 1>(root, start, links, identityInformation, why)
              : chordal<3, 3>(root, start, links, identityInformation, why);
}

}  // namespace rtabmap::graph
