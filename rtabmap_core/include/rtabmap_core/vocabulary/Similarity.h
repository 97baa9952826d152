#pragma once
// Scores between the words of a new location and the locations of the vocabulary's inverted
// index: the raw likelihoods the Bayes filter adjusts (bayes/Likelihood.h).
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rtabmap_core/vocabulary/Vocabulary.h"

namespace rtabmap::vocabulary {

// Word id -> occurrences, from Signature::getWords() (word id -> keypoint index).
std::map<int, int> wordCounts(const std::multimap<int, int>& words);

// T-RO 2013 eq. 1: s = N_pair / max(N_a, N_b), with N_pair the matched word pairs (a word seen
// m times in one location and n times in the other makes min(m, n) pairs) and N the word
// counts. 0 when either location has no word. Also the rehearsal similarity (Mem/RehearsalSimilarity).
float similarity(const std::multimap<int, int>& wordsA, const std::multimap<int, int>& wordsB);

// Raw likelihood of the new location's words against each candidate location, through the
// inverted index, so the cost is the number of references of the new location's words, not the
// number of candidates. candidates: location id -> its total word count; only they get a score
// (locations sharing no word get 0).
//   tfIdf = true (Kp/TfIdfLikelihoodUsed): score_i = sum over words w of the new location of
//     (n_wi / n_i) * log10(N / n_w), with n_wi the occurrences of w in i, n_i the words of i,
//     n_w the locations referencing w and N = totalLocations (locations in the vocabulary's
//     references, i.e. in Working Memory and STM).
//   tfIdf = false: eq. 1 against each candidate.
std::map<int, float> computeLikelihood(const Vocabulary& vocabulary, const std::multimap<int, int>& newWords,
                                       const std::unordered_map<int, int>& candidates, int totalLocations,
                                       bool tfIdf);
// The same on flat lists (the loop-closure path: no tree of 20,000 nodes per update):
// candidates (location id, word count) sorted by id with distinct ids; one score per
// candidate, in the same order.
std::vector<std::pair<int, float>> computeLikelihoodScores(const Vocabulary& vocabulary,
                                                           const std::multimap<int, int>& newWords,
                                                           const std::vector<std::pair<int, int>>& candidates,
                                                           int totalLocations, bool tfIdf);

}  // namespace rtabmap::vocabulary
