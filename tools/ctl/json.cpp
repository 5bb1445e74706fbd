#include "json.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace coopnav::ctl {

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

std::string jsonQuote(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"':
        out += "\\\"";
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
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

Json Json::boolean(bool b) {
  Json j;
  j.type_ = Type::kBool;
  j.text_ = b ? "true" : "false";
  return j;
}

Json Json::number(double v) {
  if (!std::isfinite(v)) return null();
  Json j;
  j.type_ = Type::kNumber;
  j.text_ = jsonNumber(v);
  return j;
}

Json Json::number(std::int64_t v) {
  Json j;
  j.type_ = Type::kNumber;
  j.text_ = std::to_string(v);
  return j;
}

Json Json::numberLiteral(std::string text) {
  Json j;
  j.type_ = Type::kNumber;
  j.text_ = std::move(text);
  return j;
}

Json Json::string(std::string s) {
  Json j;
  j.type_ = Type::kString;
  j.text_ = std::move(s);
  return j;
}

Json Json::array() {
  Json j;
  j.type_ = Type::kArray;
  return j;
}

Json Json::object() {
  Json j;
  j.type_ = Type::kObject;
  return j;
}

Json& Json::set(const std::string& key, Json value) {
  for (auto& [k, v] : members_) {
    if (k == key) {
      v = std::move(value);
      return *this;
    }
  }
  members_.emplace_back(key, std::move(value));
  return *this;
}

Json& Json::push(Json value) {
  items_.push_back(std::move(value));
  return *this;
}

const Json* Json::find(const std::string& key) const {
  for (const auto& [k, v] : members_)
    if (k == key) return &v;
  return nullptr;
}

double Json::asNumber() const {
  if (type_ != Type::kNumber) return std::nan("");
  return std::strtod(text_.c_str(), nullptr);
}

std::string Json::dump() const {
  std::string out;
  dumpTo(out, 0);
  out += "\n";
  return out;
}

void Json::dumpTo(std::string& out, int indent) const {
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  const std::string close_pad(static_cast<std::size_t>(indent), ' ');
  switch (type_) {
    case Type::kNull:
      out += "null";
      return;
    case Type::kBool:
    case Type::kNumber:
      out += text_;
      return;
    case Type::kString:
      out += jsonQuote(text_);
      return;
    case Type::kArray: {
      if (items_.empty()) {
        out += "[]";
        return;
      }
      bool scalars = true;
      for (const auto& i : items_)
        scalars = scalars && i.type_ != Type::kArray && i.type_ != Type::kObject;
      if (scalars) {
        out += "[";
        for (std::size_t i = 0; i < items_.size(); ++i) {
          if (i) out += ", ";
          items_[i].dumpTo(out, indent);
        }
        out += "]";
        return;
      }
      out += "[\n";
      for (std::size_t i = 0; i < items_.size(); ++i) {
        out += pad;
        items_[i].dumpTo(out, indent + 2);
        out += i + 1 < items_.size() ? ",\n" : "\n";
      }
      out += close_pad + "]";
      return;
    }
    case Type::kObject: {
      if (members_.empty()) {
        out += "{}";
        return;
      }
      out += "{\n";
      for (std::size_t i = 0; i < members_.size(); ++i) {
        out += pad + jsonQuote(members_[i].first) + ": ";
        members_[i].second.dumpTo(out, indent + 2);
        out += i + 1 < members_.size() ? ",\n" : "\n";
      }
      out += close_pad + "}";
      return;
    }
  }
}

namespace {

Json fromYaml(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      return Json::null();
    case YAML::NodeType::Scalar: {
      const std::string& s = n.Scalar();
      // Quoted scalars carry the non-specific tag "!": JSON strings. Plain ones are literals.
      if (n.Tag() == "!") return Json::string(s);
      if (s == "true" || s == "false") return Json::boolean(s == "true");
      if (s == "null" || s == "~") return Json::null();
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (!s.empty() && end && *end == '\0' && std::isfinite(v)) return Json::numberLiteral(s);
      throw std::runtime_error("not a JSON value: '" + s + "'");
    }
    case YAML::NodeType::Sequence: {
      Json a = Json::array();
      for (const auto& item : n) a.push(fromYaml(item));
      return a;
    }
    case YAML::NodeType::Map: {
      Json o = Json::object();
      for (const auto& kv : n) o.set(kv.first.as<std::string>(), fromYaml(kv.second));
      return o;
    }
  }
  return Json::null();
}

}  // namespace

Json Json::parse(const std::string& text) {
  try {
    return fromYaml(YAML::Load(text));
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(std::string("invalid JSON: ") + e.what());
  }
}

}  // namespace coopnav::ctl
