#include "config/config.hpp"

#include <cstdint>
#include <cstdio>

namespace coopnav {

std::string notOneOfMessage(const std::string& value, const std::vector<std::string>& allowed) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  return "= '" + value + "' is not one of {" + list + "}";
}

std::string notConfigText(const std::string& s) {
  const auto* b = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned c = b[i];
    std::size_t len = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      len = 1, cp = c;
    } else if (c >= 0xC2 && c <= 0xDF) {
      len = 2, cp = c & 0x1Fu;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3, cp = c & 0x0Fu;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4, cp = c & 0x07u;
    } else {
      return "is not UTF-8 text (byte " + std::to_string(i) + ")";
    }
    if (i + len > n) return "is not UTF-8 text (truncated at byte " + std::to_string(i) + ")";
    for (std::size_t k = 1; k < len; ++k) {
      if ((b[i + k] & 0xC0u) != 0x80u)
        return "is not UTF-8 text (byte " + std::to_string(i + k) + ")";
      cp = (cp << 6) | (b[i + k] & 0x3Fu);
    }
    const bool overlong = (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000);
    if (overlong || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
      return "is not UTF-8 text (byte " + std::to_string(i) + ")";
    if (cp < 0x20 || (cp >= 0x7F && cp <= 0x9F) || cp == 0x2028 || cp == 0x2029 || cp == 0xFEFF) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "U+%04X", static_cast<unsigned>(cp));
      return std::string("contains the control character ") + hex + " (byte " + std::to_string(i) +
             "); config text must be printable";
    }
    i += len;
  }
  return {};
}

void applyOverrides(YAML::Node& root, const std::vector<std::string>& overrides) {
  for (const auto& o : overrides) {
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ConfigError("--set '" + o + "': expected key=value (dotted keys for nested settings)");
    const std::string key = o.substr(0, eq);
    YAML::Node value;
    try {
      value = YAML::Load(o.substr(eq + 1));
    } catch (const YAML::ParserException& e) {
      throw ConfigError("--set '" + o + "': value is not valid YAML: " + e.msg);
    }
    // Walk/create the nested maps; yaml-cpp nodes are handles, so reassigning descends.
    std::vector<std::string> parts;
    std::string::size_type start = 0;
    for (std::string::size_type dot; (dot = key.find('.', start)) != std::string::npos;
         start = dot + 1)
      parts.push_back(key.substr(start, dot - start));
    parts.push_back(key.substr(start));
    YAML::Node node = root;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      if (parts[i].empty()) throw ConfigError("--set '" + o + "': empty key component");
      YAML::Node child = node[parts[i]];
      if (!child.IsDefined() || child.IsNull()) {
        node[parts[i]] = YAML::Node(YAML::NodeType::Map);
        child = node[parts[i]];
      } else if (!child.IsMap()) {
        throw ConfigError("--set '" + o + "': '" + parts[i] + "' is not a group of settings");
      }
      node.reset(child);
    }
    if (parts.back().empty()) throw ConfigError("--set '" + o + "': empty key component");
    node[parts.back()] = value;
  }
}

}  // namespace coopnav
