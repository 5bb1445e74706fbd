#pragma once
/// @file Loading YAML into structs: a daemon's config, and world_sim's scenario files
/// (daemons/world_sim/scenario.hpp). The struct's in-class initialisers are the only defaults;
/// each struct lists its keys once, in `template <class V> void visit(V&)`, which serves loading,
/// range validation and printing alike.
///
///   struct FooConfig {
///     double speed_m_s{0.7};
///     template <class V> void visit(V& v) { v("speed_m_s", speed_m_s, Range{0.0, 2.0}); }
///   };

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "config/file_read.hpp"

namespace coopnav {

/// Thrown when a config cannot be used; what() lists every problem found, one per line.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Closed range [min, max] for numeric keys.
struct Range {
  double min{-std::numeric_limits<double>::infinity()};
  double max{std::numeric_limits<double>::infinity()};
};

/// Allowed values for string keys.
struct OneOf {
  std::vector<std::string> values;
};

/// Marks a key that must be given (the struct's value is no default): "is missing (required)"
/// when the mapping lacks it or gives it no value.
struct Required {};

/// Why a config string would not survive `--print-config` and loading again, or empty when it
/// is text: not UTF-8, a control character (C0, DEL, C1) or a character YAML reads as a line
/// break (U+2028, U+2029) or a byte order mark. yaml-cpp prints such a string as it is, and a
/// "\r" before the line end, for example, is read back as part of the line break (found by
/// fuzz_config in a dialogue template).
std::string notConfigText(const std::string& s);

/// "= 'value' is not one of {a, b, c}": the message for a string key outside its allowed values.
std::string notOneOfMessage(const std::string& value, const std::vector<std::string>& allowed);

/// Calls report(key, message) for each key of the mapping `node` that `known` lacks. A key that is
/// no name ("[a, b]: 1", "{x: 1}: 2") is reported with an empty key and its line: as<std::string>()
/// on it throws YAML::TypedBadConversion, which once took every daemon past its config loader
/// (found by fuzz_config) and world_sim past its scenario reader (fuzz_scenario) in two copies of
/// this loop, when the scenario had a reader of its own; ConfigReader reads both since.
template <class Report>
void reportUnknownKeys(const YAML::Node& node, const std::set<std::string>& known,
                       Report&& report) {
  if (!node || !node.IsMap()) return;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) {
      report(std::string(), "has a key that is not a name (line " +
                                std::to_string(kv.first.Mark().line + 1) + ")");
      continue;
    }
    const std::string& k = kv.first.Scalar();
    if (!known.count(k)) report(k, "is not a known key");
  }
}

/// Calls report(key, message) once for each key the mapping `node` gives more than once, naming
/// the lines of its first two occurrences. yaml-cpp keeps every pair of a duplicated key and
/// `node[key]` returns the first, so the later value was silently ignored (a config giving a key
/// twice, the second time out of range, loaded with the first). Keys that are no name are left to
/// reportUnknownKeys.
template <class Report>
void reportDuplicateKeys(const YAML::Node& node, Report&& report) {
  if (!node || !node.IsMap()) return;
  std::map<std::string, std::pair<int, bool>> first_line;  // key -> (line, reported)
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) continue;
    const int line = kv.first.Mark().line + 1;
    const auto [it, fresh] = first_line.emplace(kv.first.Scalar(), std::make_pair(line, false));
    if (fresh || it->second.second) continue;
    it->second.second = true;
    report(it->first, "is given more than once (lines " + std::to_string(it->second.first) +
                          " and " + std::to_string(line) + "); give each key once");
  }
}

namespace detail {
template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};
template <class T, class = void>
struct HasVisit : std::false_type {};
template <class T>
struct HasVisit<T, std::void_t<decltype(&T::template visit<int>)>> : std::true_type {};
}  // namespace detail

/// Reads a YAML mapping into a struct through its visit(); collects every error, each naming the
/// source, the dotted key path (list items as "humans[0].") and the value. The one YAML reader of
/// the project: the daemons' configs and world_sim's scenario files.
///
/// A key given twice in any mapping it reads is an error (reportDuplicateKeys), whichever value
/// is right.
///
/// A visit() calls v(key, field, options...) once per key, options among Range (numeric fields),
/// OneOf (strings) and Required. A key the mapping lacks, or gives no value ("key:", "key: ~"),
/// keeps the struct's value (an error for a Required key). A value that is out of its Range, not
/// one of its OneOf, or of the wrong type is reported and not stored. A field with a visit() is a
/// nested mapping; a std::vector a YAML list (of scalars, or of mappings when the element type
/// has a visit()).
class ConfigReader {
 public:
  ConfigReader(const YAML::Node& node, std::string where, std::string prefix = "")
      : node_(node), where_(std::move(where)), prefix_(std::move(prefix)) {
    if (node_ && !node_.IsNull() && !node_.IsMap()) error("", "must be a mapping");
    // Every mapping read (the file's, a nested one, a list item) is read by a reader of its own.
    reportDuplicateKeys(
        node_, [this](const std::string& key, const std::string& msg) { error(key, msg); });
  }

