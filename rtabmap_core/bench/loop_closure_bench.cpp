// bench-loop_closure_bench: does an update of appearance-based loop-closure detection stay
// fast as Working Memory grows (T-RO 2013; goal: under 100 ms with 20,000 locations of 500
// words in WM, on one core)?
//
// Runs the stages of LoopClosureDetector::process() on synthetic locations of W words (default
// parameters: 32-byte binary descriptors, FLANN kd-trees over their bits, TF-IDF likelihood,
// Bayes filter over 16 neighbours) with no transfer (WM keeps every location), and prints at
// each checkpoint the median over the next 50 updates of:
//   memory update (location creation: quantisation, index insertion, STM/WM), likelihood
//   (inverted index + eq. 3-4), posterior (prediction + Bayes update + selection), whole update.
// Times are the CPU time of this thread (CLOCK_THREAD_CPUTIME_ID): on a shared machine the wall
// clock measures the other processes (the wall-clock median of the whole update is printed
// too, with the CPU share). Vocabulary growth as in bench-db_bench: location n brings
// max(25, W / (1 + n / 50)) new descriptors, the others repeat existing words. Index rebuilds
// (the vocabulary doubled) are counted and their longest update printed: they are the spikes the
// median hides. Human-readable lines, then one JSON line.
//
// Usage: bench-loop_closure_bench [--locations N] [--words W] [--checks C (FLANN search checks)]
#include <opencv2/core.hpp>

#include <time.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "rtabmap_core/bayes/BayesFilter.h"
#include "rtabmap_core/bayes/Likelihood.h"
#include "rtabmap_core/memory/LoopClosureDetector.h"

namespace {

using rtabmap::memory::LocationInput;

struct Figures {
  int wm = 0;
  size_t vocabulary = 0;
  double vocabularyMs = 0, quantizeMs = 0, likelihoodMs = 0, posteriorMs = 0, totalMs = 0, wallMs = 0;
};

double cpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double wallMs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

// One update: the stages of LoopClosureDetector::process() without retrieval and transfer
// (no LTM), each timed on the thread's CPU clock.
struct Update {
  double memoryMs = 0, likelihoodMs = 0, posteriorMs = 0, totalMs = 0, wallMs = 0;
};

class Pipeline {
 public:
  explicit Pipeline(const rtabmap::memory::LoopClosureDetectorOptions& options)
      : options_(options), memory_(options.memory, nullptr), filter_(options.bayes) {}

  Update process(const LocationInput& in) {
    Update u;
    const double wall0 = wallMs(), t0 = cpuMs();
    const int id = memory_.addLocation(in).id;
    const double t1 = cpuMs();
    double t2 = t1, t3 = t1;
    const auto* s = memory_.signature(id);
    if (s && !s->isBadSignature() && !memory_.wm().empty()) {
      const auto likelihood = rtabmap::bayes::adjustLikelihoodScores(memory_.likelihoodScores(id));
      t2 = cpuMs();
      const auto neighbors = [this](int node, int depth) { return memory_.neighbors(node, depth); };
      const auto& posterior = filter_.updateScores(likelihood, neighbors);
      const auto h = rtabmap::bayes::selectHypothesisScores(posterior, options_.hypothesis, previous_);
      previous_ = h.value;
      if (h.accepted) {  // as LoopClosureDetector::acceptLoopClosure
        memory_.addLoopClosure(rtabmap::Link(id, h.id, rtabmap::Link::kGlobalClosure, rtabmap::Transform::Identity()));
        filter_.invalidateNeighborhood({id, h.id}, neighbors);
        ++loopClosures_;
      }
      t3 = cpuMs();
    }
    u.memoryMs = t1 - t0;
    u.likelihoodMs = t2 - t1;
    u.posteriorMs = t3 - t2;
    u.totalMs = t3 - t0;
    u.wallMs = wallMs() - wall0;
    return u;
  }

  const rtabmap::memory::Memory& memory() const { return memory_; }
  int loopClosures() const { return loopClosures_; }

