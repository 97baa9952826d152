#include "WordIndex.h"

#include <flann/flann.hpp>

#include "ReproducibleKdTree.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace rtabmap::vocabulary {
namespace {

// How descriptor rows are stored in an index.
enum class Encoding {
  kAsIs,           // float rows, or binary rows under the Hamming distance (LSH, linear)
  kBitsAsBytes,    // binary rows under L2 kd-trees: one byte per bit, 0 or kBitValue
  kBytesAsFloats,  // Kp/ByteToFloat: one float per byte (8x less memory, distances only approximate Hamming)
};

// A bit set is stored as 2, not 1: the kd-tree splits a leaf at the midpoint of two values in
// the element type, (0 + 2) / 2 = 1 in bytes where (0 + 1) / 2 would truncate to 0. Every tree
// quantity then scales by a power of two (distances and bounds by 4, means by 2), exactly, so
// the trees and the search are those of the 0/1 floats the index used before, with 4x less
// memory to walk (256 bytes a word instead of 1 KB: the search is bound by memory reads).
constexpr uchar kBitValue = 2;
constexpr float kBitDistanceScale = static_cast<float>(kBitValue * kBitValue);

cv::Mat toIndexRows(const cv::Mat& descriptors, Encoding encoding) {
  if (descriptors.type() == CV_32F || encoding == Encoding::kAsIs) return descriptors;
  if (encoding == Encoding::kBytesAsFloats) {
    cv::Mat out;
    descriptors.convertTo(out, CV_32F);
    return out;
  }
  cv::Mat out(descriptors.rows, descriptors.cols * 8, CV_8U);
  for (int r = 0; r < descriptors.rows; ++r) {
    const uchar* in = descriptors.ptr<uchar>(r);
    uchar* o = out.ptr<uchar>(r);
    for (int c = 0; c < descriptors.cols; ++c) {
      for (int b = 0; b < 8; ++b) o[c * 8 + b] = ((in[c] >> b) & 1) ? kBitValue : 0;
    }
  }
  return out;
}

// FLANN keeps pointers to the rows it indexes: every batch lives in `chunks_` until the next
// rebuild, which copies the surviving words into one new chunk. FlannType is flann::Index (LSH,
// linear) or flann::KDTreeIndex itself (kd-trees over the reproducible distances).
template <class Distance, class FlannType = flann::Index<Distance>>
class FlannIndex : public Vocabulary::Index {
  using T = typename Distance::ElementType;

 public:
  // squaredDistance: FLANN's distance is the square of the descriptors' one; else it is theirs
  // times distanceScale.
  FlannIndex(flann::IndexParams params, int checks, bool squaredDistance, Encoding encoding, float distanceScale = 1.f)
      : params_(std::move(params)), search_(checks), squared_(squaredDistance), encoding_(encoding),
        distanceScale_(distanceScale) {
    search_.cores = 1;
  }

  void add(const cv::Mat& descriptors, const std::vector<int>& wordIds) override {
    if (!index_) return rebuild(descriptors, wordIds);
    flann::Matrix<T> rows = store(descriptors, wordIds);
    // FLANN would rebuild by itself past a growth threshold; the vocabulary decides when.
    index_->addPoints(rows, std::numeric_limits<float>::max());
  }

  void rebuild(const cv::Mat& descriptors, const std::vector<int>& wordIds) override {
    chunks_.clear();
    wordOfPoint_.clear();
    pointOfWord_.clear();
    index_.reset();
    if (wordIds.empty()) return;
    flann::Matrix<T> rows = store(descriptors, wordIds);
    index_ = std::make_unique<FlannType>(rows, params_);
    index_->buildIndex();
    builtSize_ = wordIds.size();
  }

  void remove(int wordId) override {
    auto it = pointOfWord_.find(wordId);
    if (it == pointOfWord_.end()) return;
    index_->removePoint(it->second);
    wordOfPoint_[it->second] = 0;
    pointOfWord_.erase(it);
  }

  std::vector<NearestTwo> nearestTwo(const cv::Mat& queries) const override {
    std::vector<NearestTwo> result(queries.rows, NearestTwo{{{0, 0.f}, {0, 0.f}}});
    if (!index_ || pointOfWord_.empty() || queries.empty()) return result;
    cv::Mat q = toIndexRows(queries, encoding_);
    if (!q.isContinuous()) q = q.clone();
    flann::Matrix<T> query(reinterpret_cast<T*>(q.data), q.rows, q.cols);
    // One batch search into flat result matrices (no per-query vectors). FLANN skips removed
    // points itself; slots it could not fill keep the "none" marker.
    constexpr size_t kNone = std::numeric_limits<size_t>::max();
    std::vector<size_t> indices(static_cast<size_t>(q.rows) * 2, kNone);
    std::vector<typename Distance::ResultType> dists(indices.size());
    flann::Matrix<size_t> indexMatrix(indices.data(), q.rows, 2);
    flann::Matrix<typename Distance::ResultType> distMatrix(dists.data(), q.rows, 2);
    index_->knnSearch(query, indexMatrix, distMatrix, 2, search_);
    for (int r = 0; r < queries.rows; ++r) {
      int k = 0;
      for (size_t j = 0; j < 2; ++j) {
        const size_t point = indices[r * 2 + j];
        if (point >= wordOfPoint_.size() || wordOfPoint_[point] == 0) continue;  // none or removed
        const float d = static_cast<float>(dists[r * 2 + j]);
        result[r][k++] = {wordOfPoint_[point], squared_ ? std::sqrt(std::max(0.f, d)) : d / distanceScale_};
      }
    }
    return result;
  }

