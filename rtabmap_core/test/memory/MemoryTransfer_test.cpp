// Transfer to and retrieval from the LTM (T-RO 2013, Algorithms 3 and 4).
#include <gtest/gtest.h>

#include <set>

#include "MemoryTestPlaces.h"
#include "common/TestData.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Memory.h"

namespace rtabmap::memory {
namespace {

using test::view;
using test::WithLtm;

TEST(MemoryTransfer, LowestWeightThenOldestFirst) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  // Exact nearest neighbours: the word counts below assume no descriptor of one place
  // quantises to another's word, which the kd-trees' approximate search (built from
  // std::random_device in Debian's FLANN) gets wrong in about one run in three.
  o.vocabulary.nnStrategy = vocabulary::NNStrategy::kLinear;
  Memory m(o, &ltm.database);
  m.addLocation(view(1));
  m.addLocation(view(2));
  m.addLocation(view(2, 1));  // 2 gets weight 1
  for (int p = 3; p <= 6; ++p) m.addLocation(view(p));
  // WM: 1, 2 (weight 1), 4, 5, 6 (ids: views 3..6 are 4..7; 7 in STM).
  ASSERT_EQ(m.wm().size(), 5u);
  TransferResult r = m.transfer({}, 0, 2, false);
  EXPECT_EQ(r.transferred, (std::vector<int>{1, 4, 5}));  // weight 0 by age; 2 (weight 1) stays
  EXPECT_EQ(r.wordsRemoved, 300);
  EXPECT_EQ(m.wm().size(), 2u);
  EXPECT_EQ(m.vocabulary().size(), 300u);  // 2, 6 and 7's words
  m.joinLtmWriter();
  EXPECT_TRUE(ltm.database.loadNode(1).has_value());
}

TEST(MemoryTransfer, ImmuneAndRecentLocationsStay) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.5f;
  Memory m(o, &ltm.database);
  for (int p = 1; p <= 7; ++p) m.addLocation(view(p));
  // WM 1..6, no loop closure yet: the newest half (4, 5, 6) is recent.
  TransferResult r = m.transfer({1}, 1000, 0, false);
  EXPECT_EQ(r.transferred, (std::vector<int>{2, 3}));
  EXPECT_TRUE(m.wm().count(1) && m.wm().count(4) && m.wm().count(6));
}

TEST(MemoryTransfer, AtLeastOneAndWordsTarget) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  Memory m(o, &ltm.database);
  for (int p = 1; p <= 6; ++p) m.addLocation(view(p));
  EXPECT_EQ(m.transfer({}, 0, 0, true).transferred.size(), 1u);
  EXPECT_EQ(m.transfer({}, 150, 0, false).transferred.size(), 2u);  // 100 words each
  EXPECT_TRUE(m.transfer({}, 0, 0, false).transferred.empty());
}

TEST(MemoryTransfer, RetrievalBringsBackNeighboursInTimeFirstWithTheirWords) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  o.maxRetrieved = 2;
  Memory m(o, &ltm.database);
  for (int p = 1; p <= 8; ++p) m.addLocation(view(p));
  m.addLoopClosure(Link(8, 3, Link::kGlobalClosure, Transform::Identity()));
  const std::multimap<int, int> words4 = m.signature(4)->getWords();
  // Transfer everything but 5 (the future hypothesis) and the STM.
  TransferResult t = m.transfer({5}, 100000, 0, false);
  ASSERT_FALSE(m.inRam(4));
  ASSERT_FALSE(m.inRam(3));
  EXPECT_EQ(m.vocabulary().size(), 200u);  // words of 5 and 8
  // From 5: depth 1 = 4 and 6 (time); then 3 (time, via 4) and 7...
  std::vector<int> back = m.retrieve(5);
  EXPECT_EQ(back, (std::vector<int>{4, 6}));
  EXPECT_EQ(m.signature(4)->getWords(), words4);  // the same words back
  EXPECT_EQ(m.vocabulary().size(), 400u);
  EXPECT_EQ(m.vocabulary().word(words4.begin()->first)->references.count(4), 1u);
  // A revisit of place 4 finds it again.
  AddResult r = m.addLocation(view(4, 1));
  auto l = m.computeLikelihood(r.id);
  EXPECT_GT(l.at(4), 0.f);
  for (const auto& [id, score] : l) {
    if (id != 4) {
      EXPECT_FLOAT_EQ(score, 0.f) << id;
    }
  }
  // Next retrieval: depth 2 from 5 is 3 and 7; 3 has a loop closure with 8 (space) but
  // neighbours in time of the frontier come first.
  back = m.retrieve(5);
  EXPECT_EQ(back, (std::vector<int>{3, 7}));
}

