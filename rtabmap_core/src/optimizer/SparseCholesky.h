#pragma once
// Sparse Cholesky factorisation of a symmetric positive-definite matrix with SuiteSparse
// CHOLMOD (linked through Ceres), for the linear systems of the chordal initialisation
// (internal header; CHOLMOD stays out of public headers).
//
// CHOLMOD picks a supernodal factorisation (dense blocks through BLAS) when the factor fills in,
// as on sphere2500, where it is faster than Eigen's simplicial one, and a simplicial one
// otherwise. One symbolic analysis serves several numeric factorisations of matrices with the
// same pattern.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <string>
#include <vector>

namespace rtabmap::optimizer_internal {

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // The matrix is compressed and symmetric; only its lower triangle is read. analyze() computes
  // the symbolic factor, with the given fill-reducing ordering (ordering[k] = the original index
  // eliminated k-th) or CHOLMOD's own (AMD) if null; factorize() the numeric one (after analyze()
  // on a matrix of the same pattern). Both return false with the reason in *why.
  bool analyze(const Eigen::SparseMatrix<double>& matrix, const std::vector<int>* ordering,
               std::string* why);
  bool factorize(const Eigen::SparseMatrix<double>& matrix, std::string* why);
  // Solves A x = b for every column of b.
  bool solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x, std::string* why);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rtabmap::optimizer_internal
