#include "rtabmap_core/vocabulary/Vocabulary.h"

#include <opencv2/core.hpp>
#include <opencv2/core/hal/hal.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>
#include <stdexcept>

#include "WordIndex.h"
#include "rtabmap_core/common/Error.h"

namespace rtabmap::vocabulary {
namespace {

// Distance between rows i and j of one descriptor matrix, the one the index uses: Hamming for
// binary rows, Euclidean for float ones. On raw row pointers, without cv::norm's per-call Mat
// headers: it runs for every pair of a frame's new words (125,000 pairs on a first frame of 500).
float rowDistance(const cv::Mat& descriptors, int i, int j) {
  if (descriptors.type() == CV_8U) {
    return static_cast<float>(cv::hal::normHamming(descriptors.ptr<uchar>(i), descriptors.ptr<uchar>(j), descriptors.cols));
  }
  return std::sqrt(cv::normL2Sqr<float, float>(descriptors.ptr<float>(i), descriptors.ptr<float>(j), descriptors.cols));
}

// Keeps the two smallest (word, distance) pairs.
void offer(NearestTwo& best, int wordId, float distance) {
  if (best[0].first == 0 || distance < best[0].second) {
    best[1] = best[0];
    best[0] = {wordId, distance};
  } else if (best[1].first == 0 || distance < best[1].second) {
    best[1] = {wordId, distance};
  }
}

}  // namespace

VocabularyOptions VocabularyOptions::fromParameters(const ParametersMap& parameters) {
  VocabularyOptions o;
  o.nnStrategy = static_cast<NNStrategy>(Parameters::getInt(parameters, Parameters::kKpNNStrategy()));
  o.nndrRatio = Parameters::getFloat(parameters, Parameters::kKpNndrRatio());
  o.incrementalDictionary = Parameters::getBool(parameters, Parameters::kKpIncrementalDictionary());
  o.incrementalFlann = Parameters::getBool(parameters, Parameters::kKpIncrementalFlann());
  o.rebalancingFactor = Parameters::getFloat(parameters, Parameters::kKpFlannRebalancingFactor());
  o.byteToFloat = Parameters::getBool(parameters, Parameters::kKpByteToFloat());
  o.newWordsComparedTogether = Parameters::getBool(parameters, Parameters::kKpNewWordsComparedTogether());
  o.rebuildInBackground = Parameters::getBool(parameters, Parameters::kKpParallelized());
  std::string why;
  if (!o.IsValid(&why)) throw ParameterError(why);
  return o;
}

bool VocabularyOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  const int s = static_cast<int>(nnStrategy);
  if (s < 0 || s > 3) return fail(Parameters::kKpNNStrategy() + " must be 0, 1, 2 or 3");
  if (!(nndrRatio > 0.0f && nndrRatio <= 1.0f)) return fail(Parameters::kKpNndrRatio() + " must be in (0, 1]");
  if (kdTrees < 1) return fail("kd-tree count must be at least 1");
  if (searchChecks < 1) return fail("FLANN search checks must be at least 1");
  return true;
}

Vocabulary::Vocabulary(const VocabularyOptions& options) : options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("Vocabulary: " + why);
}

// A background rebuild owns copies of what it builds from: nothing to stop, only to wait for.
Vocabulary::~Vocabulary() {
  if (rebuilt_.valid()) rebuilt_.wait();
}

void Vocabulary::setLastWordId(int id) {
  if (id < lastWordId_) {
    std::ostringstream m;
    m << "Vocabulary::setLastWordId(" << id << "): ids already go up to " << lastWordId_;
    throw std::invalid_argument(m.str());
  }
  lastWordId_ = id;
}

void Vocabulary::checkDescriptors(const cv::Mat& descriptors) {
  if (descriptors.empty()) return;
  if (descriptors.type() != CV_32F && descriptors.type() != CV_8U) {
    throw std::invalid_argument("Vocabulary: descriptors must be CV_32F (float) or CV_8U (binary) rows");
  }
  if (descriptorType_ < 0) {
    descriptorType_ = descriptors.type();
    descriptorWidth_ = descriptors.cols;
    index_ = Index::create(options_, descriptorType_);
    return;
  }
  if (descriptors.type() != descriptorType_ || descriptors.cols != descriptorWidth_) {
    std::ostringstream m;
    m << "Vocabulary: descriptors of type " << descriptors.type() << " and width " << descriptors.cols
      << " do not fit the vocabulary (type " << descriptorType_ << ", width " << descriptorWidth_
      << "); was the feature type changed (Kp/DetectorStrategy) on an existing map?";
    throw std::invalid_argument(m.str());
  }
}