// Mem/RawDescriptorsKept false: locations hold word ids, keypoints and 3D, not descriptors, in
// RAM and in the LTM; the vocabulary keeps each word's own descriptor, so words leave it and come
// back on retrieval as with descriptors, and a revisit is still recognised.
TEST(MemoryTransfer, WithoutRawDescriptorsTheWordsStillLeaveAndComeBack) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  o.rawDescriptorsKept = false;
  Memory m(o, &ltm.database);
  for (int p = 1; p <= 6; ++p) m.addLocation(view(p));
  const Signature* kept = m.signature(2);
  ASSERT_EQ(kept->getWords().size(), 100u);
  EXPECT_EQ(kept->getWordsKpts().size(), 100u);
  EXPECT_TRUE(kept->getWordsDescriptors().empty());
  EXPECT_EQ(m.vocabulary().word(kept->getWords().begin()->first)->descriptor.cols, 64);
  const std::multimap<int, int> words2 = kept->getWords();
  m.transfer({3}, 100000, 0, false);
  ASSERT_FALSE(m.inRam(2));
  EXPECT_EQ(m.vocabulary().size(), 200u);  // words of 3 and 6
  const std::optional<Signature> saved = ltm.database.loadNode(2);
  ASSERT_TRUE(saved.has_value());
  EXPECT_EQ(saved->getWords(), words2);
  EXPECT_TRUE(saved->getWordsDescriptors().empty());
  EXPECT_EQ(m.retrieve(3), (std::vector<int>{2, 4}));
  EXPECT_EQ(m.signature(2)->getWords(), words2);
  EXPECT_EQ(m.vocabulary().size(), 400u);
  const AddResult r = m.addLocation(view(2, 1));
  const std::map<int, float> l = m.computeLikelihood(r.id);
  EXPECT_GT(l.at(2), 0.f);
  for (const auto& [id, score] : l) {
    if (id != 2) {
      EXPECT_FLOAT_EQ(score, 0.f) << id;
    }
  }
  // The default keeps one descriptor row per word.
  WithLtm other;
  Memory withDescriptors(MemoryOptions(), &other.database);
  const int id = withDescriptors.addLocation(view(1)).id;
  EXPECT_EQ(withDescriptors.signature(id)->getWordsDescriptors().rows, 100);
}

TEST(MemoryTransfer, ChangedWordsAreReusedOnRetrieval) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 0;
  o.recentWmRatio = 0.f;
  Memory m(o, &ltm.database);
  m.addLocation(view(1));
  m.addLocation(view(2));
  const int firstWord = m.signature(1)->getWords().begin()->first;
  m.transfer({2}, 0, 0, true);  // 1 leaves with its words
  ASSERT_FALSE(m.inRam(1));
  // The exact same descriptors come back as new words of location 3.
  m.addLocation(view(1));
  std::vector<int> back = m.retrieve(2);
  ASSERT_EQ(back, (std::vector<int>{1}));
  // Location 1's words were re-quantised to location 3's identical words, not duplicated.
  EXPECT_EQ(m.vocabulary().size(), 200u);
  EXPECT_EQ(m.vocabulary().word(firstWord), nullptr);
}

