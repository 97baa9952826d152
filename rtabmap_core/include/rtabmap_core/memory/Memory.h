#pragma once
// Memory management of RTAB-Map (T-RO 2013, sections III-A to III-F, Algorithms 1-4): where the
// locations live and how they move.
//
//   Short-Term Memory (STM): the Mem/STMSize newest locations. A new location is compared with
//     the previous one (eq. 1); over Mem/RehearsalSimilarity they are merged and the weight grows
//     (rehearsal). STM locations are not loop-closure candidates (they look like the present).
//   Working Memory (WM): the candidates of loop-closure detection, in RAM.
//   Long-Term Memory (LTM): the SQLite database. Locations move there when an update takes too
//     long (transfer: the lowest weight, then the oldest, first) and come back when a neighbour
//     is the highest loop-closure hypothesis (retrieval).
//
// The vocabulary holds the words of the locations in RAM (STM + WM) only: words without any
// reference leave with the last location that used them and come back with it.
//
// Saving: a location is written to the LTM when it leaves STM (so a crash loses at most the
// STM), again when it is transferred if it changed, and on close. Writes go through the
// database's writer thread; Algorithm 1 joins it at the next update (Database::flush).
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "rtabmap_core/geometry/SensorData.h"
#include "rtabmap_core/geometry/Transform.h"
#include "rtabmap_core/memory/Link.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_core/vocabulary/Vocabulary.h"

namespace rtabmap::db {
class Database;
}

namespace rtabmap::memory {

struct MemoryOptions {
  int stmSize = 10;                        // Mem/STMSize
  float rehearsalSimilarity = 0.6f;        // Mem/RehearsalSimilarity (>= 1: no merging)
  float recentWmRatio = 0.2f;              // Mem/RecentWmRatio
  bool transferSortingByWeightId = false;  // Mem/TransferSortingByWeightId
  bool rehearsalIdUpdatedToNewOne = false; // Mem/RehearsalIdUpdatedToNewOne
  bool badSignaturesIgnored = false;       // Mem/BadSignaturesIgnored
  int maxFeatures = 500;                   // Kp/MaxFeatures (0: all; < 0: no words)
  float badSignRatio = 0.5f;               // Kp/BadSignRatio
  bool tfIdf = true;                       // Kp/TfIdfLikelihoodUsed
  int maxRetrieved = 2;                    // Rtabmap/MaxRetrieved
  // Graph range (links) of the neighbourhood of a hypothesis: the Bayes filter's transition
  // range (Bayes/PredictionLC size - 2). Retrieval searches it.
  int neighborhoodDepth = 16;
  // Mem/IncrementalMemory: false = localization on a saved map: nothing is ever written to the
  // LTM (locations leaving RAM were loaded from it and are unchanged there).
  bool incremental = true;
  // Metric SLAM (locations with odometry poses): two consecutive locations farther apart than
  // RGBD/LinearUpdate or RGBD/AngularUpdate are both kept, whatever their similarity (the
  // graph needs both poses); rehearsal then only moves the weight to the newer one, unless
  // Mem/RehearsalWeightIgnoredWhileMoving.
  float stillLinear = 0.0f;   // RGBD/LinearUpdate (m)
  float stillAngular = 0.0f;  // RGBD/AngularUpdate (rad)
  bool rehearsalWeightIgnoredWhileMoving = false;
  // Mem/UseOdomGravity: a new location's gravity link (GravityLink.h) takes its orientation
  // from the odometry pose rather than from the frame's IMU.
  bool useOdomGravity = false;
  // Mem/ReduceGraph: a location that leaves STM with a loop closure to an older location is
  // merged into it (MemoryReduceGraph.cpp), so revisiting a place does not grow the graph.
  // Mapping only (Mem/IncrementalMemory).
  bool reduceGraph = false;
  // Mem/RawDescriptorsKept: false = a location keeps its words' keypoints and 3D points, not
  // their descriptors (the vocabulary has each word's own); registration then pairs by word id.
  bool rawDescriptorsKept = true;
  vocabulary::VocabularyOptions vocabulary;

