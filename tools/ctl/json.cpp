#include "json.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace coopnav::ctl {
namespace {

// Length of the well-formed UTF-8 sequence at s[i] (RFC 3629 table 3), 0 when it is ill-formed.
std::size_t utf8SequenceLength(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80;
  unsigned char hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;  // no overlong forms
    if (c == 0xED) hi = 0x9F;  // no surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;  // no overlong forms
    if (c == 0xF4) hi = 0x8F;  // nothing above U+10FFFF
  } else {
    return 0;
  }
  if (i + n > s.size() || byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
  return n;
}

void dumpTo(const Json& v, std::string& out, int indent) {
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  const std::string close_pad(static_cast<std::size_t>(indent), ' ');
  switch (v.type()) {
    case Json::value_t::null:
      out += "null";
      return;
    case Json::value_t::boolean:
      out += v.get<bool>() ? "true" : "false";
      return;
    case Json::value_t::number_integer:
      out += std::to_string(v.get<std::int64_t>());
      return;
    case Json::value_t::number_unsigned:
      out += std::to_string(v.get<std::uint64_t>());
      return;
    case Json::value_t::number_float:
      out += jsonNumber(v.get<double>());
      return;
    case Json::value_t::string:
      out += jsonQuote(v.get_ref<const std::string&>());
      return;
    case Json::value_t::array: {
      if (v.empty()) {
        out += "[]";
        return;
      }
      bool scalars = true;
      for (const auto& item : v) scalars = scalars && !item.is_structured();
      if (scalars) {
        out += "[";
        for (std::size_t i = 0; i < v.size(); ++i) {
          if (i) out += ", ";
          dumpTo(v[i], out, indent);
        }
        out += "]";
        return;
      }
      out += "[\n";
      for (std::size_t i = 0; i < v.size(); ++i) {
        out += pad;
        dumpTo(v[i], out, indent + 2);
        out += i + 1 < v.size() ? ",\n" : "\n";
      }
      out += close_pad + "]";
      return;
    }
    case Json::value_t::object: {
      if (v.empty()) {
        out += "{}";
        return;
      }
      out += "{\n";
      std::size_t i = 0;
      for (const auto& [key, value] : v.items()) {
        out += pad + jsonQuote(key) + ": ";
        dumpTo(value, out, indent + 2);
        out += ++i < v.size() ? ",\n" : "\n";
      }
      out += close_pad + "}";
      return;
    }
    case Json::value_t::binary:
    case Json::value_t::discarded:
      break;
  }
  throw std::invalid_argument("dumpJson: a binary or discarded value is not JSON text");
}

}  // namespace

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  if (v == 0.0) return "0";  // also -0
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

namespace {

// Escapes s onto out: control characters (C0, DEL and the C1 range U+0080..U+009F, which some
// terminals obey as CSI), backslash, and, for JSON, the double quote. Ill-formed UTF-8 becomes
// "\ufffd" per byte. Nothing from the bus can then end a line or steer a terminal.
void escapeTo(const std::string& s, std::string& out, bool quote) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    switch (c) {
      case '"':
        out += quote ? "\\\"" : "\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else if (const std::size_t n = utf8SequenceLength(s, i); n == 0) {
          out += "\\ufffd";
        } else if (n == 2 && c == 0xC2 && static_cast<unsigned char>(s[i + 1]) < 0xA0) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned char>(s[i + 1]));
          out += buf;
          i += n;
          continue;
        } else {
          out.append(s, i, n);
          i += n;
          continue;
        }
    }
    ++i;
  }
}

}  // namespace

std::string jsonQuote(const std::string& s) {
  std::string out = "\"";
  escapeTo(s, out, true);
  return out + "\"";
}

std::string printable(const std::string& s) {
  std::string out;
  escapeTo(s, out, false);
  return out;
}

Json numberOrNull(double v) { return std::isfinite(v) ? Json(v) : Json(); }

Json numberOrNull(std::optional<double> v) { return v ? numberOrNull(*v) : Json(); }

std::string dumpJson(const Json& value) {
  std::string out;
  dumpTo(value, out, 0);
  out += "\n";
  return out;
}

Json parseJson(const std::string& text) {
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ..." without the id.
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0) {
      const auto end = what.find("] ");
      if (end != std::string::npos) what.erase(0, end + 2);
    }
    throw std::runtime_error("invalid JSON: " + what);
  }
}

const Json* member(const Json& value, const std::string& key) {
  if (!value.is_object()) return nullptr;
  const auto it = value.find(key);
  return it == value.end() ? nullptr : &*it;
}

const Json::array_t& elements(const Json* value) {
  static const Json::array_t kEmpty;
  return value && value->is_array() ? value->get_ref<const Json::array_t&>() : kEmpty;
}

double numberValue(const Json* value) {
  return value && value->is_number() ? value->get<double>()
                                     : std::numeric_limits<double>::quiet_NaN();
}

std::string stringValue(const Json* value) {
  return value && value->is_string() ? value->get<std::string>() : std::string();
}

bool boolValue(const Json* value) { return value && value->is_boolean() && value->get<bool>(); }

}  // namespace coopnav::ctl
