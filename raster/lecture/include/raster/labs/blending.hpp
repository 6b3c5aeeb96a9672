// The blending lab's scene (labs/blending/): everything but the student's states, sort key and
// comparator. The lab's file (and its solution, which fills the file's places) defines
//
//   BlendState additiveBlend()                 LAB 1     DepthStencilState noDepthTest()        LAB 2
//   DepthStencilState depthTestNoWrite()       LAB 3     BlendState overBlend()                  LAB 4
//   float viewDepth(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead)                           LAB 5
//   bool drawnBefore(const SortItem& a, const SortItem& b)                                        LAB 6
//
// and registers a scene that hands them to BlendingScene: five panels of (width / 3) × (height / 2)
// pixels, three on top, two centred below, each drawing the occluder (opaque: depth test and write)
// and then soft discs with its figure's states. The particles fill a box around the occluder, half in
// front of it, half behind, coloured blue (far) to yellow (near).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "raster/lab.hpp"

namespace raster::blending_lab {

// A particle to sort: its index and its sort key.
struct SortItem {
    uint32_t index;
    float depth;
};

// The view depth of `position` along the camera's forward axis `ahead` (unit length), from `eye`.
using ViewDepthFn = float (*)(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead);
// True when `a` must be drawn before `b`; checked to be a strict weak ordering before it sorts.
using DrawnBeforeFn = bool (*)(const SortItem& a, const SortItem& b);

// One panel: its title, the particles' states, and whether they are drawn sorted.
struct Figure {
    const char* title;
    BlendState blend;
    DepthStencilState depth;
    bool sorted;  // back to front with viewDepth and drawnBefore; else in storage order
};

// The lecture's five figures: top row additive (depth test and write, no depth test, test without
// write), bottom row "over" with test without write (storage order, then sorted).
std::vector<Figure> lectureFigures(const BlendState& additive, const DepthStencilState& noTest,
                                   const DepthStencilState& testNoWrite, const BlendState& over);

// Where the lab looks from.
inline const SceneCamera kBlendingCamera{{0, 0.2f, 3.2f}, {0, -0.2f, 0}};

// The scene: `figures` (lectureFigures) drawn panel by panel; the sorted ones in the order that
// `viewDepth` and `drawnBefore` give (a named error where drawnBefore is not a strict weak ordering).
class BlendingScene : public LabScene {
  public:
    BlendingScene(const SceneOptions& o, std::vector<Figure> figures, ViewDepthFn viewDepth,
                  DrawnBeforeFn drawnBefore);
    void render(Context& context, RenderTarget& color, DepthTarget& depth) override;

  private:
    std::vector<uint32_t> backToFront() const;

    SceneOptions panel_;
    ParticleSceneData data_;  // the occluder and P·V for the panel's aspect
    std::vector<Figure> figures_;
    ViewDepthFn view_depth_;
    DrawnBeforeFn drawn_before_;
    InputLayout layout_;
    std::vector<glm::vec3> centres_;
    VertexBuffer vertices_;
    IndexBuffer stored_;
    glm::mat4 view_proj_{1.0f};
    glm::vec3 eye_{0.0f}, ahead_{0.0f, 0.0f, -1.0f};
};

}  // namespace raster::blending_lab
