// The lecture's part-1 figures drawn by ray marching (NOTES.md, part 1), each a full-screen pixel shader
// per panel that marches the pixel's view ray back to front through the `media` scene's six metaballs
// (raster/media/figure_march.hpp) in front of an analytic background:
//   media-absorption  a medium that only absorbs (q = 0; σa per unit density, grey) before a checkered
//                     room (a back wall and a floor): the room darkens through it, L = L_bg·e^{−∫μ ds}.
//   media-emission    a medium that only emits (μ = 0; an orange ε per unit density) before the same
//                     room, dimmed: it glows, L = L_bg + ∫q ds, and hides nothing.
//   media-scattering  three panels, left to right: isotropic, Rayleigh, Henyey–Greenstein (g = 0.7).
//                     A white, scattering cloud (albedo 0.95) lit by a directional light from behind
//                     it and a little above (its disc drawn in the sky above the cloud), with shadow
//                     rays and a faint ambient term: the view looks towards the light, where HG's
//                     forward lobe lights the cloud's thin edges brightly and Rayleigh (symmetric,
//                     3/(16π)·(1 + cos²θ)) stays close to isotropic. Shown as 1 − e^{−L} per channel,
//                     so that HG's peak (19 times isotropic's) does not clip.
//   media-euler       three panels, left to right: the lecture's forward Euler step and the exponential
//                     step, both with kEulerFigureSteps steps per ray, and the converged reference (the
//                     midpoint exponential step, kReferenceSteps steps). The medium absorbs and emits
//                     towards a grey (q = μ·0.8, so every true radiance lies in [0, 1]); where μΔs > 2
//                     Euler's radiance oscillates and blows up. Shown in false colour: grey where the
//                     radiance is in [0, 1], red where it exceeds 1, blue where it is negative (brighter
//                     the further out: log10 of the excess over two decades).
// --sigma R,G,B replaces media-absorption's σa, --source R,G,B media-emission's ε (per unit density;
// 0 gives the background alone).
//
// Drawn through the teaching pipeline (raster/teaching_draw.hpp): figures, compiled in seconds.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "raster/media/figure_march.hpp"
#include "raster/shaders/media.hpp"
#include "raster/teaching_draw.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

// The room: a back wall at z = kWallZ and a floor at y = kFloorY (metres; the medium's box spans
// z ∈ [−1.2, 1.2], y ∈ [−0.8, 1.2]), checkered in squares of kChecker.
constexpr float kWallZ = -1.9f, kFloorY = -0.85f, kChecker = 0.4f;

// What lies behind the medium, as radiance along a view ray: the room (each surface a constant
// radiance per checker colour, the floor brighter than the wall) or a sky gradient with the light's disc.
struct Backdrop {
    bool room = true;
    glm::vec3 light{0.9f}, dark{0.3f};  // the checker's two radiances (room)
    glm::vec3 horizon{0.0f}, zenith{0.0f};  // the sky's (no room)
    glm::vec3 sunDirection{0.0f, 1.0f, 0.0f}, sunRadiance{0.0f};
    float sunCos = 1.0f;  // cos of the disc's angular radius

    glm::vec3 radiance(const glm::vec3& eye, const glm::vec3& d) const {
        if (!room) {
            const glm::vec3 sky = glm::mix(horizon, zenith, std::sqrt(std::clamp(d.y, 0.0f, 1.0f)));
            return glm::dot(d, sunDirection) > sunCos ? sky + sunRadiance : sky;
        }
        const float t_wall = d.z < 0.0f ? (kWallZ - eye.z) / d.z : INFINITY;
        const float t_floor = d.y < 0.0f ? (kFloorY - eye.y) / d.y : INFINITY;
        const bool floor = t_floor < t_wall;
        const glm::vec3 p = eye + d * (floor ? t_floor : t_wall);
        const float u = p.x / kChecker, v = (floor ? p.z : p.y) / kChecker;
        const bool odd = (int64_t(std::floor(u)) + int64_t(std::floor(v))) & 1;
        return (odd ? dark : light) * (floor ? 1.0f : 0.8f);
    }
};

// L in [0, 1] as grey (its own colour); above 1 red, below 0 blue, brighter the further out.
glm::vec3 outOfRangeColour(const glm::vec3& L) {
    const float high = std::max({L.x, L.y, L.z}), low = std::min({L.x, L.y, L.z});
    if (high <= 1.0f && low >= 0.0f) return L;
    const float excess = high > 1.0f ? high - 1.0f : -low;
    const float strength = 0.6f + 0.4f * std::clamp(std::log10(1.0f + excess) / 2.0f, 0.0f, 1.0f);
    return (high > 1.0f ? glm::vec3(1.0f, 0.12f, 0.06f) : glm::vec3(0.1f, 0.35f, 1.0f)) * strength;
}

// One panel: the pixel's view ray marched through the medium before the backdrop.
struct PsFigure {
    glm::mat4 invViewProj{1.0f};
    glm::vec3 eye{0.0f};
    const media::MetaballVolume* volume = nullptr;
    media::FigureMedium medium;
    media::VolumeLight light;  // its g and albedo unused: the medium's
    media::FigureMarch march;
    Backdrop backdrop;
    bool falseColour = false;  // outOfRangeColour, else clamped to [0, 1]
    bool toneMap = false;      // 1 − e^{−L} per channel (HG's forward peak is ~20 times isotropic's)

