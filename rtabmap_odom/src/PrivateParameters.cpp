#include "rtabmap_odom/PrivateParameters.h"

#include "rtabmap_core/params/Parameters.h"
#include "rtabmap_slam_node/SlamNodeSupport.h"

#include <cctype>
#include <optional>
#include <sstream>

namespace rtabmap_odom {
namespace {

std::optional<std::string> asText(XmlRpc::XmlRpcValue& v) {
  std::ostringstream out;
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return bool(v) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeInt: return std::to_string(int(v));
    case XmlRpc::XmlRpcValue::TypeDouble: out.precision(9); out << double(v); return out.str();
    case XmlRpc::XmlRpcValue::TypeString: return std::string(v);
    default: return std::nullopt;
  }
}

}  // namespace

std::map<std::string, std::string> configFileParameters(const ros::NodeHandle& pnh, std::string* path,
                                                        std::string* error) {
  std::string configured;
  pnh.param("config_path", configured, configured);
  *path = rtabmap_slam_node::expandHome(configured);
  error->clear();
  if (path->empty()) return {};
  try {
    return rtabmap::Parameters::readIni(*path);
  } catch (const std::exception& e) {
    *error = e.what();
    return {};
  }
}

std::map<std::string, std::string> privateParameters(const ros::NodeHandle& pnh, std::vector<std::string>* odd) {
  std::map<std::string, std::string> out;
  std::vector<std::string> names;
  pnh.getParamNames(names);
  const std::string prefix = pnh.getNamespace() + "/";
  for (const std::string& full : names) {
    if (full.compare(0, prefix.size(), prefix) != 0) continue;
    XmlRpc::XmlRpcValue value;
    if (!pnh.getParam(full, value)) continue;
    if (std::optional<std::string> text = asText(value)) {
      out[full.substr(prefix.size())] = *text;
    } else if (odd) {
      odd->push_back(full.substr(prefix.size()));
    }
  }
  return out;
}

std::string throttleKey(const std::string& text) {
  std::string key;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) key += c;
  }
  return key;
}

}  // namespace rtabmap_odom
