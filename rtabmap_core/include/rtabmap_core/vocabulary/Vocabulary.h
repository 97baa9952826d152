#pragma once
// The incremental visual vocabulary of loop-closure detection (T-RO 2013, section III-B and
// Algorithm 2; the incremental FLANN index of the 2017/2019 papers).
//
// A visual word is a descriptor that stands for all the similar descriptors seen so far. A new
// location's descriptors are quantised by nearest neighbour with the distance-ratio test
// (Kp/NndrRatio): a descriptor whose nearest word is clearly nearer than the second nearest maps
// to it; otherwise it becomes a new word. Each word keeps the locations that contain it (the
// inverted index behind the TF-IDF likelihood) and how many times each does.
//
// The nearest-neighbour index is FLANN (Kp/NNStrategy): randomised kd-trees (4, drawn from a
// fixed seed so that runs repeat) on float descriptors (binary ones are expanded per bit, one
// byte a bit, or with Kp/ByteToFloat to one float per byte), LSH on binary descriptors with the Hamming distance, or linear search. New words are added to
// the index incrementally; it is rebuilt from the current words only when the vocabulary has
// grown by Kp/FlannRebalancingFactor (2 = doubled) since the last build, which bounds both the
// search-quality loss of incremental insertion and the memory of removed words. The rebuild
// runs on another thread from a copy of the words (about 350 ms for 60,000 binary words on
// this project's 2-core machine, once per Working Memory's worth of new words with memory
// management): the index in use keeps answering and taking new words, and the next location's
// quantize() swaps the new one in, brought up to date. Same words in, same swaps, same answers:
// runs still repeat.
//
// Memory management moves words out (removeWord, when no Working-Memory location references
// them any more) and back (addWord, on retrieval); the vocabulary never talks to the database.
#include <opencv2/core/mat.hpp>

#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::vocabulary {

enum class NNStrategy { kLinear = 0, kKdTree = 1, kLsh = 2, kBruteForce = 3 };

struct VocabularyOptions {
  NNStrategy nnStrategy = NNStrategy::kKdTree;  // Kp/NNStrategy
  float nndrRatio = 0.8f;                       // Kp/NndrRatio
  bool incrementalDictionary = true;            // Kp/IncrementalDictionary
  bool incrementalFlann = true;                 // Kp/IncrementalFlann
  float rebalancingFactor = 2.0f;               // Kp/FlannRebalancingFactor
  bool byteToFloat = false;                     // Kp/ByteToFloat
  bool newWordsComparedTogether = true;         // Kp/NewWordsComparedTogether
  int kdTrees = 4;      // the paper's forest of four randomised kd-trees
  // Leaves visited per kd-tree / LSH query: the approximation of the search. The original's 32;
  // each check costs a descent through trees far larger than the caches (about 2 us per check
  // over 100k binary words), so quantisation time is proportional to it. 64 was not better on
  // 7-Scenes (521 accepted loop closures against 538 with 32, none false in both).
  int searchChecks = 32;
  // Incremental rebuilds on another thread (see above); false: at once, on the caller's.
  bool rebuildInBackground = true;              // Kp/Parallelized

  static VocabularyOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

struct VisualWord {
  int id = 0;
  cv::Mat descriptor;              // one row, the descriptor that created the word
  std::map<int, int> references;   // location id -> occurrences of the word in it
};

struct VocabularySummary {
  int words = 0;                // words in the vocabulary (and the index)
  int indexBuilds = 0;          // full index builds since construction
  int lastBuildSize = 0;        // words at the last full build
  int lastNewWords = 0;         // words created by the last quantize()
  int lastMatchedWords = 0;     // descriptors of the last quantize() that matched a word
  double lastQuantizeMs = 0.0;  // time of the last quantize(), index update included
  long searchedDescriptors = 0;  // descriptors looked up in the index (quantize, findWords)
};

class Vocabulary {
 public:
  explicit Vocabulary(const VocabularyOptions& options = VocabularyOptions());
  ~Vocabulary();
  Vocabulary(const Vocabulary&) = delete;
  Vocabulary& operator=(const Vocabulary&) = delete;