bool Vocabulary::passesRatio(const Match& m) const {
  if (m.wordId == 0) return false;
  if (m.first == 0.0f) return true;   // the very descriptor of a word
  if (m.second < 0.0f) return false;  // a single candidate: no ratio to test
  return m.first <= options_.nndrRatio * m.second;
}

std::vector<Vocabulary::Match> Vocabulary::nearestTwo(const cv::Mat& descriptors) const {
  std::vector<Match> matches(descriptors.rows);
  if (!index_ || descriptors.empty()) return matches;
  summary_.searchedDescriptors += descriptors.rows;
  const auto found = index_->nearestTwo(descriptors);
  for (int i = 0; i < descriptors.rows; ++i) {
    matches[i].wordId = found[i][0].first;
    if (found[i][0].first) matches[i].first = found[i][0].second;
    if (found[i][1].first) matches[i].second = found[i][1].second;
  }
  return matches;
}

std::vector<int> Vocabulary::findWords(const cv::Mat& descriptors) const {
  if (!descriptors.empty() && descriptorType_ >= 0 &&
      (descriptors.type() != descriptorType_ || descriptors.cols != descriptorWidth_)) {
    throw std::invalid_argument("Vocabulary::findWords: descriptors do not fit the vocabulary");
  }
  std::vector<int> ids(descriptors.rows, 0);
  const auto matches = nearestTwo(descriptors);
  for (int i = 0; i < descriptors.rows; ++i) {
    if (passesRatio(matches[i])) ids[i] = matches[i].wordId;
  }
  return ids;
}

std::vector<int> Vocabulary::quantize(const cv::Mat& descriptors, int locationId) {
  const auto start = std::chrono::steady_clock::now();
  checkDescriptors(descriptors);
  if (rebuilt_.valid()) adoptRebuiltIndex();
  std::vector<int> ids(descriptors.rows, 0);
  summary_.lastNewWords = summary_.lastMatchedWords = 0;
  if (descriptors.empty()) return ids;

  const auto matches = nearestTwo(descriptors);
  // Words created by this location so far: a later descriptor of the same image may match one
  // of them (they are not in the index yet), so they compete with the index's two nearest.
  std::vector<int> newIds;
  std::vector<int> newRows;
  // Without Kp/IncrementalDictionary the first location's words are the whole vocabulary.
  const bool fixed = !options_.incrementalDictionary && !words_.empty();
  for (int i = 0; i < descriptors.rows; ++i) {
    NearestTwo best{{{0, 0.f}, {0, 0.f}}};
    if (matches[i].wordId) offer(best, matches[i].wordId, matches[i].first);
    if (matches[i].second >= 0.f) offer(best, -1, matches[i].second);  // only its distance matters
    for (size_t n = 0; options_.newWordsComparedTogether && n < newIds.size(); ++n) {
      offer(best, newIds[n], rowDistance(descriptors, i, newRows[n]));
    }
    Match m;
    m.wordId = best[0].first;
    m.first = best[0].first ? best[0].second : -1.f;
    m.second = best[1].first ? best[1].second : -1.f;
    if (m.wordId > 0 && (passesRatio(m) || fixed)) {
      ids[i] = m.wordId;
      ++summary_.lastMatchedWords;
    } else if (!fixed) {
      VisualWord w;
      w.id = ++lastWordId_;
      w.descriptor = descriptors.row(i).clone();
      ids[i] = w.id;
      newIds.push_back(w.id);
      newRows.push_back(i);
      insertWord(std::move(w));
      ++summary_.lastNewWords;
    }
    if (ids[i]) countReference(words_.at(ids[i]), locationId, 1);
  }
  indexWords(newIds);
  summary_.words = static_cast<int>(words_.size());
  summary_.lastQuantizeMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return ids;
}

