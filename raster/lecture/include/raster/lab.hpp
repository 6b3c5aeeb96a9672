// What a lab's file includes. A lab is one .cpp file, labs/<name>/<name>.cpp, that builds a scene
// of the lecture with some of its parts left for the student (marked `LAB n`); the same file
// filled in is solutions/<name>/<name>.cpp. Both are compiled into build/bin/raster:
//
//   raster view <name>           the student's scene; K shows the solution's image, J the difference
//   raster render <name>         writes <name>.png (and <name>@solution.png when no name is given)
//   raster trace <name> --pixel X,Y
//
// A lab file defines its types in an unnamed namespace (the student's and the solution's file
// define the same names and end up in one program) and ends with
//
//   RASTER_LAB("billboards", "Lab: billboards and particles (lecture 11, part 3)", BillboardsLab,
//              (raster::SceneCamera{{0, 0.3f, 4}, {0, 0, 0}}));
//
// where BillboardsLab derives from raster::LabScene and has a constructor taking
// const raster::SceneOptions& (size, camera and counts, already checked by makeScene).
#pragma once

#include <memory>
#include <string>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/shaders/billboard.hpp"
#include "raster/shaders/fog.hpp"
#include "raster/teaching_draw.hpp"

namespace raster {

// A lab's scene: its name is the one it was registered under (the solution's carries "@solution").
class LabScene : public Scene {
  public:
    std::string_view name() const final { return name_; }
    void setName(std::string name) { name_ = std::move(name); }

  private:
    std::string name_;
};

// Registers an entry at construction; RASTER_LAB makes one static instance per lab file.
struct SceneRegistration {
    explicit SceneRegistration(SceneEntry entry) { registerScene(std::move(entry)); }
};

}  // namespace raster

// The build defines RASTER_LAB_SUFFIX: "" for labs/, "@solution" for solutions/.
#ifndef RASTER_LAB_SUFFIX
#define RASTER_LAB_SUFFIX ""
#endif

#define RASTER_LAB(lab_name, lab_title, SceneType, lab_camera)                                     \
    namespace {                                                                                    \
    const ::raster::SceneRegistration raster_lab_registration{::raster::SceneEntry{                \
        std::string(lab_name) + RASTER_LAB_SUFFIX,                                                 \
        std::string(lab_title) + (sizeof(RASTER_LAB_SUFFIX) > 1 ? " - solution" : ""), lab_camera, \
        [](const std::string& registered,                                                          \
           const ::raster::SceneOptions& options) -> std::unique_ptr<::raster::Scene> {            \
            auto scene = std::make_unique<SceneType>(options);                                     \
            scene->setName(registered);                                                            \
            return scene;                                                                          \
        }}};                                                                                       \
    }
