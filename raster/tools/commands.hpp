// The subcommands of build/bin/raster, one file each. Each add* function adds its subcommand to the
// program's CLI::App, declaring its options (with ranges, choices and --help) into variables it
// owns, and returns what runs the subcommand once the command line has parsed.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace raster::tools {

struct ViewerOptions;

struct Command {
    CLI::App* app;             // the subcommand; app->parsed() once it was on the command line
    std::function<int()> run;  // the exit status; throws Error (and CLI::ParseError for a value
                               // found bad only while running)
};

Command addBench(CLI::App& app);
Command addGrade(CLI::App& app);
Command addMicrobench(CLI::App& app);
Command addReferences(CLI::App& app);
Command addRender(CLI::App& app);
Command addTrace(CLI::App& app);
Command addView(CLI::App& app);

// Opens the viewer as raster view does (render --view). Throws Error for an unknown scene or
// --solution, before a window opens.
int openViewer(ViewerOptions options);

}  // namespace raster::tools
