#pragma once
// "Did you mean ...?" for misspelled parameter keys and command-line options.
#include <cstddef>
#include <string>
#include <vector>

namespace rtabmap {

// Levenshtein distance between a and b, ignoring ASCII case.
std::size_t editDistanceIgnoringCase(const std::string& a, const std::string& b);
// The candidate nearest to word by editDistanceIgnoringCase (first one on ties); "" if none.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace rtabmap
