#pragma once
// Where this build's tree, test data and binaries are. They are compiled into one object,
// test_paths.cpp, rather than given to every test as macros, so that the test objects do not
// depend on the checkout's location and ccache shares them between checkouts and worktrees.

#include <string>

namespace coopnav::test {

/// The source tree's root (the directory holding the top-level CMakeLists.txt).
const std::string& sourceDir();
/// test/data in the source tree.
const std::string& testDataDir();
/// The build tree's root (where daemons/<name>/coopnav_<name> and tools/ are built).
const std::string& binaryDir();

}  // namespace coopnav::test
