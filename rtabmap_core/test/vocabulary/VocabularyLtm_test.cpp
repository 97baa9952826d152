// The vocabulary's words go to the long-term memory and come back unchanged (T-RO 2013,
// transfer and retrieval): the database keeps id and descriptor; the references are rebuilt
// from the retrieved locations' words.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "common/TestData.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/vocabulary/Vocabulary.h"

namespace rtabmap::vocabulary {
namespace {

template <int Type>
cv::Mat randomRows(int rows, int cols, uint64_t seed) {
  cv::Mat m(rows, cols, Type);
  cv::RNG rng(seed);
  if (Type == CV_8U) {
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  } else {
    rng.fill(m, cv::RNG::UNIFORM, 0.f, 1.f);
  }
  return m;
}

template <int Type>
void roundTrip(int cols) {
  test::TempDir dir;
  Vocabulary v;
  cv::Mat d = randomRows<Type>(80, cols, 11);
  auto ids = v.quantize(d, 1);
  ASSERT_EQ(v.size(), 80u);

  std::vector<db::StoredWord> stored;
  std::multimap<int, int> words;
  for (int i = 0; i < d.rows; ++i) words.emplace(ids[i], i);
  v.removeReferences(1, words);
  for (int id : v.unreferencedWords()) {
    VisualWord w = v.removeWord(id);
    stored.push_back({w.id, w.descriptor});
  }
  EXPECT_EQ(v.size(), 0u);
  {
    db::Database database(dir.path() + "/ltm.db");
    database.saveWords(stored);
    database.flush();
  }
  db::Database database(dir.path() + "/ltm.db");
  std::vector<int> wanted(ids.begin(), ids.end());
  auto loaded = database.loadWords(wanted);
  ASSERT_EQ(loaded.size(), 80u);
  std::vector<VisualWord> back;
  for (auto& s : loaded) back.push_back({s.id, s.descriptor, {{1, 1}}});
  v.addWords(std::move(back));
  EXPECT_EQ(v.findWords(d), ids);  // every descriptor finds its own word again
  EXPECT_EQ(v.word(ids[3])->references.at(1), 1);
}

TEST(VocabularyLtm, FloatWordsRoundTrip) { roundTrip<CV_32F>(64); }
TEST(VocabularyLtm, BinaryWordsRoundTrip) { roundTrip<CV_8U>(32); }

}  // namespace
}  // namespace rtabmap::vocabulary