// New words go into the index incrementally, except when the index has grown by the
// rebalancing factor since the last build (or incremental FLANN is off): then the whole index
// is rebuilt from the current words. Growth counts every point inserted, removed words included:
// with memory management words leave as fast as they come, and an index that only counted its
// live words would never be rebuilt while its trees fill with removed points and unbalanced
// insertions (seen on the simulator's long run: 2 s updates at 48 locations in WM).
void Vocabulary::indexWords(const std::vector<int>& ids) {
  if (ids.empty()) return;
  const bool grown = options_.rebalancingFactor > 1.0f &&
                     index_->points() + ids.size() > options_.rebalancingFactor * index_->builtSize();
  const bool background = options_.rebuildInBackground && options_.incrementalFlann && index_->built();
  if (!index_->built() || !options_.incrementalFlann || (grown && !background)) {
    auto [all, rows] = snapshot();
    index_->rebuild(rows, all);
    ++summary_.indexBuilds;
    summary_.lastBuildSize = static_cast<int>(all.size());
    return;
  }
  // Meanwhile (and while a background rebuild runs) the index in use takes the new words.
  if (grown && !rebuilt_.valid()) startBackgroundRebuild();
  index_->add(rowsOf(ids), ids);
}

cv::Mat Vocabulary::rowsOf(const std::vector<int>& ids) const {
  cv::Mat rows(static_cast<int>(ids.size()), descriptorWidth_, descriptorType_);
  for (size_t i = 0; i < ids.size(); ++i) words_.at(ids[i]).descriptor.copyTo(rows.row(static_cast<int>(i)));
  return rows;
}

std::pair<std::vector<int>, cv::Mat> Vocabulary::snapshot() const {
  std::vector<int> all;
  all.reserve(words_.size());
  for (const auto& [id, w] : words_) all.push_back(id);
  std::sort(all.begin(), all.end());
  cv::Mat rows = rowsOf(all);
  return {std::move(all), std::move(rows)};
}

void Vocabulary::startBackgroundRebuild() {
  auto [all, rows] = snapshot();
  rebuiltIds_ = all;
  const VocabularyOptions options = options_;
  const int type = descriptorType_;
  rebuilt_ = std::async(std::launch::async, [options, type, all = std::move(all), rows = std::move(rows)] {
    std::unique_ptr<Index> index = Index::create(options, type);
    index->rebuild(rows, all);
    return index;
  });
}

void Vocabulary::adoptRebuiltIndex() {
  std::unique_ptr<Index> fresh = rebuilt_.get();  // rethrows what the build threw
  const std::vector<int> built = std::move(rebuiltIds_);
  rebuiltIds_.clear();
  // Words removed since the snapshot leave it; words added since (new or retrieved) join it,
  // in id order, as the index in use took them.
  for (int id : built) {
    if (!words_.count(id)) fresh->remove(id);
  }
  std::vector<int> added;
  for (const auto& [id, w] : words_) {
    if (!std::binary_search(built.begin(), built.end(), id)) added.push_back(id);
  }
  std::sort(added.begin(), added.end());
  if (!added.empty()) fresh->add(rowsOf(added), added);
  index_ = std::move(fresh);
  ++summary_.indexBuilds;
  summary_.lastBuildSize = static_cast<int>(built.size());
}

// Every update's statistics ask for it: counted from sizes, not by walking the words (a walk of
// 65k words was 7% of an update on the simulator's long run). Every word's descriptor has the
// vocabulary's type and width (checkDescriptors), and references_ follows every reference added
// or removed.
size_t Vocabulary::memoryUsed() const {
  // Container nodes counted as their payload plus two pointers and a hash; a cv::Mat row as its
  // bytes plus OpenCV's shared block header (UMatData, about 100 bytes).
  constexpr size_t kNode = 2 * sizeof(void*) + sizeof(size_t), kMatBlock = 100;
  constexpr size_t kReference = 4 * sizeof(void*) + 2 * sizeof(int);  // std::map node
  const size_t descriptorBytes =
      descriptorType_ < 0 ? 0 : static_cast<size_t>(descriptorWidth_) * CV_ELEM_SIZE(descriptorType_);
  size_t bytes = words_.bucket_count() * sizeof(void*) + byDescriptor_.bucket_count() * sizeof(void*);
  bytes += byDescriptor_.size() * (kNode + sizeof(uint64_t) + sizeof(int));
  bytes += words_.size() * (kNode + sizeof(int) + sizeof(VisualWord) + kMatBlock + descriptorBytes);
  bytes += references_ * kReference;
  return bytes + (index_ ? index_->memoryUsed() : 0);
}

