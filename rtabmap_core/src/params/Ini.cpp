// INI files in the layout of the original config.ini: a [Core] section of "Group/Name = value".
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ValueText.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

using value_text::trim;

// Quoting is needed only where a plain value would not read back the same: surrounding
// blanks (trimmed on read), a leading quote, and line breaks or other control characters.
bool needsQuotes(const std::string& value) {
  if (value.empty()) return false;
  if (value != trim(value) || value.front() == '"') return true;
  for (unsigned char c : value) {
    if (c < 0x20 || c == 0x7F) return true;
  }
  return false;
}

std::string quote(const std::string& value) {
  static const char* hex = "0123456789ABCDEF";
  std::string quoted = "\"";
  for (unsigned char c : value) {
    switch (c) {
      case '"': quoted += "\\\""; break;
      case '\\': quoted += "\\\\"; break;
      case '\n': quoted += "\\n"; break;
      case '\r': quoted += "\\r"; break;
      case '\t': quoted += "\\t"; break;
      default:
        if (c < 0x20 || c == 0x7F) {
          quoted += "\\x";
          quoted += hex[c >> 4];
          quoted += hex[c & 0xF];
        } else {
          quoted += static_cast<char>(c);
        }
    }
  }
  return quoted + "\"";
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// The value between the quotes, escapes resolved; throws a message (without location) if the
// quoting is broken.
std::string unquote(const std::string& text) {
  if (text.size() < 2 || text.back() != '"') {
    throw ParameterError("unterminated quoted value " + text);
  }
  std::string value;
  for (std::size_t i = 1; i + 1 < text.size(); ++i) {
    if (text[i] != '\\') {
      value += text[i];
      continue;
    }
    if (i + 2 >= text.size()) throw ParameterError("value ends with a lone backslash: " + text);
    const char escaped = text[++i];
    switch (escaped) {
      case '"': value += '"'; break;
      case '\\': value += '\\'; break;
      case 'n': value += '\n'; break;
      case 'r': value += '\r'; break;
      case 't': value += '\t'; break;
      case 'x': {
        const int high = i + 2 < text.size() - 1 ? hexDigit(text[i + 1]) : -1;
        const int low = high >= 0 ? hexDigit(text[i + 2]) : -1;
        if (low < 0) throw ParameterError("bad \\x escape in " + text);
        value += static_cast<char>(high * 16 + low);
        i += 2;
        break;
      }
      default:
        throw ParameterError(std::string("unknown escape \\") + escaped + " in " + text);
    }
  }
  return value;
}

struct IniReader {
  const std::string& sourceName;
  ParametersMap parameters;
  bool inCore = true;  // lines before any section header count as [Core]
  int lineNumber = 0;

  [[noreturn]] void fail(const std::string& message) const {
    throw ParameterError(sourceName + ":" + std::to_string(lineNumber) + ": " + message);
  }

  void readLine(const std::string& rawLine) {
    ++lineNumber;
    const std::string line = trim(rawLine);
    if (line.empty() || line[0] == '#' || line[0] == ';') return;
    if (line[0] == '[') {
      if (line.back() != ']') fail("malformed section header \"" + line + "\"");
      inCore = value_text::toLower(trim(line.substr(1, line.size() - 2))) == "core";
      return;
    }
    if (!inCore) return;
    const auto equal = line.find('=');
    if (equal == std::string::npos || trim(line.substr(0, equal)).empty()) {
      fail("malformed line \"" + line + "\": expected \"Group/Name = value\"");
    }
    readEntry(trim(line.substr(0, equal)), trim(line.substr(equal + 1)));
  }

  void readEntry(std::string key, std::string value) {
    // The original's Qt settings write "Group\Name"; it also stores its version in [Core].
    for (char& c : key) {
      if (c == '\\') c = '/';
    }
    if (value_text::toLower(key) == "version") return;
    if (!value.empty() && value.front() == '"') {
      try {
        value = unquote(value);
      } catch (const ParameterError& error) {
        fail(error.what());
      }
    }
    std::string why;
    if (!Parameters::isValid(key, value, &why)) fail(why);
    if (parameters.count(key)) {
      RTABMAP_WARN(sourceName << ":" << lineNumber << ": " << key
                              << " is set again; this later value wins");
    }
    parameters[key] = value;
  }
};

}  // namespace

ParametersMap Parameters::parseIni(const std::string& text, const std::string& sourceName) {
  IniReader reader{sourceName, {}, true, 0};
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) reader.readLine(line);
  return reader.parameters;
}

ParametersMap Parameters::readIni(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw ParameterError("cannot open parameter file \"" + path + "\": " + std::strerror(errno));
  }
  std::ostringstream text;
  text << file.rdbuf();
  return parseIni(text.str(), path);
}

std::string Parameters::formatIni(const ParametersMap& parameters) {
  validate(parameters);
  std::ostringstream out;
  out << "# RTAB-Map core parameters. One \"Group/Name = value\" per line in [Core];\n"
      << "# lines starting with # or ; are comments. Run any rtabmap tool with --params\n"
      << "# to list every parameter with its default.\n"
      << "[Core]\n";
  std::string group;
  for (const auto& [key, value] : parameters) {
    const ParameterInfo& parameter = info(key);
    if (parameter.group != group) {
      out << "\n";
      group = parameter.group;
    }
    out << "# " << parameter.description << " (" << parameter.expectation() << ", default \""
        << parameter.defaultValue << "\")\n"
        << key << " = " << (needsQuotes(value) ? quote(value) : value) << "\n";
  }
  return out.str();
}

void Parameters::writeIni(const std::string& path, const ParametersMap& parameters) {
  const std::string text = formatIni(parameters);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    throw ParameterError("cannot write parameter file \"" + path + "\": " + std::strerror(errno));
  }
  file << text;
  file.close();
  if (!file) throw ParameterError("failed writing parameter file \"" + path + "\"");
}

}  // namespace rtabmap
