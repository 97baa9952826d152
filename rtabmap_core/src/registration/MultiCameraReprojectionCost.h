#pragma once
// Residual of the multi-camera PnP refinement (internal header, tested in
// test/registration/MultiCameraReprojection_test.cpp).
//
// Parameters: the reference frame in the new base frame (quaternion in Eigen's x y z w order,
// on ceres::EigenQuaternionManifold, and translation), i.e. the inverse of the motion.
// Residual (pixels): K_c * (opticalFromBase_c * (q * X + t)) - uv, camera c of the observation.
#include <ceres/autodiff_cost_function.h>

#include "MultiCameraReprojection.h"

namespace rtabmap::registration_internal {

class MultiCameraReprojectionCost {
 public:
  MultiCameraReprojectionCost(const CameraObservation& o, const PinholeCamera& c) : o_(o), c_(c) {}

  template <typename T>
  bool operator()(const T* q, const T* t, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> baseFromReference(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> translation(t);
    const Eigen::Matrix<T, 3, 1> inBase = baseFromReference * o_.point.cast<T>() + translation;
    const Eigen::Matrix<T, 3, 1> p =
        c_.opticalFromBase.linear().cast<T>() * inBase + c_.opticalFromBase.translation().cast<T>();
    // A step that pushes the point behind its camera gets a large, finite residual: the trust
    // region rejects the step instead of the solver dividing by zero.
    const T z = p.z() > T(1e-3) ? p.z() : T(1e-3);
    r[0] = T(c_.fx) * p.x() / z + T(c_.cx) - T(o_.pixel.x());
    r[1] = T(c_.fy) * p.y() / z + T(c_.cy) - T(o_.pixel.y());
    return true;
  }

  static ceres::CostFunction* create(const CameraObservation& o, const PinholeCamera& c) {
    return new ceres::AutoDiffCostFunction<MultiCameraReprojectionCost, 2, 4, 3>(new MultiCameraReprojectionCost(o, c));
  }

 private:
  CameraObservation o_;
  PinholeCamera c_;
};

}  // namespace rtabmap::registration_internal
