// bench-loop_closure_bench: does an update of appearance-based loop-closure detection stay
// fast as Working Memory grows (T-RO 2013; goal: under 100 ms with 20,000 locations of 500
// words in WM, on one core)?
//
// Feeds LoopClosureDetector (default parameters: GFTT/ORB-like 32-byte binary descriptors,
// FLANN kd-trees over their bits, TF-IDF likelihood, Bayes filter over 16 neighbours) with
// synthetic locations of W words and no transfer (WM keeps every location), then prints at
// each checkpoint the median over the next 50 updates of:
//   memory update (location creation, of which quantisation and index insertion), likelihood,
//   posterior, whole update.
// Vocabulary growth as in bench-db_bench: location n brings max(25, W / (1 + n / 50)) new
// descriptors, the others repeat existing words. Human-readable lines, then one JSON line.
//
// Usage: bench-loop_closure_bench [--locations N] [--words W] [--checks C (FLANN search checks)]
#include <opencv2/core.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "rtabmap_core/memory/LoopClosureDetector.h"

namespace {

using rtabmap::memory::LocationInput;

struct Figures {
  int wm = 0;
  size_t vocabulary = 0;
  double vocabularyMs = 0, quantizeMs = 0, likelihoodMs = 0, posteriorMs = 0, totalMs = 0;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

class SyntheticWorld {
 public:
  explicit SyntheticWorld(int words) : words_(words), rng_(42) {}

  LocationInput next(int n) {
    const int fresh = std::max(25, words_ / (1 + n / 50));
    LocationInput in;
    in.descriptors = cv::Mat(words_, 32, CV_8U);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int i = 0; i < words_; ++i) {
      uchar* row = in.descriptors.ptr<uchar>(i);
      if (i < fresh || seen_.empty()) {
        for (int b = 0; b < 32; ++b) row[b] = static_cast<uchar>(byte(rng_));
        seen_.push_back(in.descriptors.row(i).clone());
      } else {
        std::uniform_int_distribution<size_t> pick(0, seen_.size() - 1);
        seen_[pick(rng_)].copyTo(in.descriptors.row(i));
      }
      in.keypoints.emplace_back(static_cast<float>(i % 640), static_cast<float>(i / 640), 7.f, -1.f, 1.f);
    }
    return in;
  }

 private:
  int words_;
  std::mt19937 rng_;
  std::vector<cv::Mat> seen_;
};

}  // namespace

int main(int argc, char** argv) {
  int locations = 20000, words = 500, checks = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--locations")) locations = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--words")) words = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--checks")) checks = std::atoi(argv[i + 1]);
  }
  std::vector<int> checkpoints;
  for (int c : {1000, 2000, 5000, 10000, 20000}) {
    if (c <= locations) checkpoints.push_back(c);
  }
  if (checkpoints.empty() || checkpoints.back() != locations) checkpoints.push_back(locations);

  rtabmap::ParametersMap parameters{{"Kp/MaxFeatures", std::to_string(words)}};
  auto options = rtabmap::memory::LoopClosureDetectorOptions::fromParameters(parameters);
  if (checks > 0) options.memory.vocabulary.searchChecks = checks;
  rtabmap::memory::LoopClosureDetector detector(options, nullptr);
  SyntheticWorld world(words);
  std::vector<Figures> results;
  const int window = 50;
  int n = 0;
  for (int checkpoint : checkpoints) {
    while (static_cast<int>(detector.memory().wm().size()) < checkpoint) detector.process(world.next(++n));
    std::vector<double> vocabularyMs, quantizeMs, likelihoodMs, posteriorMs, totalMs;
    for (int k = 0; k < window; ++k) {
      const auto u = detector.process(world.next(++n));
      vocabularyMs.push_back(u.memoryUpdateMs);
      quantizeMs.push_back(detector.memory().vocabulary().summary().lastQuantizeMs);
      likelihoodMs.push_back(u.likelihoodMs);
      posteriorMs.push_back(u.posteriorMs);
      totalMs.push_back(u.totalMs);
    }
    Figures f;
    f.wm = static_cast<int>(detector.memory().wm().size());
    f.vocabulary = detector.memory().vocabulary().size();
    f.vocabularyMs = median(vocabularyMs);
    f.quantizeMs = median(quantizeMs);
    f.likelihoodMs = median(likelihoodMs);
    f.posteriorMs = median(posteriorMs);
    f.totalMs = median(totalMs);
    results.push_back(f);
    std::cout << "WM " << f.wm << " locations, vocabulary " << f.vocabulary << " words: median update "
              << f.totalMs << " ms (memory update " << f.vocabularyMs << " ms of which quantisation " << f.quantizeMs
              << " ms, likelihood " << f.likelihoodMs
              << " ms, posterior " << f.posteriorMs << " ms) over " << window << " updates" << std::endl;
  }
  const Figures& last = results.back();
  std::cout << "goal: update under 100 ms at 20000 locations x 500 words: "
            << (last.wm >= 20000 && words == 500 ? (last.totalMs < 100.0 ? "met" : "NOT met") : "not measured")
            << std::endl;
  std::cout << "{\"bench\":\"loop_closure\",\"words_per_location\":" << words
            << ",\"search_checks\":" << options.memory.vocabulary.searchChecks << ",\"points\":[";
  for (size_t i = 0; i < results.size(); ++i) {
    const Figures& f = results[i];
    std::cout << (i ? "," : "") << "{\"wm\":" << f.wm << ",\"vocabulary\":" << f.vocabulary
              << ",\"update_ms\":" << f.totalMs << ",\"memory_update_ms\":" << f.vocabularyMs << ",\"quantize_ms\":" << f.quantizeMs
              << ",\"likelihood_ms\":" << f.likelihoodMs << ",\"posterior_ms\":" << f.posteriorMs << "}";
  }
  std::cout << "]}" << std::endl;
  return 0;
}
