#pragma once
// The nearest-neighbour index behind the vocabulary (private to the vocabulary area: FLANN's
// headers stay out of the public ones).
#include <opencv2/core/mat.hpp>

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "rtabmap_core/vocabulary/Vocabulary.h"

namespace rtabmap::vocabulary {

// Up to two nearest words of one query: (word id, distance); word id 0 when absent. Distances
// are the descriptors' own: Euclidean (not squared) for float ones, Hamming bit counts for
// binary ones, so the ratio test reads as written.
using NearestTwo = std::array<std::pair<int, float>, 2>;

class Vocabulary::Index {
 public:
  virtual ~Index() = default;
  // Adds words to the built index (incremental insertion).
  virtual void add(const cv::Mat& descriptors, const std::vector<int>& wordIds) = 0;
  // Replaces the whole index by one built over these words only.
  virtual void rebuild(const cv::Mat& descriptors, const std::vector<int>& wordIds) = 0;
  virtual void remove(int wordId) = 0;
  virtual std::vector<NearestTwo> nearestTwo(const cv::Mat& queries) const = 0;
  virtual size_t size() const = 0;        // words in the index
  // Points the index holds: its words plus the removed ones it still stores until a rebuild.
  virtual size_t points() const = 0;
  virtual size_t builtSize() const = 0;   // words at the last rebuild
  virtual size_t memoryUsed() const = 0;  // bytes: rows, trees and the point <-> word tables
  virtual bool built() const = 0;

  // The index that suits the strategy and the descriptor type (CV_32F or CV_8U rows).
  static std::unique_ptr<Index> create(const VocabularyOptions& options, int descriptorType);
};

}  // namespace rtabmap::vocabulary
