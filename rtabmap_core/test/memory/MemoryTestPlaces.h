#pragma once
// Synthetic "images" for memory-management tests: a place is a fixed set of random float
// descriptors; a view of it is those descriptors with a little noise (so they quantise to the
// place's words), a different place shares nothing.
#include <opencv2/core.hpp>

#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory::test {

inline cv::Mat placeDescriptors(int place, int words = 100) {
  cv::Mat m(words, 64, CV_32F);
  cv::RNG rng(static_cast<uint64_t>(1000 + place));
  rng.fill(m, cv::RNG::UNIFORM, 0.f, 1.f);
  return m;
}

// Descriptors every environment repeats (door frames, floor texture): a view shows a few of
// them, chosen at random, so most locations share some words as in real images.
inline cv::Mat commonDescriptors() { return placeDescriptors(-1, 40); }

inline LocationInput view(int place, int visit = 0, int words = 100, int common = 0) {
  LocationInput in;
  cv::Mat noise(words, 64, CV_32F);
  cv::RNG rng(static_cast<uint64_t>(77 * place + 13 * visit + 1));
  rng.fill(noise, cv::RNG::UNIFORM, -0.005f, 0.005f);
  in.descriptors = placeDescriptors(place, words) + noise;
  const cv::Mat pool = commonDescriptors();
  for (int i = 0; i < common && i < words; ++i) pool.row(rng.uniform(0, pool.rows)).copyTo(in.descriptors.row(i));
  for (int i = 0; i < words; ++i) in.keypoints.emplace_back(static_cast<float>(i), 0.f, 3.f, -1.f, 1.f);
  return in;
}

// A view taken from an odometry pose (metric SLAM).
inline LocationInput viewAt(int place, int visit, const Transform& pose) {
  LocationInput in = view(place, visit);
  in.pose = pose;
  return in;
}

// A Long-Term Memory: a database in a folder removed with it.
struct WithLtm {
  rtabmap::test::TempDir dir;
  db::Database database{dir.file("ltm.db")};
};

}  // namespace rtabmap::memory::test
