// The source tree this build was configured from: the folder holding labs/, solutions/ and the grading
// declarations. A function defined in a file CMake writes (source_tree.cpp.in), not a definition on
// the compile line, so that no other file's compile depends on where the tree lies and a compiler
// cache serves a clone of the tree anywhere.
#pragma once

namespace raster::tools {

const char* sourceTree();  // absolute path, no trailing slash

}  // namespace raster::tools
