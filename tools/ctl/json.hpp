#pragma once
/// @file JSON of the run summaries: values are nlohmann::ordered_json (members keep the order
/// they were set or read in), read with nlohmann's strict RFC 8259 parser, written with our one
/// fixed layout and number text (so identical runs give identical files, and a file we wrote
/// reads and writes back byte for byte).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace coopnav::ctl {

using Json = nlohmann::ordered_json;

/// Shortest decimal text of 15 to 17 significant digits that reads back to exactly `v` ("0.1",
/// "0.98", "1e-05"); "null" for NaN and infinities (JSON has no such numbers).
std::string jsonNumber(double v);

/// JSON string literal with quotes and escapes. Bytes that are not well-formed UTF-8 are written
/// as "\ufffd" (one per byte), so the text is always JSON.
std::string jsonQuote(const std::string& s);

/// s with the escapes of jsonQuote but no quotes and '"' kept: for text from the bus printed
/// unquoted (a scenario or daemon name, a reason), so that no newline, carriage return, escape
/// or C1 byte of a peer's string forges a line or reaches the terminal.
std::string printable(const std::string& s);

/// A number value; null for NaN and infinities (and for an empty optional).
Json numberOrNull(double v);
Json numberOrNull(std::optional<double> v);

/// Fixed layout: two-space indent, one member per line, arrays of scalars on one line, numbers as
/// jsonNumber (integers as integers), strings as jsonQuote; ends with a newline.
std::string dumpJson(const Json& value);

/// Parses JSON text (RFC 8259: no comments, no trailing commas, no YAML). Throws
/// std::runtime_error("invalid JSON: parse error at line L, column C: ...") when it is not.
Json parseJson(const std::string& text);

/// Lenient reading of a summary whose shape is not guaranteed (another tool's file, an older
/// format): the member `key` of an object, nullptr when `value` is not an object or lacks it.
const Json* member(const Json& value, const std::string& key);
/// The elements of an array; empty for a null pointer or any other value.
const Json::array_t& elements(const Json* value);
/// A number's value; NaN for a null pointer or any other value.
double numberValue(const Json* value);
/// A string's text; "" for a null pointer or any other value.
std::string stringValue(const Json* value);
/// A boolean's value; false for a null pointer or any other value.
bool boolValue(const Json* value);

}  // namespace coopnav::ctl