  static MemoryOptions fromParameters(const ParametersMap& parameters);
  bool IsValid(std::string* why = nullptr) const;
};

// What a new location is made of: features already extracted from its image (Algorithm 2
// keeps the Kp/MaxFeatures strongest by response) and the data and pose it carries.
struct LocationInput {
  int id = 0;                          // its id (Mem/GenerateIds false), above every other; 0: the next one
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;                 // one row per keypoint
  std::vector<cv::Point3f> points3D;   // optional, one per keypoint
  SensorData data;
  Transform pose;                      // odometry pose (null for appearance only)
  // Information matrix of the neighbour link from the previous location (inverse of the
  // odometry covariance of the motion between them).
  Link::InfMatrix odomInformation = Link::InfMatrix::Identity();
  double stamp = 0.0;
  int mapId = 0;
  // Rtabmap/CreateIntermediateNodes: a pose of the trajectory between two updates. No words
  // (keypoints and descriptors are ignored), weight -1 (Signature::isIntermediate), never
  // rehearsed nor a loop-closure candidate; linked to the previous location like any other.
  bool intermediate = false;
};

struct AddResult {
  int id = 0;             // the location that now holds the new data (0: dropped bad signature)
  bool merged = false;    // rehearsal merged it with the previous location
  int mergedWith = 0;     // the other location of the merge (removed from memory)
  float rehearsalSimilarity = 0.0f;
  bool moving = false;    // metric: farther than the still thresholds from the previous location
  bool badSignature = false;
  int words = 0;
  int newWords = 0;
  // Mem/ReduceGraph: the locations that left STM this update merged into an older one, as
  // (location, the location it was merged into). They are gone from memory and never saved.
  std::vector<std::pair<int, int>> reduced;
  std::set<int> relinked;  // the locations whose links the reductions changed
};

struct TransferResult {
  std::vector<int> transferred;  // in transfer order
  int wordsRemoved = 0;          // words that left the vocabulary for the LTM
};

struct MemorySummary {
  int stmSize = 0, wmSize = 0, vocabularySize = 0, lastLocationId = 0;  // sizes without intermediate nodes
  int intermediatesInRam = 0;
  int lastGlobalLoopClosureId = 0;
  int reducedTotal = 0;  // Mem/ReduceGraph
  int transferredTotal = 0, retrievedTotal = 0;
};

class Memory {
 public:
  // ltm may be null: no long-term memory (transfer and retrieval then throw).
  explicit Memory(const MemoryOptions& options, db::Database* ltm = nullptr);
  ~Memory();
  Memory(const Memory&) = delete;
  Memory& operator=(const Memory&) = delete;

  // Algorithm 2 + STM update (III-C): creates the location, quantises its words, links it to
  // the previous one, merges it with it on rehearsal, moves the STM overflow to WM.
  AddResult addLocation(const LocationInput& input);

  // Raw likelihood of a location against every WM location that is not a bad signature (TF-IDF
  // or eq. 1 per Kp/TfIdfLikelihoodUsed), through the inverted index.
  std::map<int, float> computeLikelihood(int id) const;
  // The same as (location id, score) pairs sorted by id: what the loop-closure detector uses.
  std::vector<std::pair<int, float>> likelihoodScores(int id) const;
  // Graph neighbourhood in RAM (STM + WM): id -> link distance, within maxDepth. For the Bayes
  // filter's transition model. Intermediate nodes are passed through at no distance and left
  // out: the neighbourhood is of locations, however many intermediate nodes lie between them.
  std::map<int, int> neighbors(int id, int maxDepth) const;

  // An accepted loop closure between the new location and an older one (both in RAM): the link
  // on both ends and the weight rule of the original: the newer location takes the sum of both
  // weights, the older one 0 (it may be transferred; the place lives on in the newer one).
  void addLoopClosure(const Link& link);
  // Any other link between two locations in RAM (proximity, user, refined neighbour), on both
  // ends, replacing a link of the same type between them. No weight change.
  void addLink(const Link& link);
  // Removes the links of this type (kUndef: all) between two locations (those in RAM; the LTM
  // copy of a saved location is updated too). Returns false if neither is in RAM.
  bool removeLink(int from, int to, Link::Type type);
  // The newest location leaves memory without a trace (metric SLAM: the robot did not move
  // and rehearsal did not merge it; localization: the location was only used to localise):
  // its links, its words, its place in STM. Throws std::logic_error for a location that is not
  // the last one added or that is already saved.
  void removeLastLocation();
  // Loads these LTM locations into WM (local retrieval near the robot, path planning, the WM
  // of the previous session at start), re-quantising their words. Ids already in RAM or
  // unknown are skipped. Returns the ids loaded.
  std::vector<int> retrieveIds(const std::vector<int>& ids);
  // Label of a location in RAM (saved again when it leaves) or in the LTM. False if unknown.
  bool setLabel(int id, const std::string& label);
  // User data of a location in RAM not saved yet (it is written when the location leaves), if
  // it has none: user data given with the input is never overwritten. False, with why, if not.
  bool setUserData(int id, const cv::Mat& data, std::string* why);

  // Algorithm 3: brings back from LTM at most Rtabmap/MaxRetrieved locations near `id` (within
  // the neighbourhood range, breadth first, neighbours in time before neighbours in space), their
  // words re-quantised against the current vocabulary. Intermediate nodes on the way are passed
  // through at no distance and come back too, uncounted (the graph in RAM stays connected).
  // Returns the retrieved ids.
  std::vector<int> retrieve(int id);