// Mem/RehearsalIdUpdatedToNewOne with Mem/STMSize 0: the previous location entered WM, and so
// the LTM, the moment it was added. Rehearsal must not drop it from RAM behind the database's
// back (the LTM would keep it, still linked, and a reload would bring back a branch the map no
// longer has): the saved location keeps its id and the new view merges into it.
TEST(MemoryTransfer, RehearsalKeepsAnAlreadySavedLocation) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 0;
  o.rehearsalIdUpdatedToNewOne = true;
  Memory m(o, &ltm.database);
  m.addLocation(view(1));
  m.addLocation(view(2));
  m.joinLtmWriter();
  ASSERT_TRUE(ltm.database.loadNode(2).has_value());  // saved on entering WM
  const AddResult again = m.addLocation(view(2, 1));
  ASSERT_TRUE(again.merged);
  EXPECT_EQ(again.id, 2);
  EXPECT_EQ(again.mergedWith, 3);
  ASSERT_NE(m.signature(2), nullptr);
  EXPECT_EQ(m.signature(2)->weight(), 1);
  EXPECT_EQ(m.signature(3), nullptr);
  m.saveAll();
  EXPECT_EQ(ltm.database.nodeIds(), (std::vector<int>{1, 2}));
  EXPECT_EQ(ltm.database.loadNode(2)->weight(), 1);
  const std::multimap<int, Link> links1 = ltm.database.loadLinks(1);
  ASSERT_EQ(links1.size(), 1u);
  EXPECT_EQ(links1.begin()->first, 2);
}

// The location rehearsal removes may hold a loop closure to one that went to the LTM since:
// the kept location takes the link over, in RAM and in the LTM, which must not keep a link to a
// location it will never have.
TEST(MemoryTransfer, RehearsalMovesALinkToTheLtm) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 2;
  o.recentWmRatio = 0.f;
  o.rehearsalIdUpdatedToNewOne = true;
  Memory m(o, &ltm.database);
  for (int p = 1; p <= 4; ++p) m.addLocation(view(p));
  m.addLoopClosure(Link(4, 1, Link::kGlobalClosure, Transform::Identity()));
  m.transfer({2, 3}, 0, 0, true);  // 1 leaves (4 is in STM)
  ASSERT_FALSE(m.inRam(1));
  const AddResult again = m.addLocation(view(4, 1));
  ASSERT_TRUE(again.merged);
  ASSERT_EQ(again.id, 5);  // 4 was not saved yet: the new id stays
  EXPECT_TRUE(m.signature(5)->hasLink(1, Link::kGlobalClosure));
  EXPECT_TRUE(m.signature(5)->hasLink(3, Link::kNeighbor));
  m.saveAll();
  const std::multimap<int, Link> links1 = ltm.database.loadLinks(1);
  std::set<int> ends;
  for (const auto& [to, link] : links1) ends.insert(to);
  EXPECT_EQ(ends, (std::set<int>{2, 5}));
  EXPECT_FALSE(ltm.database.loadNode(4).has_value());
}

// Retrieval puts words back by id or by their exact bytes: it searches the vocabulary's index
// for none of them (one FLANN query per word was most of Reactivation on long runs).
TEST(MemoryTransfer, RetrievalDoesNotSearchTheVocabulary) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 0;
  o.recentWmRatio = 0.f;
  Memory m(o, &ltm.database);
  m.addLocation(view(1));
  m.addLocation(view(2));
  m.addLocation(view(3));
  m.transfer({3}, 0, 0, true);
  m.transfer({3}, 0, 0, true);
  ASSERT_FALSE(m.inRam(1));
  ASSERT_FALSE(m.inRam(2));
  m.addLocation(view(1));  // location 1's descriptors come back as new words of location 4
  const long searched = m.vocabulary().summary().searchedDescriptors;
  const size_t words = m.vocabulary().size();
  const std::vector<int> back = m.retrieveIds({1, 2});
  ASSERT_EQ(back, (std::vector<int>{1, 2}));
  EXPECT_EQ(m.vocabulary().summary().searchedDescriptors, searched);
  EXPECT_EQ(m.vocabulary().size(), words + 100);  // 2's words back; 1's are 4's
  for (const auto& [word, keypoint] : m.signature(1)->getWords()) {
    (void)keypoint;
    ASSERT_NE(m.vocabulary().word(word), nullptr);
    EXPECT_TRUE(m.vocabulary().word(word)->references.count(4)) << word;  // shared with 4
    EXPECT_TRUE(m.vocabulary().word(word)->references.count(1)) << word;
  }
}

