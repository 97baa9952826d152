// One-string form of a ParametersMap, stored with each session in the database.
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/params/Parameters.h"

namespace rtabmap {
namespace {

// Percent-encode the separators, '%' itself and control characters; everything else
// (spaces, UTF-8 bytes) is stored as is, which keeps the string readable in an SQL browser.
bool needsEscape(unsigned char c) { return c == '%' || c == ';' || c == '=' || c < 0x20 || c == 0x7F; }

std::string escape(const std::string& text) {
  static const char* hex = "0123456789ABCDEF";
  std::string escaped;
  escaped.reserve(text.size());
  for (unsigned char c : text) {
    if (needsEscape(c)) {
      escaped += '%';
      escaped += hex[c >> 4];
      escaped += hex[c & 0xF];
    } else {
      escaped += static_cast<char>(c);
    }
  }
  return escaped;
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string unescape(const std::string& text, std::size_t offset) {
  std::string plain;
  plain.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      plain += text[i];
      continue;
    }
    const int high = i + 1 < text.size() ? hexDigit(text[i + 1]) : -1;
    const int low = i + 2 < text.size() ? hexDigit(text[i + 2]) : -1;
    if (high < 0 || low < 0) {
      throw ParameterError("corrupt parameter string: bad escape at character " +
                           std::to_string(offset + i + 1));
    }
    plain += static_cast<char>(high * 16 + low);
    i += 2;
  }
  return plain;
}

// Splits "k=v;k=v" into raw pairs (still escaped content is unescaped here).
ParametersMap splitEntries(const std::string& text) {
  ParametersMap entries;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(';', start);
    if (end == std::string::npos) end = text.size();
    const std::string entry = text.substr(start, end - start);
    if (!entry.empty()) {
      const auto equal = entry.find('=');
      if (equal == std::string::npos) {
        throw ParameterError("corrupt parameter string: entry \"" + entry + "\" at character " +
                             std::to_string(start + 1) + " has no '='");
      }
      entries[unescape(entry.substr(0, equal), start)] =
          unescape(entry.substr(equal + 1), start + equal + 1);
    }
    start = end + 1;
  }
  return entries;
}

}  // namespace

std::string Parameters::serialize(const ParametersMap& parameters) {
  std::string text;
  for (const auto& [key, value] : parameters) {
    if (!text.empty()) text += ';';
    text += escape(key) + '=' + escape(value);
  }
  return text;
}

ParametersMap Parameters::deserialize(const std::string& text) {
  const ParametersMap entries = splitEntries(text);
  validate(entries);
  return entries;
}

DeserializedParameters Parameters::deserializeLenient(const std::string& text) {
  DeserializedParameters result;
  for (auto& [key, value] : splitEntries(text)) {
    if (!isDeclared(key)) {
      result.unknown[key] = value;
    } else if (isValid(key, value)) {
      result.known[key] = value;
    } else {
      result.invalid[key] = value;
    }
  }
  return result;
}

}  // namespace rtabmap
