// What raster grade grades, declared next to each lab (docs/GRADING.md): nothing in the grader names a lab.
//
//   labs/<lab>/grading.json        the public scenes: those the lab's README names, which students see
//                                  and grade themselves on (raster grade --public)
//   solutions/<lab>/grading.json   the hidden scenes: variations a student has not seen (other cameras,
//                                  sizes, counts, seeds), kept with the solution by lecturers
//
// Both files have the same form, one JSON object:
//
//   {"title": "Billboards and a particle system",          (optional; the public file's is used)
//    "scenes": [
//      {"name": "start_camera", "number": "1.1", "points": 4,
//       "options": {"width": 1280, "height": 720, "count": 10000,
//                   "camera": {"eye": [0, 0.3, 4], "target": [0, 0, 0]}},
//       "comparison": {"method": "threshold", "rgba": [1, 1, 1, 1]}}]}
//
// name: [a-z0-9_-], unique within the lab (it names the PNGs); number: Gradescope's test number,
// "1.1"; points: > 0; options: raster::SceneOptions overrides (width, height, count, seed, cubes, fog
// "constant"|"height", camera {eye, target}, time: an animated lab's clock in seconds, [0, 600], fov
// the vertical field of view in degrees), every one optional, unset ones keep SceneOptions' defaults
// (camera unset: the lab's registered camera; time unset: the lab's own start); comparison: what raster::Comparison::parse
// reads. Unknown fields are errors (a misspelt "ponts" must not grade a scene for 0 points).
//
// The grader reads these from its own source tree (the location compiled in, --grading-root to
// override), never from a submission.
#pragma once

#include <string>
#include <vector>

#include "raster/image_compare.hpp"
#include "raster/scenes.hpp"

namespace raster::grade {

struct GradedScene {
    std::string name, number;
    double points = 0;
    bool isPublic = true;
    SceneOptions options;
    raster::Comparison comparison;
};

struct LabGrading {
    std::string lab;                  // the lab's name: labs/<lab>/<lab>.cpp, the registered scene <lab>
    std::string title;                // for the reports; may be empty
    std::vector<GradedScene> scenes;  // public first, in file order, then hidden
};

// Reads one grading file: its scenes get isPublic = is_public. Throws Error(BadFile) naming the path
// and the field for a file that is missing, not JSON or wrong in any field.
LabGrading readGradingFile(const std::string& path, const std::string& lab, bool is_public);

// Every lab under `root` that has labs/<lab>/grading.json, in name order, with its public scenes and,
// unless public_only, the hidden ones of solutions/<lab>/grading.json where that file exists. Throws
// Error(BadFile) for a file that cannot be read, Error(InvalidArgument) for scene names or numbers used
// twice in one lab.
std::vector<LabGrading> discoverLabs(const std::string& root, bool public_only);

// "--width 320 --height 180 ...": the options as the lab runner's command line (lab_runner_main.cpp).
std::vector<std::string> runnerOptionArgs(const SceneOptions& options);

}  // namespace raster::grade
