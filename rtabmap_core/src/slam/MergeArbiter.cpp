#include "MergeArbiter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rtabmap {

bool MergeArbiterOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (minDissent < 1) return fail("MergeArbiterOptions::minDissent must be >= 1");
  if (!(agreementMetres > 0.0) || !std::isfinite(agreementMetres)) return fail("MergeArbiterOptions::agreementMetres must be > 0");
  if (!(agreementRadians > 0.0) || !std::isfinite(agreementRadians)) {
    return fail("MergeArbiterOptions::agreementRadians must be > 0");
  }
  if (windowNodes < 1) return fail("MergeArbiterOptions::windowNodes must be >= 1");
  return true;
}

MergeArbiter::MergeArbiter(const MergeArbiterOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument(why);
}

void MergeArbiter::dissent(const Link& link, const Transform& graphPose, const Transform& impliedPose) {
  if (graphPose.isNull() || impliedPose.isNull()) return;
  Transform correction = impliedPose * graphPose.inverse();
  if (options_.planar) correction = correction.to3DoF();
  dissent_.push_back({link, graphPose, impliedPose, correction});
}

// Where b's correction puts a's node, against where a's closure put it.
bool MergeArbiter::agree(const Evidence& a, const Evidence& b) const {
  const Transform there = b.correction * a.graphPose;
  const Transform error = there.inverse() * a.impliedPose;
  return error.getNorm() <= options_.agreementMetres && std::fabs(error.getAngle()) <= options_.agreementRadians;
}

std::optional<Remerge> MergeArbiter::decide(int newestId) {
  dissent_.erase(std::remove_if(dissent_.begin(), dissent_.end(),
                                [&](const Evidence& e) { return e.link.from() < newestId - options_.windowNodes; }),
                 dissent_.end());
  if (settled_) return std::nullopt;
  // Each closure in turn proposes its correction; the one most others agree with wins (the
  // newest on a tie: its correction is measured against the freshest graph).
  size_t best = dissent_.size(), bestVotes = 0;
  for (size_t i = 0; i < dissent_.size(); ++i) {
    size_t votes = 0;
    for (const Evidence& e : dissent_) votes += agree(e, dissent_[i]) ? 1 : 0;
    if (votes >= bestVotes) {
      bestVotes = votes;
      best = i;
    }
  }
  if (best == dissent_.size() || bestVotes < static_cast<size_t>(options_.minDissent) ||
      bestVotes <= static_cast<size_t>(support_)) {
    return std::nullopt;
  }
  Remerge r;
  r.correction = dissent_[best].correction;
  for (const Evidence& e : dissent_) {
    if (agree(e, dissent_[best])) r.links.push_back(e.link);
  }
  return r;
}

void MergeArbiter::reset(int support) {
  support_ = support;
  settled_ = false;
  dissent_.clear();
}

}  // namespace rtabmap
