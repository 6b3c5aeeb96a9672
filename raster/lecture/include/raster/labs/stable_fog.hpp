// The stable-fog lab's scene (labs/stable-fog/): everything but the student's fog functions and the
// two pixel shaders that call them. The lab's file (and its solution, which fills the file's places)
// defines the shaders and registers
//
//   StableFogScene<PsFogged, PsSky>
//
// four panels of (width / 2) × (height / 2) pixels, constant and black fog on top, coloured and height
// fog below, each drawing the world part by part (FogWorldData, scenes.hpp), then the sky where nothing
// was drawn. What the scene hands the shaders, by aggregate initialisation in this order of members:
//   Fogged{medium, rays, albedo}   the world's parts: reads LitVertex
//   Sky{medium, rays}              a full-screen triangle at depth 1: reads SkyVertex
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <vector>

#include "raster/lab.hpp"

namespace raster::fog_lab {

// A homogeneous medium per channel (R, G, B): extinction sigma (1/m) and source term q (radiance per
// metre). Height fog: both scaled by e^{b·y} at height y (b < 0: thinner higher up); constant fog: b
// is not used.
struct Medium {
    glm::vec3 sigma{0.0f};
    glm::vec3 q{0.0f};
    float b = 0.0f;
    bool height = false;
};

// Each panel's camera: the pixel's view ray from its centre (SV_Position) and the camera's axes, so
// that a camera looking level gives rays with dy = 0 exactly along a panel's middle row.
struct PanelRays {
    glm::vec3 eye{0.0f}, ahead{0.0f, 0.0f, -1.0f}, right{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};
    glm::vec2 origin{0.0f}, size{1.0f};  // the panel's viewport, pixels
    glm::vec3 direction(float px, float py) const {
        const float nx = 2.0f * (px - origin.x) / size.x - 1.0f, ny = 1.0f - 2.0f * (py - origin.y) / size.y;
        return glm::normalize(ahead + nx * right + ny * up);
    }
};

// The world's vertex format, what its vertex shader passes on and the shader (raster/shaders/fog.hpp).
using shaders::LitIn;
using shaders::LitVertex;
using shaders::VsLit;

struct SkyIn {
    glm::vec2 ndc;
    RASTER_INPUT_SIGNATURE(SkyIn, RASTER_INPUT(ndc, "POSITION", 0))
};
struct SkyVertex {
    glm::vec4 position;
};
// A full-screen triangle at depth 1: drawn only where no surface is.
struct VsSky {
    SkyVertex operator()(const SkyIn& in) const { return {glm::vec4(in.ndc, 1.0f, 1.0f)}; }
};

// The panels' media (the lecture's scenes fog-constant, fog-black, fog-coloured and fog-height draw the
// same): grey-blue fog; the same without its source; three times as dense and sand-coloured; the
// benchmark's height fog. The options' sigma and source replace every panel's (black fog keeps q = 0),
// their falloff the height fog's.
std::vector<Medium> panelMedia(const SceneOptions& o);
// The panels' rays for the options' camera (or kCamera) and field of view, a panel's size and origin 0.
PanelRays panelRays(const SceneOptions& o, const SceneCamera& camera);

inline constexpr SceneCamera kCamera{{0, 1.5f, 6}, {0, 0.5f, -10}};

template <class Fogged, class Sky>
class StableFogScene final : public LabScene {
  public:
    explicit StableFogScene(const SceneOptions& o)
        : world_(o.cubes), media_(panelMedia(o)), rays_(panelRays(o, o.camera.value_or(kCamera))) {
        SceneOptions panel = o;
        panel.width = std::max(1u, o.width / 2), panel.height = std::max(1u, o.height / 2);
        vs_.viewProj = sceneProjection(panel) * sceneView(o.camera.value_or(kCamera));
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        context.setBlendState(BlendState::opaque());
        context.setPrimitiveTopology(Topology::TriangleList);
        for (size_t k = 0; k < media_.size(); ++k) {
            PanelRays rays = rays_;
            rays.origin = glm::vec2(float(k % 2) * rays.size.x, float(k / 2) * rays.size.y);
            context.setViewport({rays.origin.x, rays.origin.y, rays.size.x, rays.size.y, 0.0f, 1.0f});
            context.setDepthStencilState({true, true, ComparisonFunc::Less});
            context.setInputLayout(&world_.layout);
            context.setVertexBuffer(0, &world_.lit);
            for (const FogWorldData::Part& part : world_.parts)
                if (part.count > 0)
                    context.draw(vs_, Fogged{media_[k], rays, part.albedo}, part.count, part.first);
            context.setDepthStencilState({true, true, ComparisonFunc::LessEqual});
            context.setInputLayout(&world_.skyLayout);
            context.setVertexBuffer(0, &world_.sky);
            context.draw(VsSky{}, Sky{media_[k], rays}, 3);
        }
    }

  private:
    FogWorldData world_;
    std::vector<Medium> media_;
    PanelRays rays_;
    VsLit vs_;
};

}  // namespace raster::fog_lab
