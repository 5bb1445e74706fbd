#include "runtime/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace coopnav {

spdlog::logger& log() {
  static std::shared_ptr<spdlog::logger> logger = [] {
    auto l = spdlog::stderr_color_mt("coopnav");
    l->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%n:%P] [%^%l%$] %v");
    return l;
  }();
  return *logger;
}

bool setLogLevel(const std::string& level) {
  const auto lvl = spdlog::level::from_str(level);
  // from_str maps unknown names to "off": accept "off" only when asked for explicitly.
  if (lvl == spdlog::level::off && level != "off") return false;
  log().set_level(lvl);
  return true;
}

}  // namespace coopnav