  template <class T, class... Options>
  void operator()(const char* key, T& field, const Options&... options) {
    static_assert(((std::is_same_v<Options, Range> || std::is_same_v<Options, OneOf> ||
                    std::is_same_v<Options, Required>)&&...),
                  "options of a key: Range, OneOf, Required");
    static_assert(!(std::is_same_v<Options, Range> || ...) || std::is_arithmetic_v<T>,
                  "a Range is for a number");
    static_assert(!(std::is_same_v<Options, OneOf> || ...) || std::is_same_v<T, std::string>,
                  "a OneOf is for a string");
    constexpr bool required = (std::is_same_v<Options, Required> || ...);
    const Range* range = nullptr;
    const OneOf* one_of = nullptr;
    (pick(options, range, one_of), ...);
    seen_.insert(key);
    const bool is_map = node_ && node_.IsMap();
    const YAML::Node v = is_map ? node_[key] : YAML::Node(YAML::NodeType::Undefined);
    if (!v || v.IsNull()) {
      if (required && is_map) {
        error(key, "is missing (required)");
        return;
      }
      // The struct's own value stands; it must meet the key's constraints too (validateConfig).
      if constexpr (std::is_arithmetic_v<T>) {
        if (range) checkRange(key, static_cast<double>(field), *range, nullptr);
      }
      if constexpr (std::is_same_v<T, std::string>) {
        if (one_of) checkOneOf(key, field, *one_of);
      }
      return;
    }
    if constexpr (detail::HasVisit<T>::value || detail::IsVector<T>::value) {
      readValue(key, v, field);
    } else {
      T value = field;
      if (!readValue(key, v, value)) return;
      if constexpr (std::is_arithmetic_v<T>) {
        if (range && !checkRange(key, static_cast<double>(value), *range, &v)) return;
      }
      if constexpr (std::is_same_v<T, std::string>) {
        if (one_of && !checkOneOf(key, value, *one_of)) return;
      }
      field = std::move(value);
    }
  }

  /// A key the mapping may have that this visit() does not read (e.g. the parameters of a
  /// behaviour that is itself reported unknown): not reported as unknown.
  void skip(const char* key) { seen_.insert(key); }

  /// Extra cross-field check from a config's visit(): adds an error when !ok.
  void require(bool ok, const std::string& key, const std::string& message) {
    if (!ok) error(key, message);
  }

  /// Reports keys present in the file that the struct does not know.
  void rejectUnknownKeys() {
    reportUnknownKeys(node_, seen_,
                      [this](const std::string& key, const std::string& msg) { error(key, msg); });
  }

  const std::vector<std::string>& errors() const { return errors_; }

 private:
  static void pick(const Range& r, const Range*& range, const OneOf*&) { range = &r; }
  static void pick(const OneOf& o, const Range*&, const OneOf*& one_of) { one_of = &o; }
  static void pick(const Required&, const Range*&, const OneOf*&) {}

  void error(const std::string& key, const std::string& msg) {
    const std::string path = prefix_ + key;
    std::ostringstream s;
    s << where_ << ": ";
    if (!path.empty()) s << "key '" << path << "' ";
    s << msg;
    errors_.push_back(s.str());
  }

  static std::string lineOf(const YAML::Node& v) {
    return "(line " + std::to_string(v.Mark().line + 1) + ")";
  }

  /// `v`: the value's node, whose text the message quotes as written; nullptr: the struct's value.
  bool checkRange(const std::string& key, double value, Range r, const YAML::Node* v) {
    if (value >= r.min && value <= r.max) return true;
    std::ostringstream s;
    s << "= ";
    if (v) {
      s << v->Scalar();
    } else {
      s << value;
    }
    s << " is outside the allowed range [" << r.min << ", " << r.max << "]";
    error(key, s.str());
    return false;
  }

  bool checkOneOf(const std::string& key, const std::string& value, const OneOf& allowed) {
    for (const auto& a : allowed.values)
      if (a == value) return true;
    error(key, notOneOfMessage(value, allowed.values));
    return false;
  }

  template <class T>
  static const char* typeName() {
    if constexpr (std::is_same_v<T, bool>) {
      return "true or false";
    } else if constexpr (std::is_floating_point_v<T>) {
      return "a number";
    } else if constexpr (std::is_integral_v<T>) {
      return "an integer";
    } else if constexpr (std::is_same_v<T, std::string>) {
      return "a string";
    } else {
      return "a value";
    }
  }

