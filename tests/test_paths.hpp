// Where the suites find their files: the course's shared folder (../shared beside the source tree:
// the benchmark scenes' textures) and tests/data. Functions defined in a file CMake writes
// (test_paths.cpp.in), not definitions on the compile line, so that no suite's compile depends on
// where the tree lies and a compiler cache serves a clone of the tree anywhere.
#pragma once

#include <string>

namespace raster::test {

std::string sharedDir();    // ../shared beside the source tree
std::string testDataDir();  // tests/data
std::string sourceDir();    // the source tree's root

}  // namespace raster::test