  size_t size() const override { return pointOfWord_.size(); }
  size_t points() const override { return wordOfPoint_.size(); }
  size_t builtSize() const override { return builtSize_; }
  size_t memoryUsed() const override {
    size_t bytes = index_ ? static_cast<size_t>(index_->usedMemory()) : 0;  // trees (node pools)
    for (const cv::Mat& c : chunks_) bytes += c.total() * c.elemSize();
    bytes += wordOfPoint_.size() * (sizeof(void*) + sizeof(size_t));  // FLANN's point and id tables
    bytes += wordOfPoint_.capacity() * sizeof(int);
    // A hash node (next pointer, key, value, cached hash) per word, and the bucket array.
    bytes += pointOfWord_.size() * (sizeof(void*) + sizeof(int) + 2 * sizeof(size_t)) +
             pointOfWord_.bucket_count() * sizeof(void*);
    return bytes;
  }
  bool built() const override { return index_ != nullptr; }

 private:
  flann::Matrix<T> store(const cv::Mat& descriptors, const std::vector<int>& wordIds) {
    cv::Mat rows = toIndexRows(descriptors, encoding_).clone();  // owned, continuous
    const size_t first = wordOfPoint_.size();
    for (size_t i = 0; i < wordIds.size(); ++i) {
      wordOfPoint_.push_back(wordIds[i]);
      pointOfWord_[wordIds[i]] = first + i;
    }
    chunks_.push_back(rows);
    return flann::Matrix<T>(reinterpret_cast<T*>(rows.data), rows.rows, rows.cols);
  }

  flann::IndexParams params_;
  flann::SearchParams search_;
  bool squared_;
  Encoding encoding_;
  float distanceScale_;
  std::unique_ptr<FlannType> index_;
  std::vector<cv::Mat> chunks_;
  std::vector<int> wordOfPoint_;                  // FLANN point id -> word id (0 = removed)
  std::unordered_map<int, size_t> pointOfWord_;   // word id -> FLANN point id
  size_t builtSize_ = 0;
};

}  // namespace

std::unique_ptr<Vocabulary::Index> Vocabulary::Index::create(const VocabularyOptions& options,
                                                             int descriptorType) {
  const bool binary = descriptorType == CV_8U;
  const bool linear = options.nnStrategy == NNStrategy::kLinear || options.nnStrategy == NNStrategy::kBruteForce;
  if (binary && options.nnStrategy == NNStrategy::kLsh) {
    return std::make_unique<FlannIndex<flann::Hamming<unsigned char>>>(
        flann::LshIndexParams(12, 20, 2), options.searchChecks, false, Encoding::kAsIs);
  }
  if (binary && linear) {
    return std::make_unique<FlannIndex<flann::Hamming<unsigned char>>>(
        flann::LinearIndexParams(), flann::FLANN_CHECKS_UNLIMITED, false, Encoding::kAsIs);
  }
  if (linear) {
    return std::make_unique<FlannIndex<flann::L2<float>>>(
        flann::LinearIndexParams(), flann::FLANN_CHECKS_UNLIMITED, true, Encoding::kAsIs);
  }
  // kd-trees (also for float descriptors under the LSH strategy: LSH needs binary ones). FLANN's
  // L2 is squared: the true distance is its square root, except for binary descriptors
  // expanded per bit, whose squared L2 is exactly (a multiple of) their Hamming distance, the
  // distance the ratio test must use for them (as the linear and LSH indexes and the in-image
  // matching do).
  // The trees are built reproducibly (ReproducibleKdTree.h): same words, same trees, same answers.
  using BytesTree = FlannIndex<ReproducibleL2Bytes, flann::KDTreeIndex<ReproducibleL2Bytes>>;
  using FloatsTree = FlannIndex<ReproducibleL2Floats, flann::KDTreeIndex<ReproducibleL2Floats>>;
  if (binary && !options.byteToFloat) {
    return std::make_unique<BytesTree>(flann::KDTreeIndexParams(options.kdTrees), options.searchChecks, false,
                                       Encoding::kBitsAsBytes, kBitDistanceScale);
  }
  return std::make_unique<FloatsTree>(flann::KDTreeIndexParams(options.kdTrees), options.searchChecks, true,
                                      binary ? Encoding::kBytesAsFloats : Encoding::kAsIs);
}

}  // namespace rtabmap::vocabulary
