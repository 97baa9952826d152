#include "WordIndex.h"

#include <flann/flann.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace rtabmap::vocabulary {
namespace {

// Binary descriptors searched with L2 kd-trees are expanded to floats: one float per bit (the
// squared L2 distance is then the Hamming distance) or one per byte (Kp/ByteToFloat: 8x less
// memory, distances only approximate Hamming).
cv::Mat toIndexRows(const cv::Mat& descriptors, bool expandBinary, bool perByte) {
  if (descriptors.type() == CV_32F || !expandBinary) return descriptors;
  if (perByte) {
    cv::Mat out;
    descriptors.convertTo(out, CV_32F);
    return out;
  }
  cv::Mat out(descriptors.rows, descriptors.cols * 8, CV_32F);
  for (int r = 0; r < descriptors.rows; ++r) {
    const uchar* in = descriptors.ptr<uchar>(r);
    float* o = out.ptr<float>(r);
    for (int c = 0; c < descriptors.cols; ++c) {
      for (int b = 0; b < 8; ++b) o[c * 8 + b] = static_cast<float>((in[c] >> b) & 1);
    }
  }
  return out;
}

// FLANN keeps pointers to the rows it indexes: every batch lives in `chunks_` until the next
// rebuild, which copies the surviving words into one new chunk.
template <class Distance>
class FlannIndex : public Vocabulary::Index {
  using T = typename Distance::ElementType;

 public:
  FlannIndex(flann::IndexParams params, int checks, bool squaredDistance, bool expandBinary, bool perByte)
      : params_(std::move(params)), search_(checks), squared_(squaredDistance),
        expandBinary_(expandBinary), perByte_(perByte) {
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
    index_ = std::make_unique<flann::Index<Distance>>(rows, params_);
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
    cv::Mat q = toIndexRows(queries, expandBinary_, perByte_);
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
        result[r][k++] = {wordOfPoint_[point], squared_ ? std::sqrt(std::max(0.f, d)) : d};
      }
    }
    return result;
  }

  size_t size() const override { return pointOfWord_.size(); }
  size_t points() const override { return wordOfPoint_.size(); }
  size_t builtSize() const override { return builtSize_; }
  bool built() const override { return index_ != nullptr; }

 private:
  flann::Matrix<T> store(const cv::Mat& descriptors, const std::vector<int>& wordIds) {
    cv::Mat rows = toIndexRows(descriptors, expandBinary_, perByte_).clone();  // owned, continuous
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
  bool squared_, expandBinary_, perByte_;
  std::unique_ptr<flann::Index<Distance>> index_;
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
        flann::LshIndexParams(12, 20, 2), options.searchChecks, false, false, false);
  }
  if (binary && linear) {
    return std::make_unique<FlannIndex<flann::Hamming<unsigned char>>>(
        flann::LinearIndexParams(), flann::FLANN_CHECKS_UNLIMITED, false, false, false);
  }
  if (linear) {
    return std::make_unique<FlannIndex<flann::L2<float>>>(
        flann::LinearIndexParams(), flann::FLANN_CHECKS_UNLIMITED, true, false, false);
  }
  // kd-trees (also for float descriptors under the LSH strategy: LSH needs binary ones). FLANN's
  // L2 is squared: the true distance is its square root, except for binary descriptors
  // expanded per bit, whose squared L2 is exactly their Hamming distance, the distance the
  // ratio test must use for them (as the linear and LSH indexes and the in-image matching do).
  const bool hamming = binary && !options.byteToFloat;
  return std::make_unique<FlannIndex<flann::L2<float>>>(
      flann::KDTreeIndexParams(options.kdTrees), options.searchChecks, !hamming, binary, options.byteToFloat);
}

}  // namespace rtabmap::vocabulary
