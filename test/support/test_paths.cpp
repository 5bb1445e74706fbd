#include "test_paths.hpp"

namespace coopnav::test {

const std::string& sourceDir() {
  static const std::string dir = COOPNAV_SOURCE_DIR;
  return dir;
}

const std::string& testDataDir() {
  static const std::string dir = COOPNAV_TEST_DATA_DIR;
  return dir;
}

const std::string& binaryDir() {
  static const std::string dir = COOPNAV_BINARY_DIR;
  return dir;
}

}  // namespace coopnav::test