    glm::vec4 operator()(const shaders::MediaRayVertex& in) const {
        const glm::vec3 d = shaders::viewRay(invViewProj, in.ndc);
        const glm::vec3 L = media::marchFigure(*volume, medium, light, march, eye, d, backdrop.radiance(eye, d));
        if (falseColour) return {outOfRangeColour(L), 1.0f};
        return {toneMap ? 1.0f - glm::exp(-L) : glm::clamp(L, 0.0f, 1.0f), 1.0f};
    }
};

constexpr uint32_t kEulerFigureSteps = 8;
constexpr uint32_t kReferenceSteps = 512;

// The checkered room in light greys and blue-greys.
Backdrop roomBackdrop(float brightness) {
    Backdrop b;
    b.light = glm::vec3(0.92f, 0.9f, 0.84f) * brightness;
    b.dark = glm::vec3(0.24f, 0.3f, 0.42f) * brightness;
    return b;
}

// The panels of one figure (one, or three side by side), each a PsFigure without its camera.
std::vector<PsFigure> figurePanels(std::string_view name, const SceneOptions& o) {
    PsFigure p;
    p.march.steps = 64;
    if (name == "media-absorption") {
        p.medium.absorption = o.fogSigma.value_or(glm::vec3(1.6f));
        p.backdrop = roomBackdrop(1.0f);
        return {p};
    }
    if (name == "media-emission") {
        p.medium.emission = o.fogSource.value_or(glm::vec3(1.5f, 0.6f, 0.2f));
        p.backdrop = roomBackdrop(0.25f);
        return {p};
    }
    if (name == "media-scattering") {
        p.medium.absorption = glm::vec3(0.3f), p.medium.scattering = glm::vec3(5.7f);
        p.light.toLight = glm::normalize(glm::vec3(0.12f, 0.2f, -1.0f));
        p.light.sun = glm::vec3(12.0f, 11.4f, 10.4f);
        p.light.ambient = glm::vec3(0.06f, 0.08f, 0.12f);
        p.toneMap = true;
        p.backdrop.room = false;
        p.backdrop.horizon = {0.10f, 0.12f, 0.17f}, p.backdrop.zenith = {0.02f, 0.04f, 0.10f};
        p.backdrop.sunDirection = p.light.toLight, p.backdrop.sunRadiance = glm::vec3(4.0f);
        p.backdrop.sunCos = std::cos(0.02f);
        std::vector<PsFigure> panels(3, p);
        panels[0].medium.phase = media::PhaseFunction::isotropic;
        panels[1].medium.phase = media::PhaseFunction::rayleigh;
        panels[2].medium.phase = media::PhaseFunction::henyeyGreenstein, panels[2].medium.g = 0.7f;
        return panels;
    }
    // media-euler: q = μ·0.8, grey over a grey room.
    p.medium.absorption = glm::vec3(12.0f), p.medium.emission = glm::vec3(9.6f);
    p.backdrop.light = glm::vec3(0.55f), p.backdrop.dark = glm::vec3(0.15f);
    p.falseColour = true;
    std::vector<PsFigure> panels(3, p);
    panels[0].march = {media::StepRule::euler, kEulerFigureSteps, 1};
    panels[1].march = {media::StepRule::exponential, kEulerFigureSteps, 1};
    panels[2].march = {media::StepRule::midpointExponential, kReferenceSteps, 1};
    return panels;
}

class MediaFigureScene final : public Scene {
  public:
    MediaFigureScene(std::string_view name, const SceneOptions& o)
        : name_(name),
          volume_(media::makeMetaballVolume(media::mediaSceneMetaballs(), media::mediaSceneBox(), 1.0f, 1)),
          panels_(figurePanels(name, o)) {
        SceneOptions panel = o;
        panel.width = std::max(1u, o.width / uint32_t(panels_.size()));
        panel_width_ = float(o.width) / float(panels_.size());  // the last panel reaches the right edge
        const SceneCamera camera = o.camera.value_or(defaultCamera(name));
        const glm::mat4 inv_view_proj = glm::inverse(sceneProjection(panel) * sceneView(camera));
        for (PsFigure& p : panels_) p.invViewProj = inv_view_proj, p.eye = camera.eye, p.volume = &volume_;
    }
    std::string_view name() const override { return name_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        triangle_.bind(context);
        for (size_t k = 0; k < panels_.size(); ++k) {
            context.setViewport({panel_width_ * float(k), 0.0f, panel_width_, float(color.height()), 0.0f, 1.0f});
            context.draw(vs_, panels_[k], 3);
        }
    }

  private:
    std::string name_;
    media::MetaballVolume volume_;
    std::vector<PsFigure> panels_;
    float panel_width_ = 1.0f;
    FullScreenTriangle triangle_;
    shaders::VsMediaRay vs_;
};

}  // namespace

std::vector<std::string_view> mediaFigureNames() {
    return {"media-absorption", "media-emission", "media-scattering", "media-euler"};
}

std::unique_ptr<Scene> makeMediaFigureScene(std::string_view name, const SceneOptions& options) {
    return std::make_unique<MediaFigureScene>(name, options);
}

}  // namespace raster
