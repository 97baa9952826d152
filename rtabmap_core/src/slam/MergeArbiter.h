#pragma once
// Arbitration of a merge between maps (multi-session, IROS 2014). The first link between the
// current map and an earlier one puts the current map in the earlier one's referential; from
// then on RGBD/MaxLoopClosureDistance refuses every closure that would move the robot far from
// where the graph has it. When that first link was wrong (aliasing: materials that repeat,
// blocks of identical rooms), the session stays metres off and every true closure that follows
// is refused for its jump.
//
// So a merge is a vote. Support: the global loop closures accepted between the current map and
// the others. Dissent: closures to another map refused for their jump, or by the graph
// (RGBD/OptimizeMaxError, when there is no jump limit), kept as evidence with the pose they
// imply for the robot. When enough recent dissenting closures agree with each other
// on where the current map is, and they outnumber the support, the caller undoes the merge and
// merges again through them. Proximity links do not vote: they are searched near where the
// graph already puts the robot, so they follow the merge instead of testing it.
#include <optional>
#include <string>
#include <vector>

#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"

namespace rtabmap {

struct MergeArbiterOptions {
  int minDissent = 3;                // agreeing refused closures needed, whatever the support
  double agreementMetres = 1.0;      // two closures agree when they put the robot this close...
  double agreementRadians = 0.26;    // ...and this close in heading (15 degrees)
  int windowNodes = 50;              // dissent from nodes older than this (ids) is forgotten
  bool planar = false;               // Reg/Force3DoF: corrections keep x, y and yaw only

  bool IsValid(std::string* why = nullptr) const;
};

// A merge to redo: the agreeing closures, and the correction to apply on the left of every pose
// of the current map so that the newest of them holds.
struct Remerge {
  std::vector<Link> links;
  Transform correction;
};

class MergeArbiter {
 public:
  explicit MergeArbiter(const MergeArbiterOptions& options = {});

  // A global loop closure accepted between the current map and another one.
  void support() { ++support_; }
  // The user linked the maps (Link::kUserClosure): the merge is not put to the vote.
  void settle() { settled_ = true; }
  // A closure from the current map's node link.from() to another map, refused for its jump or
  // by the graph: the graph had the node at `graphPose`, the closure puts it at `impliedPose`.
  void dissent(const Link& link, const Transform& graphPose, const Transform& impliedPose);
  // After forgetting dissent older than windowNodes before `newestId`: the largest group of
  // agreeing dissent when it has at least minDissent closures and more than the support.
  std::optional<Remerge> decide(int newestId);
  // A new map, or a merge redone with `support` as its first votes (settled no more).
  void reset(int support = 0);

  int supportCount() const { return support_; }
  size_t dissentCount() const { return dissent_.size(); }

 private:
  struct Evidence {
    Link link;
    Transform graphPose;
    Transform impliedPose;
    Transform correction;  // impliedPose * graphPose^-1
  };
  bool agree(const Evidence& a, const Evidence& b) const;

  MergeArbiterOptions options_;
  int support_ = 0;
  bool settled_ = false;
  std::vector<Evidence> dissent_;
};

}  // namespace rtabmap
