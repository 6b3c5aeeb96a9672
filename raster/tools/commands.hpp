// The subcommands of build/bin/raster, one file each.
#pragma once

namespace raster::tools {

int bench(int argc, char** argv);
int microbench(int argc, char** argv);
int render(int argc, char** argv);
int trace(int argc, char** argv);
int view(int argc, char** argv);

}  // namespace raster::tools
