#include "SparseCholesky.h"

#include <suitesparse/cholmod.h>

namespace rtabmap::optimizer_internal {

struct SparseCholesky::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;

  Impl() {
    cholmod_start(&common);
    common.print = 0;  // errors are reported through the return values, not stderr
  }
  ~Impl() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }

  // A CHOLMOD view (no copy) of a compressed Eigen matrix, lower triangle used.
  static cholmod_sparse view(const Eigen::SparseMatrix<double>& m) {
    cholmod_sparse a{};
    a.nrow = static_cast<std::size_t>(m.rows());
    a.ncol = static_cast<std::size_t>(m.cols());
    a.nzmax = static_cast<std::size_t>(m.nonZeros());
    a.p = const_cast<int*>(m.outerIndexPtr());
    a.i = const_cast<int*>(m.innerIndexPtr());
    a.x = const_cast<double*>(m.valuePtr());
    a.stype = -1;
    a.itype = CHOLMOD_INT;
    a.xtype = CHOLMOD_REAL;
    a.dtype = CHOLMOD_DOUBLE;
    a.sorted = 1;
    a.packed = 1;
    return a;
  }
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::analyze(const Eigen::SparseMatrix<double>& matrix,
                             const std::vector<int>* ordering, std::string* why) {
  if (!matrix.isCompressed() || (ordering && static_cast<Eigen::Index>(ordering->size()) != matrix.rows())) {
    if (why) *why = "sparse Cholesky: the matrix must be compressed and the ordering cover it";
    return false;
  }
  if (impl_->factor) cholmod_free_factor(&impl_->factor, &impl_->common);
  cholmod_sparse a = Impl::view(matrix);
  if (ordering) {
    // Only the ordering given (CHOLMOD would otherwise also try its own).
    impl_->common.nmethods = 1;
    impl_->common.method[0].ordering = CHOLMOD_GIVEN;
    impl_->common.postorder = 1;
    impl_->factor = cholmod_analyze_p(&a, const_cast<int*>(ordering->data()), nullptr, 0,
                                      &impl_->common);
  } else {
    impl_->common.nmethods = 0;
    impl_->factor = cholmod_analyze(&a, &impl_->common);
  }
  if (!impl_->factor || impl_->common.status < CHOLMOD_OK) {
    if (why) *why = "sparse Cholesky: the symbolic analysis failed (out of memory?)";
    return false;
  }
  return true;
}

bool SparseCholesky::factorize(const Eigen::SparseMatrix<double>& matrix, std::string* why) {
  if (!impl_->factor || !matrix.isCompressed()) {
    if (why) *why = "sparse Cholesky: factorize() needs analyze() and a compressed matrix";
    return false;
  }
  cholmod_sparse a = Impl::view(matrix);
  const int ok = cholmod_factorize(&a, impl_->factor, &impl_->common);
  if (!ok || impl_->common.status != CHOLMOD_OK || impl_->factor->minor < impl_->factor->n) {
    if (why) *why = "the linear system is not positive definite (disconnected graph?)";
    return false;
  }
  return true;
}

bool SparseCholesky::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x, std::string* why) {
  if (!impl_->factor) {
    if (why) *why = "sparse Cholesky: solve() before factorize()";
    return false;
  }
  cholmod_dense rhs{};
  rhs.nrow = static_cast<std::size_t>(b.rows());
  rhs.ncol = static_cast<std::size_t>(b.cols());
  rhs.nzmax = rhs.nrow * rhs.ncol;
  rhs.d = rhs.nrow;
  rhs.x = const_cast<double*>(b.data());
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* solution = cholmod_solve(CHOLMOD_A, impl_->factor, &rhs, &impl_->common);
  if (!solution) {
    if (why) *why = "sparse Cholesky: the solve failed";
    return false;
  }
  *x = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(solution->x), b.rows(), b.cols());
  cholmod_free_dense(&solution, &impl_->common);
  return x->allFinite();
}

}  // namespace rtabmap::optimizer_internal
