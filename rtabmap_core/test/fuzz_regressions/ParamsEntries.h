#pragma once
// Fuzz entries of the parameter parsers: INI text, --Group/Name arguments, and the serialised
// parameters a database stores per session (outside data too: any database may be opened).
#include <vector>

#include "FuzzEntry.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap::fuzz {

// INI text, then what the INI gave written and read back: it must survive the round trip.
inline Outcome fuzzParamsIni(const uint8_t* data, size_t size) {
  return guarded([&] {
    const ParametersMap parsed = Parameters::parseIni(asText(data, size), "fuzz.ini");
    if (Parameters::parseIni(Parameters::formatIni(parsed), "roundtrip.ini") != parsed) {
      __builtin_trap();  // an accepted file that does not round-trip is a bug
    }
  });
}

// The bytes split on NUL into argv entries (as a shell would hand them over).
inline Outcome fuzzParamsArgs(const uint8_t* data, size_t size) {
  std::vector<std::string> args(1);
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == '\0') args.emplace_back();
    else args.back().push_back(static_cast<char>(data[i]));
  }
  return guarded([&] { Parameters::parseArguments(args); });
}

// Session parameters as stored in a database: strict and lenient readers.
inline Outcome fuzzParamsSerialized(const uint8_t* data, size_t size) {
  const std::string text = asText(data, size);
  const Outcome lenient = guarded([&] {
    const DeserializedParameters p = Parameters::deserializeLenient(text);
    if (Parameters::deserialize(Parameters::serialize(p.known)) != p.known) __builtin_trap();
  });
  const Outcome strict = guarded([&] { Parameters::deserialize(text); });
  return lenient == Outcome::kAccepted && strict == Outcome::kAccepted ? Outcome::kAccepted
                                                                       : Outcome::kRejected;
}

}  // namespace rtabmap::fuzz