// T-RO 2013 memory management bounds RAM by the Working Memory: what the vocabulary keeps per
// word (the saved-to-LTM mark included) must leave with the words of transferred locations,
// however many locations the map has.
TEST(MemoryTransfer, WordsOfTransferredLocationsLeaveTheVocabularyAndItsBookkeeping) {
  WithLtm ltm;
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  Memory m(o, &ltm.database);
  for (int p = 1; p <= 60; ++p) {
    m.addLocation(view(p));  // 100 words of its own each
    if (m.wm().size() > 5) m.transfer({}, 0, 5, false);
    // WM (5) + STM (1) locations hold every word in RAM; none of the transferred ones do.
    ASSERT_LE(m.vocabulary().size(), 600u) << p;
    ASSERT_LE(m.savedWordsTracked(), m.vocabulary().size()) << p;
  }
  // Random descriptors: the approximate search may quantise one onto an older word now and then.
  const size_t words = m.vocabulary().size(), saved = m.savedWordsTracked();
  EXPECT_GE(words, 590u);
  EXPECT_NEAR(double(words - saved), 100.0, 2.0);  // the STM location's words are not saved yet
  // A retrieved location's words come back, marked saved: not written twice.
  const std::vector<int> back = m.retrieveIds({1});
  ASSERT_EQ(back, (std::vector<int>{1}));
  EXPECT_NEAR(double(m.vocabulary().size() - words), 100.0, 2.0);
  EXPECT_EQ(m.savedWordsTracked() - saved, m.vocabulary().size() - words);
}

TEST(MemoryTransfer, WithoutLtmTransferIsAnError) {
  Memory m(MemoryOptions{});
  EXPECT_THROW(m.transfer({}, 1, 0, true), std::logic_error);
  EXPECT_THROW(m.retrieve(1), std::logic_error);
}

// Disk full (found through the node, test/fault_disk_full.test: the SLAM node died of the
// exception): locations the LTM refuses stay in RAM, mapping goes on, transfer keeps them,
// and everything saved before the failure is in the file.
TEST(MemoryTransfer, FullDiskKeepsRefusedLocationsInRam) {
  rtabmap::test::TempDir dir;
  db::DatabaseOptions full;
  full.maxPageCount = 60;  // 240 KiB with 4 KiB pages: fills after a few locations
  full.maxBatchNodes = 1;
  db::Database database(dir.file("full.db"), full);
  MemoryOptions o;
  o.stmSize = 1;
  o.recentWmRatio = 0.f;
  Memory m(o, &database);
  int last = 0;
  for (int p = 1; p <= 200 && !database.writerStatus().failed; ++p) {
    ASSERT_NO_THROW(m.addLocation(view(p)));
    last = m.lastLocationId();
    try {
      database.flush();  // commits what is queued, or throws once the page limit is hit
    } catch (const DatabaseError&) {
    }
  }
  ASSERT_TRUE(database.writerStatus().failed) << "the page limit was never reached";
  const int lastDurable = database.writerStatus().lastDurableNodeId;
  ASSERT_GT(lastDurable, 0);
  for (int p = 201; p <= 210; ++p) {  // mapping goes on; each update starts by joining the writer
    ASSERT_NO_THROW(m.joinLtmWriter());
    ASSERT_NO_THROW(m.addLocation(view(p)));
  }
  last = m.lastLocationId();

  // Queued before the failure: still readable from the writer's queue. Refused: in RAM only.
  const int lastQueued = lastDurable + static_cast<int>(database.writerStatus().pendingNodes);
  ASSERT_LT(lastQueued, last - 1);
  const TransferResult r = m.transfer({}, 0, 1, false);
  EXPECT_FALSE(r.transferred.empty());
  for (int id : r.transferred) EXPECT_LE(id, lastQueued) << "transferred a location the LTM refused";
  for (int id = 1; id <= last; ++id) {
    const bool inRam = m.wm().count(id) || m.stm().count(id);
    EXPECT_TRUE(inRam || database.loadNode(id).has_value()) << "location " << id << " lost";
    if (id > lastQueued) {
      EXPECT_TRUE(inRam) << id;
    }
  }
  EXPECT_THROW(m.saveAll(), DatabaseError);  // the end still tells the loss
}

}  // namespace
}  // namespace rtabmap::memory
