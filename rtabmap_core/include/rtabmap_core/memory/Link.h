#pragma once
// A constraint of the pose graph between two nodes (T-RO 2013 "links", JFR 2019 section 3):
// the rigid transform from node `from` to node `to` expressed in `from`'s frame, with the 6x6
// information matrix (inverse covariance, order x y z roll pitch yaw) that the graph
// optimiser weighs it by.
//
// The type numbers are those of rtabmap_msgs/Link.msg and of the database; never renumber.
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap {

class Link {
 public:
  enum Type {
    kNeighbor = 0,           // odometry between consecutive nodes
    kGlobalClosure = 1,      // appearance-based loop closure (Bayes filter)
    kLocalSpaceClosure = 2,  // proximity detection in space
    kLocalTimeClosure = 3,   // proximity detection in time
    kUserClosure = 4,        // added by the user (service)
    kVirtualClosure = 5,     // added by path planning, no measurement
    kNeighborMerged = 6,     // neighbor link created when rehearsal merges two nodes
    kPosePrior = 7,          // absolute pose (GPS, ground truth): from == to
    kLandmark = 8,           // to a landmark (negative id)
    kGravity = 9,            // gravity direction from IMU: from == to
    kTemporary = 10,         // localization mode only, never saved
    kUndef = -1,
  };
  // Number of defined types (kNeighbor .. kTemporary), for per-type tables.
  static constexpr int kTypeCount = 11;

  using InfMatrix = Eigen::Matrix<double, 6, 6>;

  // Undefined link (type kUndef, null transform, identity information).
  Link();
  Link(int from, int to, Type type, const Transform& transform,
       const InfMatrix& information = InfMatrix::Identity(), const cv::Mat& userData = cv::Mat());

  int from() const { return from_; }
  int to() const { return to_; }
  Type type() const { return type_; }
  const Transform& transform() const { return transform_; }
  const InfMatrix& infMatrix() const { return information_; }
  // Opaque data attached by the user (e.g. a path-planning cost); stored compressed.
  const cv::Mat& userData() const { return userData_; }

  void setFrom(int from) { from_ = from; }
  void setTo(int to) { to_ = to; }
  void setType(Type type) { type_ = type; }
  void setTransform(const Transform& t) { transform_ = t; }
  void setInfMatrix(const InfMatrix& information) { information_ = information; }
  void setUserData(const cv::Mat& data) { userData_ = data; }

  // The same constraint seen from `to`: swapped ids, inverted transform, and the information
  // matrix moved to the other frame (see Link.cpp for the derivation).
  Link inverse() const;
  // This link followed by `next` (this->to() == next.from()): from() -> next.to(), transforms
  // composed, their noise added in the frame of the result (see Link.cpp), of type `type`.
  // Throws std::invalid_argument if the links do not meet or a transform is null.
  Link compose(const Link& next, Type type) const;

  // RGBD/ScanMatchingIdsSavedInLinks: a proximity link made by one-to-many scan matching keeps,
  // as its user data, the ids of the nodes whose scans were merged: "SCANS:id;id;..." (the
  // original's text). A record, not data a user attached.
  static cv::Mat scanIdsUserData(const std::vector<int>& ids);
  bool hasScanIdsUserData() const;

  // True if type is defined, the transform is non-null and finite, and the information matrix
  // is finite, symmetric and positive definite. Otherwise explains why in *why (if given).
  bool isValid(std::string* why = nullptr) const;

  // Variances from the information matrix diagonal (1 / information). With minimum = true the
  // smallest variance of the three axes (the best-constrained one), otherwise the largest (the
  // worst, what a conservative check wants).
  double transVariance(bool minimum = true) const;
  double rotVariance(bool minimum = true) const;

  // Original names: "Neighbor", "GlobalClosure", "LocalSpaceClosure", ...; "Undefined" for an
  // unknown number.
  static std::string typeName(Type type);
  static std::string typeName(int type);
  std::string typeName() const { return typeName(type_); }
  // kUndef for a number outside the defined types.
  static Type typeFromInt(int type);

 private:
  int from_ = 0;
  int to_ = 0;
  Type type_ = kUndef;
  Transform transform_;
  InfMatrix information_ = InfMatrix::Identity();
  cv::Mat userData_;
};

}  // namespace rtabmap
