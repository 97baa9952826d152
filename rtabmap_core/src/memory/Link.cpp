#include "rtabmap_core/memory/Link.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rtabmap {

namespace {

// Skew-symmetric matrix [t]x such that [t]x * v = t x v.
Eigen::Matrix3d skew(const Eigen::Vector3d& t) {
  Eigen::Matrix3d s;
  s << 0.0, -t.z(), t.y(),
       t.z(), 0.0, -t.x(),
       -t.y(), t.x(), 0.0;
  return s;
}

// Adjoint of T = (R, t) acting on a twist ordered (translation, rotation), as our 6x6 matrices
// are (x y z roll pitch yaw): Ad(T) = [R  [t]x R; 0  R].
Eigen::Matrix<double, 6, 6> adjoint(const Transform& t) {
  const Eigen::Matrix3d r = t.rotationMatrix();
  Eigen::Matrix<double, 6, 6> ad = Eigen::Matrix<double, 6, 6>::Zero();
  ad.topLeftCorner<3, 3>() = r;
  ad.topRightCorner<3, 3>() = skew(t.translation()) * r;
  ad.bottomRightCorner<3, 3>() = r;
  return ad;
}

}  // namespace

Link::Link() = default;

Link::Link(int from, int to, Type type, const Transform& transform, const InfMatrix& information,
           const cv::Mat& userData)
    : from_(from), to_(to), type_(type), transform_(transform), information_(information),
      userData_(userData) {}

// The graph optimiser perturbs a measured transform on the right: T_noisy = T * Exp(xi), with
// xi ~ N(0, Sigma). Then T_noisy^-1 = Exp(-xi) * T^-1 = T^-1 * Exp(-Ad(T) xi), so the inverse
// link's noise is -Ad(T) xi with covariance Ad(T) Sigma Ad(T)^T, and its information
// Ad(T)^-T Omega Ad(T)^-1 = Ad(T^-1)^T Omega Ad(T^-1). Small rotations are treated as
// roll-pitch-yaw increments, the same first-order approximation the optimiser makes. For a
// pure translation with isotropic information this leaves the matrix unchanged, which is what
// the original (which copied the matrix) assumed in general.
Link Link::inverse() const {
  Link inv(to_, from_, type_, Transform(), information_, userData_);
  if (!transform_.isNull()) {
    inv.transform_ = transform_.inverse();
    const Eigen::Matrix<double, 6, 6> adInv = adjoint(inv.transform_);
    InfMatrix moved = adInv.transpose() * information_ * adInv;
    // Keep it exactly symmetric despite rounding, so isValid() keeps holding.
    inv.information_ = 0.5 * (moved + moved.transpose());
  }
  return inv;
}

// With right perturbations, A Exp(a) B Exp(b) = A B Exp(Ad(B^-1) a) Exp(b): A's noise reaches
// the composed frame through Ad(B^-1), so Sigma = Ad(B^-1) Sigma_A Ad(B^-1)^T + Sigma_B (first
// order, independent noises). Summing the covariances without the adjoint (the original's merge)
// forgets that A's rotation noise swings the end of B and that B turns A's axes.
Link Link::compose(const Link& next, Type type) const {
  if (to_ != next.from_) {
    throw std::invalid_argument("Link::compose: link " + std::to_string(from_) + "->" + std::to_string(to_) +
                                " is not followed by " + std::to_string(next.from_) + "->" + std::to_string(next.to_));
  }
  if (transform_.isNull() || next.transform_.isNull()) {
    throw std::invalid_argument("Link::compose: links " + std::to_string(from_) + "->" + std::to_string(to_) + "->" +
                                std::to_string(next.to_) + " need transforms");
  }
  const Eigen::Matrix<double, 6, 6> ad = adjoint(next.transform_.inverse());
  const Eigen::Matrix<double, 6, 6> covariance =
      ad * information_.inverse() * ad.transpose() + next.information_.inverse();
  InfMatrix information = covariance.inverse();
  information = 0.5 * (information + information.transpose());
  return Link(from_, next.to_, type, transform_ * next.transform_, information);
}

namespace {
constexpr char kScanIdsPrefix[] = "SCANS:";
}  // namespace

cv::Mat Link::scanIdsUserData(const std::vector<int>& ids) {
  std::string text = kScanIdsPrefix;
  for (size_t i = 0; i < ids.size(); ++i) text += (i ? ";" : "") + std::to_string(ids[i]);
  return cv::Mat(1, static_cast<int>(text.size()), CV_8UC1, text.data()).clone();
}

bool Link::hasScanIdsUserData() const {
  const size_t n = sizeof(kScanIdsPrefix) - 1;
  return userData_.type() == CV_8UC1 && userData_.rows == 1 && static_cast<size_t>(userData_.cols) >= n &&
         std::equal(kScanIdsPrefix, kScanIdsPrefix + n, userData_.ptr<char>(0));
}

bool Link::isValid(std::string* why) const {
  std::ostringstream reason;
  if (typeFromInt(type_) == kUndef) {
    reason << "link " << from_ << "->" << to_ << " has an undefined type (" << int(type_) << ")";
  } else if (transform_.isNull()) {
    reason << typeName() << " link " << from_ << "->" << to_ << " has a null transform";
  } else if (transform_.isInvalid()) {
    reason << typeName() << " link " << from_ << "->" << to_ << " has a non-finite transform";
  } else if (!information_.allFinite()) {
    reason << typeName() << " link " << from_ << "->" << to_
           << " has a non-finite information matrix";
  } else if ((information_ - information_.transpose()).cwiseAbs().maxCoeff() >
             1e-9 * std::max(1.0, information_.cwiseAbs().maxCoeff())) {
    reason << typeName() << " link " << from_ << "->" << to_
           << " has a non-symmetric information matrix";
  } else {
    Eigen::LLT<InfMatrix> llt(information_);
    if (llt.info() != Eigen::Success) {
      reason << typeName() << " link " << from_ << "->" << to_
             << " has an information matrix that is not positive definite";
    }
  }
  const std::string text = reason.str();
  if (why) *why = text;
  return text.empty();
}

double Link::transVariance(bool minimum) const {
  const double a = information_(0, 0), b = information_(1, 1), c = information_(2, 2);
  const double info = minimum ? std::max({a, b, c}) : std::min({a, b, c});
  return 1.0 / info;
}

double Link::rotVariance(bool minimum) const {
  const double a = information_(3, 3), b = information_(4, 4), c = information_(5, 5);
  const double info = minimum ? std::max({a, b, c}) : std::min({a, b, c});
  return 1.0 / info;
}

Link::Type Link::typeFromInt(int type) {
  return (type >= 0 && type < kTypeCount) ? static_cast<Type>(type) : kUndef;
}

std::string Link::typeName(int type) { return typeName(typeFromInt(type)); }

std::string Link::typeName(Type type) {
  switch (type) {
    case kNeighbor: return "Neighbor";
    case kGlobalClosure: return "GlobalClosure";
    case kLocalSpaceClosure: return "LocalSpaceClosure";
    case kLocalTimeClosure: return "LocalTimeClosure";
    case kUserClosure: return "UserClosure";
    case kVirtualClosure: return "VirtualClosure";
    case kNeighborMerged: return "NeighborMerged";
    case kPosePrior: return "PosePrior";
    case kLandmark: return "Landmark";
    case kGravity: return "Gravity";
    case kTemporary: return "Temporary";
    case kUndef: break;
  }
  return "Undefined";
}

}  // namespace rtabmap