size_t Vocabulary::referenceCount() const { return references_; }

void Vocabulary::countReference(VisualWord& word, int locationId, int count) {
  const auto [it, added] = word.references.try_emplace(locationId, 0);
  it->second += count;
  if (added) ++references_;
}

size_t Vocabulary::indexPoints() const { return index_ ? index_->points() : 0; }

void Vocabulary::addReference(int wordId, int locationId, int count) {
  auto it = words_.find(wordId);
  if (it == words_.end()) throw std::out_of_range("Vocabulary::addReference: unknown word " + std::to_string(wordId));
  countReference(it->second, locationId, count);
}

void Vocabulary::removeReferences(int locationId, const std::multimap<int, int>& words) {
  for (auto it = words.begin(); it != words.end(); it = words.upper_bound(it->first)) {
    auto w = words_.find(it->first);
    if (w != words_.end()) references_ -= w->second.references.erase(locationId);
  }
}

std::vector<int> Vocabulary::unreferencedWords() const {
  std::vector<int> ids;
  for (const auto& [id, w] : words_) {
    if (w.references.empty()) ids.push_back(id);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

VisualWord Vocabulary::removeWord(int wordId) {
  auto it = words_.find(wordId);
  if (it == words_.end()) throw std::out_of_range("Vocabulary::removeWord: unknown word " + std::to_string(wordId));
  VisualWord w = std::move(it->second);
  words_.erase(it);
  references_ -= w.references.size();
  auto range = byDescriptor_.equal_range(descriptorHash(w.descriptor));
  for (auto h = range.first; h != range.second; ++h) {
    if (h->second == wordId) {
      byDescriptor_.erase(h);
      break;
    }
  }
  index_->remove(wordId);
  summary_.words = static_cast<int>(words_.size());
  return w;
}

void Vocabulary::addWord(VisualWord word) {
  std::vector<VisualWord> one;
  one.push_back(std::move(word));
  addWords(std::move(one));
}

void Vocabulary::addWords(std::vector<VisualWord> words) {
  std::set<int> given;
  for (const auto& word : words) {
    if (word.id <= 0 || words_.count(word.id) || !given.insert(word.id).second) {
      throw std::invalid_argument("Vocabulary::addWords: word id " + std::to_string(word.id) + " is invalid or in use");
    }
    if (word.descriptor.rows != 1) throw std::invalid_argument("Vocabulary::addWords: a descriptor must be one row");
    checkDescriptors(word.descriptor);
  }
  std::vector<int> ids;
  for (auto& word : words) {
    const int id = word.id;
    insertWord(std::move(word));
    lastWordId_ = std::max(lastWordId_, id);
    ids.push_back(id);
  }
  indexWords(ids);
  summary_.words = static_cast<int>(words_.size());
}

// FNV-1a over the row's bytes.
uint64_t Vocabulary::descriptorHash(const cv::Mat& row) {
  uint64_t h = 1469598103934665603ull;
  const uchar* p = row.ptr<uchar>(0);
  const size_t n = row.cols * row.elemSize();
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

void Vocabulary::insertWord(VisualWord word) {
  const int id = word.id;
  byDescriptor_.emplace(descriptorHash(word.descriptor), id);
  references_ += word.references.size();
  words_.emplace(id, std::move(word));
}

int Vocabulary::exactWord(const cv::Mat& descriptor) const {
  if (descriptor.rows != 1 || descriptor.type() != descriptorType_ || descriptor.cols != descriptorWidth_) return 0;
  const size_t bytes = descriptor.cols * descriptor.elemSize();
  auto range = byDescriptor_.equal_range(descriptorHash(descriptor));
  for (auto h = range.first; h != range.second; ++h) {
    const VisualWord& w = words_.at(h->second);
    if (std::memcmp(w.descriptor.ptr<uchar>(0), descriptor.ptr<uchar>(0), bytes) == 0) return h->second;
  }
  return 0;
}

const VisualWord* Vocabulary::word(int wordId) const {
  auto it = words_.find(wordId);
  return it == words_.end() ? nullptr : &it->second;
}

}  // namespace rtabmap::vocabulary
