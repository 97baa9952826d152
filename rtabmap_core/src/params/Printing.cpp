// The listing behind every tool's --params.
#include <ostream>

#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {

void Parameters::print(std::ostream& out, const ParametersMap& current) {
  validate(current);
  out << "Core parameters (" << all().size()
      << "), set with --Group/Name value, an INI file, or ROS private parameters:\n";
  std::string group;
  for (const ParameterInfo& parameter : all()) {
    if (parameter.group != group) {
      group = parameter.group;
      out << "\n[" << group << "]\n";
    }
    const auto it = current.find(parameter.key);
    out << parameter.key << " = ";
    if (it != current.end()) {
      out << it->second << "   (default " << parameter.defaultValue << "; ";
    } else {
      out << (parameter.defaultValue.empty() ? "\"\"" : parameter.defaultValue) << "   (";
    }
    out << parameter.expectation() << ")\n    " << parameter.description << "\n";
  }
}

}  // namespace rtabmap