  // Algorithm 2: the word id of each descriptor row of a new location, creating words for the
  // descriptors that match none (only while Kp/IncrementalDictionary; a fixed vocabulary gives
  // the nearest word). Adds the location to each word's references. Descriptors are CV_32F or
  // CV_8U (binary) rows, all of the type and width of the vocabulary's first descriptors;
  // throws std::invalid_argument otherwise.
  std::vector<int> quantize(const cv::Mat& descriptors, int locationId);

  // The word each descriptor row quantises to without changing anything (0 when none passes
  // the ratio test). Used to re-quantise the words of a location retrieved from LTM.
  std::vector<int> findWords(const cv::Mat& descriptors) const;
  // The word whose descriptor is this row bit for bit (0 when none): a hash lookup, no search.
  // A word retrieved from LTM whose descriptor came back meanwhile as another word is that word.
  int exactWord(const cv::Mat& descriptor) const;

  void addReference(int wordId, int locationId, int count = 1);
  // Removes the location from the references of its words (words: word id -> keypoint, as in
  // Signature::getWords()).
  void removeReferences(int locationId, const std::multimap<int, int>& words);

  // Words no location references: to move to Long-Term Memory.
  std::vector<int> unreferencedWords() const;
  // Takes a word out of the vocabulary and the index. Throws std::out_of_range if unknown.
  VisualWord removeWord(int wordId);
  // Puts back a word (retrieval from LTM) with its id and references. Throws
  // std::invalid_argument if the id is in use or the descriptor does not fit.
  void addWord(VisualWord word);
  // Same for several words at once (one index update); nothing is added if one is invalid.
  void addWords(std::vector<VisualWord> words);

  const VisualWord* word(int wordId) const;
  const std::unordered_map<int, VisualWord>& words() const { return words_; }
  size_t size() const { return words_.size(); }
  // Ids of new words continue after this one (restored from the database on start).
  int lastWordId() const { return lastWordId_; }
  void setLastWordId(int id);
  int descriptorType() const { return descriptorType_; }  // -1 until the first descriptor
  int descriptorWidth() const { return descriptorWidth_; }
  const VocabularySummary& summary() const { return summary_; }
  // Bytes held, estimated: the words (descriptors, references, hash) and the index (its rows,
  // trees and the removed words it keeps until the next rebuild). Constant time.
  size_t memoryUsed() const;
  // (location, word) references over all words: the inverted index's entries.
  size_t referenceCount() const;
  // Points in the index: its words plus the removed ones it keeps until the next rebuild.
  size_t indexPoints() const;
  const VocabularyOptions& options() const { return options_; }

  class Index;  // the nearest-neighbour index (FLANN), private to the implementation

 private:
  void checkDescriptors(const cv::Mat& descriptors);
  void indexWords(const std::vector<int>& ids);
  cv::Mat rowsOf(const std::vector<int>& ids) const;  // the words' descriptors, one row each
  // The current words (sorted ids) and their descriptor rows, for a rebuild.
  std::pair<std::vector<int>, cv::Mat> snapshot() const;
  void startBackgroundRebuild();
  // Waits for a background rebuild, brings it up to date with the words added and removed
  // since its snapshot, and makes it the index.
  void adoptRebuiltIndex();
  struct Match { int wordId = 0; float first = -1.f, second = -1.f; };
  std::vector<Match> nearestTwo(const cv::Mat& descriptors) const;
  bool passesRatio(const Match& m) const;

  void insertWord(VisualWord word);
  // Adds count occurrences of the word in the location, keeping references_ right.
  void countReference(VisualWord& word, int locationId, int count);
  static uint64_t descriptorHash(const cv::Mat& row);

  VocabularyOptions options_;
  std::unordered_map<int, VisualWord> words_;
  std::unordered_multimap<uint64_t, int> byDescriptor_;  // descriptor hash -> word ids (exactWord)
  std::unique_ptr<Index> index_;
  std::future<std::unique_ptr<Index>> rebuilt_;  // a background rebuild, until adopted
  std::vector<int> rebuiltIds_;                   // the words it was built from (sorted)
  int lastWordId_ = 0;
  int descriptorType_ = -1;
  int descriptorWidth_ = 0;
  size_t references_ = 0;  // sum of every word's references.size(), for memoryUsed()
  mutable VocabularySummary summary_;  // mutable: the const searches count themselves
};

}  // namespace rtabmap::vocabulary
