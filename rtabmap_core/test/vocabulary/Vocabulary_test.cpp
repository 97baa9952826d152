#include "rtabmap_core/vocabulary/Vocabulary.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <random>
#include <stdexcept>

#include "common/TestData.h"

namespace rtabmap::vocabulary {
namespace {

// Rows from the test's draw (RTABMAP_TEST_DRAW). Tests that count words take 256 dimensions:
// in 64, two uniform rows pass the 0.8 ratio test against each other now and then (about one
// 200-row image in seven), and a "new" word is then rightly matched.
cv::Mat randomFloat(int rows, int cols, unsigned seed) {
  cv::Mat m(rows, cols, CV_32F);
  cv::RNG rng(test::drawSeed(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0.f, 1.f);
  return m;
}

cv::Mat randomBinary(int rows, int bytes, unsigned seed) {
  cv::Mat m(rows, bytes, CV_8U);
  cv::RNG rng(test::drawSeed(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  return m;
}

// The word a brute-force search would give with the ratio test (0 = new word).
int bruteForceWord(const Vocabulary& v, const cv::Mat& d, float ratio) {
  int best = 0;
  double d1 = 1e30, d2 = 1e30;
  for (const auto& [id, w] : v.words()) {
    double dist = cv::norm(d, w.descriptor, d.type() == CV_8U ? cv::NORM_HAMMING : cv::NORM_L2);
    if (dist < d1) {
      d2 = d1;
      d1 = dist;
      best = id;
    } else if (dist < d2) {
      d2 = dist;
    }
  }
  if (d1 == 0.0) return best;
  return d2 < 1e30 && d1 <= ratio * d2 ? best : 0;
}

class VocabularyStrategies : public ::testing::TestWithParam<std::tuple<NNStrategy, int>> {};

TEST_P(VocabularyStrategies, SameDescriptorsMapToTheSameWordsFarOnesMakeNewWords) {
  const auto [strategy, type] = GetParam();
  VocabularyOptions o;
  o.nnStrategy = strategy;
  Vocabulary v(o);
  cv::Mat first = type == CV_32F ? randomFloat(200, 256, 1) : randomBinary(200, 32, 1);
  auto ids1 = v.quantize(first, 1);
  EXPECT_EQ(v.size(), 200u);  // random descriptors: nothing shared
  EXPECT_EQ(v.summary().lastNewWords, 200);
  for (int i = 0; i < 200; ++i) EXPECT_EQ(ids1[i], i + 1);

  cv::Mat second;
  cv::vconcat(first.rowRange(0, 100), type == CV_32F ? randomFloat(50, 256, 2) : randomBinary(50, 32, 2), second);
  auto ids2 = v.quantize(second, 2);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(ids2[i], ids1[i]) << "row " << i;
  // LSH sees only the candidates of its buckets, already closer than random ones: now and then
  // (FLANN draws its hash tables from std::random_device) two of them pass the ratio test for a
  // far descriptor. Every other index finds the true two nearest here.
  int newWords = 0;
  for (int i = 100; i < 150; ++i) newWords += ids2[i] > 200;
  EXPECT_GE(newWords, strategy == NNStrategy::kLsh ? 48 : 50);
  EXPECT_EQ(v.size(), 200u + static_cast<size_t>(newWords));
  EXPECT_EQ(v.word(ids1[0])->references.at(1), 1);
  EXPECT_EQ(v.word(ids1[0])->references.at(2), 1);
  EXPECT_EQ(v.word(ids1[150])->references.count(2), 0u);
}

INSTANTIATE_TEST_SUITE_P(AllIndexes, VocabularyStrategies,
                         ::testing::Values(std::make_tuple(NNStrategy::kKdTree, CV_32F),
                                           std::make_tuple(NNStrategy::kLinear, CV_32F),
                                           std::make_tuple(NNStrategy::kKdTree, CV_8U),
                                           std::make_tuple(NNStrategy::kLsh, CV_8U),
                                           std::make_tuple(NNStrategy::kBruteForce, CV_8U)));

TEST(Vocabulary, RatioTestRejectsAmbiguousMatches) {
  Vocabulary v;
  cv::Mat words = (cv::Mat_<float>(2, 2) << 0.f, 0.f, 1.f, 0.f);
  v.quantize(words, 1);
  // Half way between the two words: distance ratio 1 > 0.8, so a new word.
  auto ambiguous = v.quantize((cv::Mat_<float>(1, 2) << 0.5f, 0.f), 2);
  EXPECT_EQ(ambiguous[0], 3);
  // Near the first word: 0.1 / 0.9 < 0.8, the first word.
  auto clear = v.quantize((cv::Mat_<float>(1, 2) << 0.f, 0.1f), 3);
  EXPECT_EQ(clear[0], 1);
}

TEST(Vocabulary, DescriptorsOfOneImageShareNewWords) {
  Vocabulary v;
  cv::Mat base = randomFloat(20, 16, 3);
  v.quantize(base, 1);
  cv::Mat fresh = randomFloat(1, 16, 4);
  cv::Mat twice;
  cv::vconcat(fresh, fresh, twice);
  auto ids = v.quantize(twice, 2);
  EXPECT_EQ(ids[0], ids[1]);  // the second copy matches the word the first one created
  EXPECT_EQ(v.word(ids[0])->references.at(2), 2);
}

// Kp/NewWordsComparedTogether false: each copy makes a word of its own.
TEST(Vocabulary, NewWordsNotComparedTogetherMakeAWordEach) {
  VocabularyOptions o;
  o.newWordsComparedTogether = false;
  Vocabulary v(o);
  v.quantize(randomFloat(20, 16, 3), 1);
  cv::Mat fresh = randomFloat(1, 16, 4);
  cv::Mat twice;
  cv::vconcat(fresh, fresh, twice);
  const auto ids = v.quantize(twice, 2);
  EXPECT_NE(ids[0], ids[1]);
  EXPECT_EQ(v.size(), 22u);
  EXPECT_FALSE(VocabularyOptions::fromParameters({{"Kp/NewWordsComparedTogether", "false"}}).newWordsComparedTogether);
}

// Same for binary descriptors, where the distance between new words of one image is the
// Hamming distance: a near copy (3 bits flipped) of a new word joins it, a far one does not.
TEST(Vocabulary, BinaryDescriptorsOfOneImageShareNewWords) {
  Vocabulary v;
  v.quantize(randomBinary(50, 32, 3), 1);
  cv::Mat image = randomBinary(3, 32, 4);
  image.row(0).copyTo(image.row(1));
  image.at<uchar>(1, 0) ^= 0x01;
  image.at<uchar>(1, 7) ^= 0x30;
  auto ids = v.quantize(image, 2);
  EXPECT_GT(ids[0], 50);
  EXPECT_EQ(ids[1], ids[0]);
  EXPECT_GT(ids[2], ids[0]);
  EXPECT_EQ(v.word(ids[0])->references.at(2), 2);
}

// Incremental insertion must answer queries like an index built over the same words: with
// unlimited checks the kd-trees are exact, so both agree with brute force.
TEST(Vocabulary, IncrementalIndexAnswersLikeARebuiltOne) {
  VocabularyOptions incremental;
  incremental.searchChecks = 1 << 30;
  VocabularyOptions rebuilt = incremental;
  rebuilt.incrementalFlann = false;
  Vocabulary a(incremental), b(rebuilt);
  for (int loc = 1; loc <= 12; ++loc) {
    cv::Mat d = randomFloat(60, 32, 100 + loc);
    a.quantize(d, loc);
    b.quantize(d, loc);
  }
  ASSERT_EQ(a.size(), b.size());
  EXPECT_LT(a.summary().indexBuilds, b.summary().indexBuilds);
  cv::Mat queries = randomFloat(300, 32, 999);
  // Some queries near existing words.
  for (int i = 0; i < 100; ++i) {
    const auto& w = a.word(1 + i * 7)->descriptor;
    cv::Mat noise = randomFloat(1, 32, 5000 + i) * 0.01;
    cv::Mat q = w + noise;
    q.copyTo(queries.row(i));
  }
  auto fa = a.findWords(queries), fb = b.findWords(queries);
  int matched = 0;
  for (int i = 0; i < queries.rows; ++i) {
    const int expected = bruteForceWord(a, queries.row(i), incremental.nndrRatio);
    EXPECT_EQ(fa[i], expected) << "query " << i;
    EXPECT_EQ(fb[i], expected) << "query " << i;
    matched += expected != 0;
  }
  EXPECT_GE(matched, 100);
}

// The randomised kd-trees are built from a fixed seed (ReproducibleKdTree.h): two vocabularies
// fed the same descriptors answer every approximate query alike, through rebuilds and
// incremental insertion. Few checks, so the answers depend on the trees: some of them (5 to 60
// of 600) differ from brute force, and trees drawn at random (Debian FLANN's own build)
// disagree between the two vocabularies.
TEST(Vocabulary, KdTreesGiveTheSameWordsRunToRun) {
  for (const int type : {CV_32F, CV_8U}) {
    SCOPED_TRACE(type == CV_32F ? "float descriptors" : "binary descriptors");
    VocabularyOptions o;
    o.searchChecks = 4;
    Vocabulary a(o), b(o);
    for (int loc = 1; loc <= 20; ++loc) {
      cv::Mat d = type == CV_32F ? randomFloat(150, 32, 300 + loc) : randomBinary(150, 32, 300 + loc);
      a.quantize(d, loc);
      b.quantize(d, loc);
    }
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GE(a.summary().indexBuilds, 2);  // rebuilt at least once after the first build
    // Queries near existing words (a few percent of noise, a few bits flipped).
    cv::Mat queries = type == CV_32F ? randomFloat(600, 32, 77) : randomBinary(600, 32, 77);
    cv::RNG rng(test::drawSeed(78));
    for (int i = 0; i < queries.rows; ++i) {
      cv::Mat q = a.word(1 + i * 4)->descriptor.clone();
      if (type == CV_32F) {
        q += randomFloat(1, 32, 9000 + i) * 0.15;
      } else {
        for (int flip = 0; flip < 6; ++flip) {
          const int bit = rng.uniform(0, 8);  // drawn in statements: the order is ours, not the compiler's
          const int byte = rng.uniform(0, 32);
          q.at<uchar>(0, byte) ^= static_cast<uchar>(1 << bit);
        }
      }
      q.copyTo(queries.row(i));
    }
    const auto fa = a.findWords(queries), fb = b.findWords(queries);
    int differFromExact = 0;
    for (int i = 0; i < queries.rows; ++i) {
      EXPECT_EQ(fa[i], fb[i]) << "query " << i;
      differFromExact += fa[i] != bruteForceWord(a, queries.row(i), o.nndrRatio);
    }
    EXPECT_GE(differFromExact, 3) << "the search is exact here: the test would not see the trees";
    EXPECT_LE(differFromExact, queries.rows / 2) << "trees far worse than FLANN's";
  }
}

// The default index for binary descriptors (kd-trees over their bits), incremental, against
// brute-force Hamming search: with unlimited checks it is exact, and distances are Hamming
// counts, so the ratio test gives the same words. Queries are words with a few bits flipped
// (real matches) and random descriptors (new words).
TEST(Vocabulary, IncrementalBinaryIndexAnswersLikeBruteForce) {
  VocabularyOptions o;
  o.searchChecks = 1 << 30;
  Vocabulary v(o);
  for (int loc = 1; loc <= 8; ++loc) v.quantize(randomBinary(60, 32, 200 + loc), loc);
  ASSERT_GT(v.summary().indexBuilds, 1);
  cv::Mat queries = randomBinary(200, 32, 998);
  cv::RNG rng(test::drawSeed(7));
  for (int i = 0; i < 100; ++i) {
    v.word(1 + i * 4)->descriptor.copyTo(queries.row(i));
    for (int f = 0; f < 12; ++f) {
      const int bit = rng.uniform(0, 8);  // drawn in statements: the order is ours, not the compiler's
      const int byte = rng.uniform(0, 32);
      queries.at<uchar>(i, byte) ^= static_cast<uchar>(1 << bit);
    }
  }
  const auto found = v.findWords(queries);
  int matched = 0;
  for (int i = 0; i < queries.rows; ++i) {
    const int expected = bruteForceWord(v, queries.row(i), o.nndrRatio);
    EXPECT_EQ(found[i], expected) << "query " << i;
    matched += expected != 0;
  }
  EXPECT_GE(matched, 100);
}

// Rebuilt at once (VocabularyOptions::rebuildInBackground false, Kp/Parallelized false): the
// build is visible in the very call that triggers it.
VocabularyOptions rebuiltAtOnce() {
  VocabularyOptions o;
  o.rebuildInBackground = false;
  return o;
}

TEST(Vocabulary, KpParallelizedChoosesWhereTheIndexIsRebuilt) {
  EXPECT_TRUE(VocabularyOptions::fromParameters({}).rebuildInBackground);
  const VocabularyOptions atOnce = VocabularyOptions::fromParameters({{"Kp/Parallelized", "false"}});
  EXPECT_FALSE(atOnce.rebuildInBackground);
  Vocabulary v(atOnce);
  v.quantize(randomFloat(100, 256, 1), 1);
  v.quantize(randomFloat(120, 256, 2), 2);  // 220 > 2 x 100: rebuilt within this call
  EXPECT_EQ(v.summary().indexBuilds, 2);
}

TEST(Vocabulary, IndexIsRebuiltWhenTheVocabularyDoubles) {
  Vocabulary v(rebuiltAtOnce());
  v.quantize(randomFloat(100, 256, 1), 1);
  ASSERT_EQ(v.size(), 100u);
  EXPECT_EQ(v.summary().indexBuilds, 1);
  v.quantize(randomFloat(100, 256, 2), 2);  // 200 words = 2 x 100: not more than doubled
  ASSERT_EQ(v.size(), 200u);
  EXPECT_EQ(v.summary().indexBuilds, 1);
  v.quantize(randomFloat(5, 256, 3), 3);  // past the double: rebuilt over all words
  EXPECT_EQ(v.summary().indexBuilds, 2);
  EXPECT_EQ(v.summary().lastBuildSize, static_cast<int>(v.size()));
}

// Words leaving (transfer) do not make room for new ones in the index: it is rebuilt once it
// holds twice the points of its last build, removed ones included, so it never fills up with
// dead points between builds.
TEST(Vocabulary, RemovedWordsCountTowardsTheRebuild) {
  Vocabulary v(rebuiltAtOnce());
  cv::Mat first = randomFloat(100, 256, 11);
  auto ids = v.quantize(first, 1);
  ASSERT_EQ(v.summary().indexBuilds, 1);
  for (int i = 0; i < 90; ++i) v.removeWord(ids[i]);
  v.quantize(randomFloat(90, 256, 12), 2);  // 100 + 90 points held: no rebuild yet
  EXPECT_EQ(v.summary().indexBuilds, 1);
  v.quantize(randomFloat(20, 256, 13), 3);  // 210 > 2 x 100: rebuilt over the 120 live words
  EXPECT_EQ(v.summary().indexBuilds, 2);
  EXPECT_EQ(v.summary().lastBuildSize, 120);
  EXPECT_EQ(v.findWords(first.row(95))[0], ids[95]);
}

// The memory the statistics report (issue 10): the index keeps removed words' rows and tree
// nodes until it is rebuilt, so between builds the vocabulary's memory follows the points held,
// not the words; a rebuild gives the removed ones back.
TEST(Vocabulary, MemoryFollowsTheIndexPointsUntilTheRebuild) {
  Vocabulary v(rebuiltAtOnce());
  const size_t empty = v.memoryUsed();
  auto ids = v.quantize(randomBinary(1000, 32, 31), 1);
  ASSERT_EQ(v.size(), 1000u);
  EXPECT_EQ(v.indexPoints(), 1000u);
  const size_t built = v.memoryUsed();
  // At least each word's descriptor and its bits as bytes in the kd-trees' rows.
  EXPECT_GE(built - empty, 1000u * (32 + 256));
  EXPECT_LT(built - empty, 1000u * 2048) << "more than 2 KB a binary word";
  for (int i = 0; i < 600; ++i) v.removeWord(ids[i]);
  EXPECT_EQ(v.size(), 400u);
  EXPECT_EQ(v.indexPoints(), 1000u) << "removed words stay in the index until a rebuild";
  const size_t removed = v.memoryUsed();
  EXPECT_LT(removed, built);                        // their descriptors and references went
  EXPECT_GT(removed - empty, 1000u * 256);          // their rows did not
  v.quantize(randomBinary(1001, 32, 32), 2);        // 2001 points > 2 x 1000: rebuilt
  ASSERT_EQ(v.summary().indexBuilds, 2);
  EXPECT_EQ(v.indexPoints(), v.size());
  EXPECT_EQ(v.size(), 1401u);
  const size_t rebuilt = v.memoryUsed();
  EXPECT_LT(rebuilt - empty, 1401u * 2048);
  EXPECT_GE(rebuilt - empty, 1401u * (32 + 256));
}

// The default rebuild runs on another thread from a snapshot of the words; until the next
// location's quantize() the index in use answers and takes new words, then the rebuilt one
// replaces it, with the words removed and added meanwhile (transfer, retrieval) brought in.
TEST(Vocabulary, BackgroundRebuildIsAdoptedUpToDateByTheNextLocation) {
  VocabularyOptions o;
  o.searchChecks = 1 << 30;  // exact: any word missing from the index would show
  Vocabulary v(o);
  const auto first = v.quantize(randomBinary(100, 32, 51), 1);
  ASSERT_EQ(v.summary().indexBuilds, 1);
  v.quantize(randomBinary(100, 32, 52), 2);
  const auto third = v.quantize(randomBinary(20, 32, 53), 3);  // 220 > 2 x 100: rebuild started
  EXPECT_EQ(v.summary().indexBuilds, 1) << "not adopted before the next location";
  EXPECT_EQ(v.findWords(v.word(third[5])->descriptor)[0], third[5]) << "the index in use took the new words";
  // Meanwhile: 30 words of the snapshot leave, one comes back, a new one arrives by retrieval.
  std::vector<VisualWord> out;
  for (int i = 0; i < 30; ++i) out.push_back(v.removeWord(first[i]));
  v.addWord(std::move(out[0]));
  VisualWord retrieved;
  retrieved.id = 5000;
  retrieved.descriptor = randomBinary(1, 32, 54);
  retrieved.references[99] = 1;
  v.addWord(retrieved);
  const auto fourth = v.quantize(randomBinary(10, 32, 55), 4);  // adopts the rebuilt index
  EXPECT_EQ(v.summary().indexBuilds, 2);
  EXPECT_EQ(v.summary().lastBuildSize, 220) << "the snapshot's words";
  EXPECT_EQ(v.size(), 220u - 30u + 1u + 1u + 10u);
  EXPECT_EQ(v.indexPoints(), 220u + 1u + 10u) << "snapshot, the retrieved word, the fourth location's";
  for (const auto& [id, w] : v.words()) ASSERT_EQ(v.findWords(w.descriptor)[0], id) << "word " << id;
  for (int i = 1; i < 30; ++i) EXPECT_EQ(v.exactWord(out[i].descriptor), 0);
  for (int i = 1; i < 30; ++i) EXPECT_NE(v.findWords(out[i].descriptor)[0], first[i]) << "a removed word answered";
  (void)fourth;
}

// Background rebuilds keep runs repeatable: the swap happens at the same location every run.
TEST(Vocabulary, BackgroundRebuildsRepeatRunToRun) {
  VocabularyOptions o;
  o.searchChecks = 4;  // approximate: the answers depend on the trees and their history
  Vocabulary a(o), b(o);
  for (int loc = 1; loc <= 30; ++loc) {
    const cv::Mat d = randomBinary(120, 32, 600 + loc);
    const std::vector<int> wa = a.quantize(d, loc), wb = b.quantize(d, loc);
    ASSERT_EQ(wa, wb) << "location " << loc;
    if (loc > 8) {  // a Working Memory of 8 locations: older words leave
      for (Vocabulary* v : {&a, &b}) {
        std::multimap<int, int> words;
        for (const auto& [id, w] : v->words()) {
          if (w.references.count(loc - 8)) words.emplace(id, 0);
        }
        v->removeReferences(loc - 8, words);
        for (int id : v->unreferencedWords()) v->removeWord(id);
      }
    }
  }
  EXPECT_GE(a.summary().indexBuilds, 3);
  EXPECT_EQ(a.summary().indexBuilds, b.summary().indexBuilds);
  EXPECT_EQ(a.indexPoints(), b.indexPoints());
}

// memoryUsed() counts the references from a running total (it runs every update): the total must
// follow every way a reference comes and goes, equal to the count over the words at each step.
TEST(Vocabulary, ReferenceCountFollowsEveryChange) {
  Vocabulary v;
  const auto walk = [&v] {
    size_t n = 0;
    for (const auto& entry : v.words()) n += entry.second.references.size();
    return n;
  };
  const cv::Mat d = randomBinary(300, 32, 41);
  const auto ids1 = v.quantize(d, 1);
  v.quantize(d.rowRange(0, 120), 2);  // the same descriptors: the same words, a second location
  ASSERT_EQ(v.referenceCount(), walk());
  EXPECT_EQ(v.referenceCount(), 420u);
  v.addReference(ids1[0], 1, 3);  // one more occurrence: no new reference
  v.addReference(ids1[0], 9, 1);  // another location: one
  EXPECT_EQ(v.referenceCount(), 421u);
  std::multimap<int, int> words2;
  for (int i = 0; i < 120; ++i) words2.emplace(ids1[i], i);
  v.removeReferences(2, words2);
  EXPECT_EQ(v.referenceCount(), walk());
  EXPECT_EQ(v.referenceCount(), 301u);
  const size_t before = v.memoryUsed();
  VisualWord out = v.removeWord(ids1[0]);  // two references leave with it
  EXPECT_EQ(v.referenceCount(), 299u);
  const size_t removed = v.memoryUsed();
  EXPECT_LT(removed, before);
  v.addWord(std::move(out));  // and come back with it
  EXPECT_EQ(v.referenceCount(), 301u);
  EXPECT_EQ(v.referenceCount(), walk());
  // Back above `before`: the word is back, in a new index point, and its old point stays in the
  // index until the next rebuild.
  EXPECT_GT(v.memoryUsed(), before);
  EXPECT_EQ(v.indexPoints(), 301u);
}

// exactWord (the re-quantisation of words retrieved from LTM) is a lookup of the very bytes:
// no index search, a one-bit difference is another descriptor, removed words are gone from it
// and words put back are in it again.
TEST(Vocabulary, ExactWordIsTheSameBytesWithoutSearching) {
  Vocabulary v;
  cv::Mat d = randomBinary(50, 32, 21);
  const auto ids = v.quantize(d, 1);
  const long searched = v.summary().searchedDescriptors;
  EXPECT_EQ(searched, 50);
  for (int i = 0; i < d.rows; ++i) ASSERT_EQ(v.exactWord(d.row(i)), ids[i]) << i;
  cv::Mat flipped = d.row(7).clone();
  flipped.at<uchar>(0, 31) ^= 1;
  EXPECT_EQ(v.exactWord(flipped), 0);
  EXPECT_EQ(v.exactWord(randomBinary(1, 16, 3)), 0);  // another width: nothing
  EXPECT_EQ(v.exactWord(randomFloat(1, 32, 3)), 0);   // another type: nothing
  VisualWord out = v.removeWord(ids[7]);
  EXPECT_EQ(v.exactWord(d.row(7)), 0);
  v.addWord(out);
  EXPECT_EQ(v.exactWord(d.row(7)), ids[7]);
  // Two words of the same bytes (one came back from LTM while the other was made): either.
  VisualWord twin{1000, d.row(9).clone(), {}};
  v.addWord(twin);
  const int found = v.exactWord(d.row(9));
  EXPECT_TRUE(found == ids[9] || found == 1000);
  v.removeWord(found);
  EXPECT_EQ(v.exactWord(d.row(9)), found == 1000 ? ids[9] : 1000);
  EXPECT_EQ(v.summary().searchedDescriptors, searched);  // none of this searched the index
}

TEST(Vocabulary, WordsLeaveAndComeBackWithTheirIds) {
  Vocabulary v;
  cv::Mat d = randomFloat(30, 256, 7);
  auto ids = v.quantize(d, 1);
  std::multimap<int, int> words;
  for (int i = 0; i < d.rows; ++i) words.emplace(ids[i], i);
  v.removeReferences(1, words);
  ASSERT_EQ(v.unreferencedWords().size(), 30u);
  VisualWord out = v.removeWord(ids[5]);
  EXPECT_EQ(out.id, ids[5]);
  EXPECT_EQ(v.findWords(d.row(5))[0], 0);  // gone from the index too
  EXPECT_THROW(v.removeWord(ids[5]), std::out_of_range);
  out.references[9] = 1;
  v.addWord(out);
  EXPECT_EQ(v.findWords(d.row(5))[0], ids[5]);
  EXPECT_EQ(v.word(ids[5])->references.at(9), 1);
  EXPECT_THROW(v.addWord(out), std::invalid_argument);  // id in use
  // New words continue after the highest id.
  auto next = v.quantize(randomFloat(1, 256, 8), 2);
  EXPECT_EQ(next[0], 31);
}

TEST(Vocabulary, FixedVocabularyGivesTheNearestWord) {
  VocabularyOptions o;
  o.incrementalDictionary = false;
  Vocabulary v(o);
  v.quantize((cv::Mat_<float>(2, 2) << 0.f, 0.f, 1.f, 0.f), 1);
  auto ids = v.quantize((cv::Mat_<float>(1, 2) << 0.6f, 0.f), 2);
  EXPECT_EQ(ids[0], 2);
  EXPECT_EQ(v.size(), 2u);
}

TEST(Vocabulary, RejectsDescriptorsThatDoNotFit) {
  Vocabulary v;
  v.quantize(randomFloat(3, 8, 1), 1);
  EXPECT_THROW(v.quantize(randomFloat(3, 9, 1), 2), std::invalid_argument);
  EXPECT_THROW(v.quantize(randomBinary(3, 8, 1), 2), std::invalid_argument);
  cv::Mat doubles(2, 8, CV_64F, cv::Scalar(0));
  EXPECT_THROW(v.quantize(doubles, 2), std::invalid_argument);
  VocabularyOptions bad;
  bad.nndrRatio = 0.f;
  EXPECT_FALSE(bad.IsValid());
  EXPECT_THROW(VocabularyOptions::fromParameters({{"Kp/NndrRatio", "0"}}), std::exception);
}

}  // namespace
}  // namespace rtabmap::vocabulary
