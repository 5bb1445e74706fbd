# Debian 12 packages (COOPNAV_DEBS in scripts/lib.sh; coopnav_install_deps there installs the
# missing ones for scripts/run.sh, scripts/test.sh and the other scripts). Debian's LCM 1.3.1 ships
# no CMake config, only a pkg-config file whose glib requirement needs libglib2.0-dev.
find_package(PkgConfig REQUIRED)
pkg_check_modules(LCM REQUIRED IMPORTED_TARGET lcm)
find_program(LCM_GEN lcm-gen REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(octomap REQUIRED)
find_package(dynamicEDT3D QUIET)
find_package(spdlog REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)  # tools/ctl: summary.json
find_package(Ceres REQUIRED)
find_package(Threads REQUIRED)

add_library(coopnav_octomap INTERFACE)
target_include_directories(coopnav_octomap SYSTEM INTERFACE ${OCTOMAP_INCLUDE_DIRS})
target_link_libraries(coopnav_octomap INTERFACE ${OCTOMAP_LIBRARIES})

if(COOPNAV_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(COOPNAV_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