  // Algorithm 4: moves WM locations to LTM, the lowest weight first, then the oldest (time in
  // WM, or id with Mem/TransferSortingByWeightId), until at least `minWordsRemoved` words have left
  // the vocabulary and WM holds at most `maxWmSize` locations (0: no size limit); at least one
  // location when `atLeastOne`. Never `immune` locations, nor the recent part of WM (the
  // locations newer than the last loop closure, up to Mem/RecentWmRatio of WM). Intermediate
  // nodes are not candidates nor counted: they leave with the location that follows them.
  TransferResult transfer(const std::set<int>& immune, int minWordsRemoved, int maxWmSize, bool atLeastOne);

  // Writes every location in RAM to the LTM and waits for the writer.
  void saveAll();
  // Joins the database writer (Algorithm 1's "join trash thread").
  void joinLtmWriter();

  const Signature* signature(int id) const;
  // For caches kept in a location's sensor data (uncompressed scan, extracted features) by
  // registration: the memory does not see changes made through it, so never change the map
  // (links, weight, words, label) this way. Null if not in RAM.
  Signature* mutableSignature(int id);
  const std::set<int>& stm() const { return stm_; }
  // WM ids with the update counter when each entered WM (its age for transfer).
  const std::map<int, long>& wm() const { return wm_; }
  // WM without its intermediate nodes: the loop-closure candidates' side of WM, what
  // Rtabmap/MemoryThr bounds.
  int wmLocations() const;
  // Intermediate nodes in RAM (STM + WM), and whether a node (in RAM or the LTM) is one.
  int intermediatesInRam() const { return intermediatesInRam_; }
  bool isIntermediate(int id) const;
  bool inRam(int id) const { return signatures_.count(id) != 0; }
  // Bytes the locations in RAM (STM and WM) hold, estimated (Signature::memoryUsed).
  size_t locationsMemoryUsed() const;
  const vocabulary::Vocabulary& vocabulary() const { return vocabulary_; }
  // Words of the vocabulary known to be in the LTM already (not written again with the next
  // location that has them). Only words in RAM are tracked: a word that leaves the vocabulary
  // leaves this set, so its size is bounded by the vocabulary's (Working Memory), not the map's.
  size_t savedWordsTracked() const { return savedWords_.size(); }
  const MemoryOptions& options() const { return options_; }
  MemorySummary summary() const;
  int lastLocationId() const { return lastId_; }

 private:
  Signature& at(int id);
  AddResult addIntermediate(const LocationInput& in, int id);
  // The neighbour link from the previous location to `fresh` (same map); its similarity and motion.
  int linkToPrevious(Signature& fresh, const LocationInput& in, AddResult& result);
  // The intermediate nodes in WM right before location `id` (its neighbour-link chain back to
  // the previous location), newest first: they leave WM with it.
  std::vector<int> intermediatesBefore(int id) const;
  void insertInRam(Signature&& s);
  void eraseFromRam(int id);
  void selectStrongest(LocationInput& in) const;
  bool isBadSignature(int words) const;
  void rehearse(Signature& previous, Signature& fresh, AddResult& result);
  void moveStmOverflowToWm(AddResult& result);
  // Mem/ReduceGraph (MemoryReduceGraph.cpp): the older location a location leaving STM is merged
  // into (0: it stays), and the merge.
  int reductionTarget(const Signature& s) const;
  void reduce(int id, int into, std::set<int>& relinked);
  void saveToLtm(Signature& s);
  // Drops the location's references; words left without any leave the vocabulary. Returns how many.
  int removeFromVocabulary(int id, const std::multimap<int, int>& words);
  std::vector<int> transferCandidates(const std::set<int>& immune) const;
  std::set<int> recentWm() const;
  void requantize(std::vector<Signature>& retrieved);
  void rehearseWhileMoving(Signature& previous, Signature& fresh);
  bool isMoving(const Signature& previous, const Signature& fresh) const;

  MemoryOptions options_;
  db::Database* ltm_;
  vocabulary::Vocabulary vocabulary_;
  std::unordered_map<int, Signature> signatures_;  // STM + WM
  std::set<int> stm_;
  std::map<int, long> wm_;
  std::unordered_set<int> savedWords_;  // words of the vocabulary already in the LTM
  long updateCounter_ = 0;
  int lastId_ = 0;
  int previousId_ = 0;  // location of the previous update (neighbour link, rehearsal)
  int previousOfLast_ = 0;  // previousId_ when the last location was added (removeLastLocation)
  int lastGlobalLoopClosureId_ = 0;
  double wordsSum_ = 0.0;  // for the average words per location (bad signatures)
  long wordsLocations_ = 0;
  int transferredTotal_ = 0, retrievedTotal_ = 0, reducedTotal_ = 0;
  // Every intermediate node's id, in RAM or the LTM (this session's and the database's),
  // ascending: retrieval passes through them before loading them. 4 bytes a node.
  std::vector<int> intermediateIds_;
  int intermediatesInRam_ = 0;
};

}  // namespace rtabmap::memory
