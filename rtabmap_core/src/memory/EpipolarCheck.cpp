#include "rtabmap_core/memory/EpipolarCheck.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>
#include <vector>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/memory/Signature.h"

namespace rtabmap::memory {

EpipolarCheckOptions EpipolarCheckOptions::fromParameters(const ParametersMap& p) {
  EpipolarCheckOptions o;
  o.enabled = Parameters::getBool(p, Parameters::kVhEpEnabled());
  o.matchCountMin = Parameters::getInt(p, Parameters::kVhEpMatchCountMin());
  o.inlierRatioMin = Parameters::getFloat(p, Parameters::kVhEpInlierRatioMin());
  o.ransacParam1 = Parameters::getFloat(p, Parameters::kVhEpRansacParam1());
  o.ransacParam2 = Parameters::getFloat(p, Parameters::kVhEpRansacParam2());
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool EpipolarCheckOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  // The 8-point solver inside OpenCV's RANSAC needs 8 pairs.
  if (matchCountMin < 8) return fail(Parameters::kVhEpMatchCountMin() + " must be >= 8");
  if (!(inlierRatioMin >= 0.f && inlierRatioMin <= 1.f)) return fail(Parameters::kVhEpInlierRatioMin() + " must be in [0, 1]");
  if (!(ransacParam1 > 0.f)) return fail(Parameters::kVhEpRansacParam1() + " must be > 0 pixels");
  if (!(ransacParam2 > 0.f && ransacParam2 < 1.f)) return fail(Parameters::kVhEpRansacParam2() + " must be in (0, 1)");
  return true;
}

std::string EpipolarCheckSummary::Summary() const {
  std::ostringstream s;
  s << "epipolar check: " << inliers << " of " << pairs << " unique-word pairs agree" << (accepted ? "" : ": " + why);
  return s.str();
}

namespace {

// Keypoints of the words that occur exactly once in `words`, by word id (sorted).
std::vector<std::pair<int, cv::Point2f>> uniqueWordPoints(const Signature& s) {
  std::vector<std::pair<int, cv::Point2f>> out;
  const auto& words = s.getWords();
  const auto& kpts = s.getWordsKpts();
  for (auto it = words.begin(); it != words.end();) {
    auto next = words.upper_bound(it->first);
    if (std::next(it) == next && it->second >= 0 && it->second < static_cast<int>(kpts.size())) {
      out.emplace_back(it->first, kpts[static_cast<size_t>(it->second)].pt);
    }
    it = next;
  }
  return out;
}

}  // namespace

EpipolarCheckSummary checkEpipolarGeometry(const Signature& query, const Signature& candidate,
                                           const EpipolarCheckOptions& options) {
  EpipolarCheckSummary r;
  const auto a = uniqueWordPoints(query);
  const auto b = uniqueWordPoints(candidate);
  std::vector<cv::Point2f> pa, pb;
  // Both lists are sorted by word id: a merge pairs them.
  for (size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    if (a[i].first < b[j].first) {
      ++i;
    } else if (b[j].first < a[i].first) {
      ++j;
    } else {
      pa.push_back(a[i++].second);
      pb.push_back(b[j++].second);
    }
  }
  r.pairs = static_cast<int>(pa.size());
  if (r.pairs < options.matchCountMin) {
    r.why = "too few unique-word pairs (" + std::to_string(r.pairs) + " < " +
            std::to_string(options.matchCountMin) + ")";
    return r;
  }
  std::vector<unsigned char> mask;
  const cv::Mat f = cv::findFundamentalMat(pa, pb, cv::FM_RANSAC, options.ransacParam1, options.ransacParam2, mask);
  if (f.empty()) {
    r.why = "no fundamental matrix fits the pairs";
    return r;
  }
  r.inliers = cv::countNonZero(mask);
  const int needed =
      std::max(options.matchCountMin, static_cast<int>(std::ceil(options.inlierRatioMin * static_cast<float>(r.pairs))));
  r.accepted = r.inliers >= needed;
  if (!r.accepted) {
    r.why = "too few pairs agree (" + std::to_string(r.inliers) + " < " + std::to_string(needed) + ")";
  }
  return r;
}

}  // namespace rtabmap::memory
