#include "common/config.hpp"

namespace coopnav {

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
