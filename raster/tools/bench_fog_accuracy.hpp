// raster bench fog-accuracy (bench_fog_accuracy.cpp): the accuracy of raster's fog and medium closed
// forms (raster/media/) against the forms of the lecture, Unreal Engine and the engines' σ floor
// (fog_forms.hpp), over media/reference.hpp's adversarial grid, in float ulps of a long-double
// reference (docs/ACCURACY.md, "Participating media").
#pragma once

#include <string>

namespace raster::tools {

inline constexpr const char* kFogAccuracyBench = "fog-accuracy";

struct FogAccuracyOptions {
    std::string outDir;       // not empty: fog-accuracy.csv, fog-accuracy-points.csv, .gp and .png there
    bool quick = false;       // every other value of each of the grid's axes (a test's run)
    bool exhaustive = false;  // ψ at every float, both signs, too (minutes)
    unsigned threads = 0;     // the exhaustive sweep's threads; 0: one per core
};

// Prints the table (Markdown) and, with outDir, writes it as CSV with the plot's points and draws the
// plot with gnuplot where it is installed. Returns the exit status: 0.
int runFogAccuracyBench(const FogAccuracyOptions& options);

}  // namespace raster::tools
