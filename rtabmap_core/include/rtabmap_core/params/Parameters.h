#pragma once
// Every core parameter of RTAB-Map, declared once in params/groups/<Group>.def with its key
// "Group/Name", type, default, accepted values and description (see ParameterList.def).
//
// From those declarations this header generates, for each parameter:
//   Parameters::kRtabmapDetectionRate()        -> "Rtabmap/DetectionRate"  (use it, not literals)
//   Parameters::defaultRtabmapDetectionRate()  -> 1.0f                     (typed default)
// and the runtime registry (Parameters::all(), info(), defaults()) behind validation, typed
// access, INI files, command-line arguments and the serialisation stored in the database.
//
// Every function that takes user input throws ParameterError with a message naming the key,
// the value, what was expected and, for an unknown key, the closest declared key.
#include <iosfwd>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rtabmap_core/params/ParameterInfo.h"

namespace rtabmap {

// Parameters as text: "Group/Name" -> value, e.g. {"Kp/MaxFeatures", "400"}.
using ParametersMap = std::map<std::string, std::string>;
using ParametersPair = std::pair<std::string, std::string>;

// Result of Parameters::parseArguments().
struct ParsedArguments {
  ParametersMap parameters;             // every --Group/Name value pair, validated
  std::vector<std::string> remaining;   // the other arguments, untouched and in order
};

// Result of Parameters::deserializeLenient(): a database written by another version may hold
// keys this version does not declare, or values its limits no longer accept.
struct DeserializedParameters {
  ParametersMap known;    // declared keys with valid values
  ParametersMap unknown;  // keys this version does not declare
  ParametersMap invalid;  // declared keys whose stored value does not validate here
};

class Parameters {
 public:
  Parameters() = delete;

  // ---- Generated key constants and typed defaults -------------------------------------------
#define RTABMAP_PARAM(GROUP, NAME, TYPE, DEFAULT, LIMITS, DESCRIPTION)         \
  static std::string k##GROUP##NAME() { return #GROUP "/" #NAME; }              \
  static TYPE default##GROUP##NAME() { return static_cast<TYPE>(DEFAULT); }
#include "rtabmap_core/params/ParameterList.def"
#undef RTABMAP_PARAM

  // ---- Registry -------------------------------------------------------------------------------
  // Every declared parameter, sorted by key.
  static const std::vector<ParameterInfo>& all();
  // nullptr if the key is not declared.
  static const ParameterInfo* find(const std::string& key);
  // Throws ParameterError naming the closest declared key if the key is not declared.
  static const ParameterInfo& info(const std::string& key);
  static bool isDeclared(const std::string& key) { return find(key) != nullptr; }
  // Every declared key with its default value.
  static const ParametersMap& defaults();
  // The group names ("Bayes", "Grid", ...), sorted.
  static std::vector<std::string> groups();
  // The declared key nearest to the given one (case-insensitive edit distance; an exact match
  // of the name part wins, so "DetectionRate" -> "Rtabmap/DetectionRate").
  static std::string closestKey(const std::string& key);

  // ---- Validation -----------------------------------------------------------------------------
  // True if the key is declared and the value has its type and limits; otherwise false with
  // the user-facing reason in *why.
  static bool isValid(const std::string& key, const std::string& value, std::string* why = nullptr);
  // Throws ParameterError with that reason.
  static void validate(const std::string& key, const std::string& value);
  // Checks every entry; the error lists every invalid entry, one per line.
  static void validate(const ParametersMap& parameters);

  // ---- Typed access: the value in the map, else the declared default -------------------------
  // Throws ParameterError if the key is not declared, if the map value is invalid, or if the
  // parameter's type does not convert (getInt on a float parameter, getBool on an int one...).
  // Numbers widen: getDouble/getFloat also read int parameters. getString reads any type.
  static bool getBool(const ParametersMap& parameters, const std::string& key);
  static int getInt(const ParametersMap& parameters, const std::string& key);
  static float getFloat(const ParametersMap& parameters, const std::string& key);
  static double getDouble(const ParametersMap& parameters, const std::string& key);
  static std::string getString(const ParametersMap& parameters, const std::string& key);
  // A number-list string parameter ("Kp/RoiRatios", "Bayes/PredictionLC") as numbers.
  static std::vector<double> getNumberList(const ParametersMap& parameters, const std::string& key);

  // The entries of one group: filterByGroup(p, "Icp") keeps "Icp/..." keys.
  static ParametersMap filterByGroup(const ParametersMap& parameters, const std::string& group);
  // defaults() overridden by the given (validated) parameters.
  static ParametersMap withDefaults(const ParametersMap& parameters);

  // ---- INI files (the original config.ini layout) --------------------------------------------
  // Reads the [Core] section: "Group/Name = value" lines ("Group\Name" as written by the
  // original's Qt settings is accepted too). Lines starting with '#' or ';' are comments; a
  // value may be double-quoted with \" \\ \n \t escapes. Other sections are skipped; lines
  // before any section count as [Core]. Errors name the file and line.
  static ParametersMap readIni(const std::string& path);
  // Same on text already read; sourceName is used in error messages.
  static ParametersMap parseIni(const std::string& text, const std::string& sourceName);
  // Writes the parameters (validated first) as a [Core] section, each preceded by its
  // description as a comment. Overwrites the file.
  static void writeIni(const std::string& path, const ParametersMap& parameters);
  static std::string formatIni(const ParametersMap& parameters);

  // ---- Command-line arguments ----------------------------------------------------------------
  // Takes "--Group/Name value" and "--Group/Name=value" pairs out of args; the rest is returned
  // untouched. A lone "--" stops the scan (it and what follows are passed through).
  static ParsedArguments parseArguments(const std::vector<std::string>& args);
  // Same on main()'s arguments; argv[0] (the program) is skipped.
  static ParsedArguments parseArguments(int argc, const char* const argv[]);

  // ---- Serialisation (one string per session in the database) --------------------------------
  // "Key=value;Key=value", with '%', ';', '=' and control characters percent-encoded, so any
  // value round-trips (spaces, newlines, UTF-8 pass through as bytes).
  static std::string serialize(const ParametersMap& parameters);
  // Strict: every key must be declared and every value valid, else ParameterError.
  static ParametersMap deserialize(const std::string& text);
  // Lenient: unknown keys and invalid values are returned apart instead of throwing. Throws
  // ParameterError only if the text itself is corrupt (bad escape, entry without '=').
  static DeserializedParameters deserializeLenient(const std::string& text);

  // ---- Printing -------------------------------------------------------------------------------
  // Every parameter, sorted by key, as two lines:
  //   Grid/CellSize = 0.05   (float > 0)
  //       Size of one cell of the occupancy grids, in meters.
  // Values in `current` (validated) are shown instead of the default, with "(default X)".
  static void print(std::ostream& out, const ParametersMap& current = {});
};

}  // namespace rtabmap
