#include "rtabmap_core/optimizer/Chi2.h"

#include "PoseMath.h"

namespace rtabmap::graph {

namespace oi = optimizer_internal;

namespace {

constexpr int kSe2Axes[3] = {0, 1, 5};

bool isRelative(const Link& link) {
  return link.from() != link.to() && link.type() != Link::kPosePrior &&
         link.type() != Link::kGravity;
}

}  // namespace

Eigen::Matrix3d informationSE2(const Link::InfMatrix& information) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = information(kSe2Axes[r], kSe2Axes[c]);
  }
  return out;
}

Link::InfMatrix linkInformationFromSE2(const Eigen::Matrix3d& information, double unusedDiagonal) {
  Link::InfMatrix out = Link::InfMatrix::Zero();
  out(2, 2) = out(3, 3) = out(4, 4) = unusedDiagonal;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(kSe2Axes[r], kSe2Axes[c]) = information(r, c);
  }
  return out;
}

Matrix6 informationSE3ToG2o(const Link::InfMatrix& information) {
  // The rotation error in radians is about twice the quaternion vector: e_link = D e_g2o with
  // D = diag(1, 1, 1, 2, 2, 2), so e_link' Omega_link e_link = e_g2o' (D Omega_link D) e_g2o.
  Eigen::Matrix<double, 6, 1> d;
  d << 1.0, 1.0, 1.0, 2.0, 2.0, 2.0;
  return d.asDiagonal() * information * d.asDiagonal();
}

Link::InfMatrix informationSE3FromG2o(const Matrix6& information) {
  Eigen::Matrix<double, 6, 1> d;
  d << 1.0, 1.0, 1.0, 0.5, 0.5, 0.5;
  return d.asDiagonal() * information * d.asDiagonal();
}

Eigen::Vector3d errorSE2(const Transform& from, const Transform& to, const Transform& z) {
  const Eigen::Vector3d xi = oi::toSE2(from), xj = oi::toSE2(to);
  return oi::errorSE2(xi.data(), xj.data(), oi::toSE2(z));
}

Vector6 errorSE3(const Transform& from, const Transform& to, const Transform& z) {
  return oi::errorSE3(from.translation(), from.quaternion().normalized(), to.translation(),
                      to.quaternion().normalized(), z.translation(), z.quaternion().normalized());
}

double linkChi2(const Link& link, const Transform& from, const Transform& to, bool is2D,
                bool identityInformation) {
  const bool prior = !isRelative(link);
  const Transform& xi = prior ? Transform::Identity() : from;
  const Transform& xj = prior ? from : to;
  if (is2D) {
    const Eigen::Vector3d e = errorSE2(xi, xj, link.transform());
    if (identityInformation) return e.squaredNorm();
    return e.dot(informationSE2(link.infMatrix()) * e);
  }
  const Vector6 e = errorSE3(xi, xj, link.transform());
  if (identityInformation) return e.squaredNorm();
  return e.dot(informationSE3ToG2o(link.infMatrix()) * e);
}

double computeChi2(const std::map<int, Transform>& poses, const std::multimap<int, Link>& links,
                   bool is2D, bool identityInformation) {
  double chi2 = 0.0;
  for (const auto& [key, link] : links) {
    (void)key;
    if (link.type() == Link::kGravity) continue;
    const auto from = poses.find(link.from());
    const auto to = poses.find(link.to());
    if (from == poses.end() || to == poses.end() || from->second.isNull() ||
        to->second.isNull()) {
      continue;
    }
    chi2 += linkChi2(link, from->second, to->second, is2D, identityInformation);
  }
  return chi2;
}

}  // namespace rtabmap::graph
