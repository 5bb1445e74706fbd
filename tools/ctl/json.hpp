#pragma once
/// @file A small JSON value for the run summaries: built by the tools, written with one fixed
/// layout (so identical runs give identical files), read back (merging, the CM table) through
/// yaml-cpp, whose YAML 1.2 parser accepts JSON. Numbers keep their text, so a file read and
/// written again keeps every digit.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace coopnav::ctl {

/// Shortest decimal text that reads back to exactly `v` ("0.1", "0.98", "1e-05"); "null" for NaN
/// and infinities (JSON has no such numbers).
std::string jsonNumber(double v);

class Json {
 public:
  enum class Type : std::uint8_t { kNull, kBool, kNumber, kString, kArray, kObject };

  Json() = default;  ///< null
  static Json null() { return Json(); }
  static Json boolean(bool b);
  static Json number(double v);  ///< NaN / inf -> null
  static Json number(std::int64_t v);
  static Json number(std::optional<double> v) { return v ? number(*v) : null(); }
  /// A number from text already known to be a JSON number (kept verbatim, every digit).
  static Json numberLiteral(std::string text);
  static Json string(std::string s);
  static Json array();
  static Json object();

  Type type() const { return type_; }
  bool isNull() const { return type_ == Type::kNull; }

  /// Object: sets `key` (replacing an existing member in place, else appending). Returns *this.
  Json& set(const std::string& key, Json value);
  /// Array: appends. Returns *this.
  Json& push(Json value);

  /// Object member or nullptr.
  const Json* find(const std::string& key) const;
  const std::vector<Json>& items() const { return items_; }
  const std::vector<std::pair<std::string, Json>>& members() const { return members_; }
  /// Number value (NaN when not a number), string text, bool value (false when not a bool).
  double asNumber() const;
  const std::string& asString() const { return text_; }
  bool asBool() const { return type_ == Type::kBool && text_ == "true"; }

  /// Fixed layout: two-space indent, one member per line, arrays of scalars on one line.
  std::string dump() const;

  /// Parses JSON text. Throws std::runtime_error with the reason when it is not valid.
  static Json parse(const std::string& text);

 private:
  void dumpTo(std::string& out, int indent) const;
  Type type_{Type::kNull};
  std::string text_;  // number literal, bool literal or string contents
  std::vector<Json> items_;
  std::vector<std::pair<std::string, Json>> members_;
};

/// JSON string literal with quotes and escapes.
std::string jsonQuote(const std::string& s);

}  // namespace coopnav::ctl