  /// Reads `v` into `field`; false (and an error) when it cannot.
  template <class T>
  bool readValue(const std::string& key, const YAML::Node& v, T& field) {
    if constexpr (detail::HasVisit<T>::value) {
      ConfigReader sub(v, where_, prefix_ + key + ".");
      if (v.IsMap()) {
        field.visit(sub);
        sub.rejectUnknownKeys();
      } else if (v.IsNull()) {
        sub.error("", "must be a mapping");  // a list item "- ~" (a key's null is absent)
      }  // else the constructor said it: nothing in it can be read
      errors_.insert(errors_.end(), sub.errors_.begin(), sub.errors_.end());
      return sub.errors_.empty();
    } else if constexpr (detail::IsVector<T>::value) {
      if (!v.IsSequence()) {
        error(key, "must be a list");
        return false;
      }
      T out;
      bool ok = true;
      for (std::size_t i = 0; i < v.size(); ++i) {
        typename T::value_type item{};
        ok = readValue(key + "[" + std::to_string(i) + "]", v[i], item) && ok;
        out.push_back(std::move(item));
      }
      field = std::move(out);
      return ok;
    } else {
      if (!v.IsScalar()) {
        error(key, std::string("must be ") + typeName<T>());
        return false;
      }
      try {
        if constexpr (std::is_floating_point_v<T>) {
          const T x = v.as<T>();
          if (!std::isfinite(x)) {
            error(key, "= " + v.Scalar() + " is not a finite number");
            return false;
          }
          field = x;
        } else if constexpr (std::is_same_v<T, std::string>) {
          const std::string text = v.as<std::string>();
          const std::string why = notConfigText(text);
          if (!why.empty()) {
            error(key, lineOf(v) + " " + why);
            return false;
          }
          field = text;
        } else {
          field = v.as<T>();
        }
        return true;
      } catch (const YAML::Exception&) {
        error(key, "= '" + v.Scalar() + "' has the wrong type: expected " + typeName<T>() + " " +
                       lineOf(v));
        return false;
      }
    }
  }

  YAML::Node node_;
  std::string where_;
  std::string prefix_;
  std::set<std::string> seen_;
  std::vector<std::string> errors_;
};

/// Validates a config struct built in code (no file): range errors as from a file.
template <class Config>
std::vector<std::string> validateConfig(Config& config, const std::string& where = "config") {
  ConfigReader r(YAML::Node(), where);
  config.visit(r);
  return r.errors();
}

/// Applies command-line overrides "a.b=value" (value parsed as YAML) onto `root`; throws
/// ConfigError for a malformed one. Validation of the result is the loader's.
void applyOverrides(YAML::Node& root, const std::vector<std::string>& overrides);

/// Loads `path` (empty = defaults only) into a Config, then `overrides` ("key=value", dotted keys
/// for nested structs); throws ConfigError listing every problem.
template <class Config>
Config loadConfig(const std::string& path, const std::vector<std::string>& overrides = {}) {
  Config config;
  YAML::Node root;
  if (!path.empty()) {
    std::string text;
    try {
      text = readFileCapped(path, kMaxYamlFileBytes, "config file");
    } catch (const FileReadError& e) {
      throw ConfigError(e.what());
    }
    try {
      root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      throw ConfigError(path + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                        ": " + e.msg);
    }
  }
  if (!overrides.empty()) {
    if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
    applyOverrides(root, overrides);
  }
  ConfigReader r(root, path.empty() ? std::string("defaults") : path);
  config.visit(r);
  r.rejectUnknownKeys();
  if (!r.errors().empty()) {
    std::string all;
    for (const auto& e : r.errors()) all += e + "\n";
    all.pop_back();
    throw ConfigError(all);
  }
  return config;
}

/// Prints a config as YAML (used by --print-config).
class ConfigPrinter {
 public:
  explicit ConfigPrinter(YAML::Emitter& out) : out_(out) {}
  template <class T, class... Rest>
  void operator()(const char* key, T& field, const Rest&...) {
    out_ << YAML::Key << key << YAML::Value;
    emit(field);
  }
  void require(bool, const std::string&, const std::string&) {}
  void skip(const char*) {}

 private:
  template <class T>
  void emit(T& field) {
    if constexpr (detail::HasVisit<T>::value) {
      out_ << YAML::BeginMap;
      field.visit(*this);
      out_ << YAML::EndMap;
    } else if constexpr (detail::IsVector<T>::value) {
      out_ << YAML::Flow << YAML::BeginSeq;
      for (auto& x : field) emit(x);
      out_ << YAML::EndSeq;
    } else {
      out_ << field;
    }
  }
  YAML::Emitter& out_;
};

template <class Config>
std::string configToYaml(Config config) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  ConfigPrinter p(out);
  config.visit(p);
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace coopnav