 private:
  rtabmap::memory::LoopClosureDetectorOptions options_;
  rtabmap::memory::Memory memory_;
  rtabmap::bayes::BayesFilter filter_;
  float previous_ = 0.0f;
  int loopClosures_ = 0;
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
  Pipeline pipeline(options);
  SyntheticWorld world(words);
  std::vector<Figures> results;
  const int window = 50;
  int n = 0, builds = 0;
  double worstBuildMs = 0.0;
  // Counts index rebuilds and their cost while growing to a checkpoint.
  auto step = [&]() {
    const int before = pipeline.memory().vocabulary().summary().indexBuilds;
    const Update u = pipeline.process(world.next(++n));
    if (pipeline.memory().vocabulary().summary().indexBuilds != before) {
      ++builds;
      worstBuildMs = std::max(worstBuildMs, u.memoryMs);
    }
    return u;
  };
  for (int checkpoint : checkpoints) {
    while (static_cast<int>(pipeline.memory().wm().size()) < checkpoint) step();
    std::vector<double> vocabularyMs, quantizeMs, likelihoodMs, posteriorMs, totalMs, wall;
    for (int k = 0; k < window; ++k) {
      const Update u = step();
      vocabularyMs.push_back(u.memoryMs);
      quantizeMs.push_back(pipeline.memory().vocabulary().summary().lastQuantizeMs);
      likelihoodMs.push_back(u.likelihoodMs);
      posteriorMs.push_back(u.posteriorMs);
      totalMs.push_back(u.totalMs);
      wall.push_back(u.wallMs);
    }
    Figures f;
    f.wm = static_cast<int>(pipeline.memory().wm().size());
    f.vocabulary = pipeline.memory().vocabulary().size();
    f.vocabularyMs = median(vocabularyMs);
    f.quantizeMs = median(quantizeMs);
    f.likelihoodMs = median(likelihoodMs);
    f.posteriorMs = median(posteriorMs);
    f.totalMs = median(totalMs);
    f.wallMs = median(wall);
    results.push_back(f);
    std::cout << "WM " << f.wm << " locations, vocabulary " << f.vocabulary << " words: median update "
              << f.totalMs << " ms CPU (memory update " << f.vocabularyMs << " ms, likelihood " << f.likelihoodMs
              << " ms, posterior " << f.posteriorMs << " ms; wall clock: update " << f.wallMs
              << " ms, quantisation " << f.quantizeMs << " ms) over " << window << " updates; "
              << builds << " index rebuilds so far, longest " << worstBuildMs << " ms CPU" << std::endl;
  }
  const Figures& last = results.back();
  std::cout << "goal: update under 100 ms at 20000 locations x 500 words: "
            << (last.wm >= 20000 && words == 500 ? (last.totalMs < 100.0 ? "met" : "NOT met") : "not measured")
            << std::endl;
  std::cout << "{\"bench\":\"loop_closure\",\"words_per_location\":" << words
            << ",\"search_checks\":" << options.memory.vocabulary.searchChecks << ",\"clock\":\"thread_cpu\""
            << ",\"index_rebuilds\":" << builds << ",\"longest_rebuild_update_ms\":" << worstBuildMs
            << ",\"loop_closures\":" << pipeline.loopClosures() << ",\"points\":[";
  for (size_t i = 0; i < results.size(); ++i) {
    const Figures& f = results[i];
    std::cout << (i ? "," : "") << "{\"wm\":" << f.wm << ",\"vocabulary\":" << f.vocabulary
              << ",\"update_ms\":" << f.totalMs << ",\"memory_update_ms\":" << f.vocabularyMs << ",\"quantize_ms\":" << f.quantizeMs
              << ",\"likelihood_ms\":" << f.likelihoodMs << ",\"posterior_ms\":" << f.posteriorMs
              << ",\"update_wall_ms\":" << f.wallMs << "}";
  }
  std::cout << "]}" << std::endl;
  return 0;
}
