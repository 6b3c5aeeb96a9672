// Lab: fog in the pixel shader, in stable form (lecture 11, part 2).
//
// The lecture's four fog figures as four panels of one image, each over the same world (a checkered
// ground and a lattice of coloured cubes) with the sky infinitely far away: top left constant fog, top
// right "zero source term, black fog", bottom left coloured fog that hides the background, bottom
// right exponential height fog. Along a view ray through a medium of extinction σ and source term q
// (dL/ds = −σ·L + q), a surface of radiance L0 at distance s reaches the eye as
//   L(s) = L0·e^{−σ·s} + (q/σ)·(1 − e^{−σ·s})
//
// As handed out, this file compiles and runs, but there is no fog and no sky: four panels of the
// world, clear, under a black sky. Fill in the four places marked `LAB n`, in order; each puts one
// panel right (labs/stable-fog/README.md has the table):
//   LAB 1  transmittance (black fog)     LAB 2  inScattered (constant fog)
//   LAB 3  PsSky, the sky at s = ∞       LAB 4  opticalDepth (height fog)
// Write them so that they stay right for every medium the grader may try: a channel with σ = 0, very
// thin fog (σ = 1e-7), a camera looking exactly level, a camera high above thinning fog looking down.
// A NaN or an infinity on the way shows as a black or white pixel, and the grader names it.
//
//   cmake --build build-lab --target raster_tool && build-lab/bin/raster view stable-fog
//   build-lab/bin/raster render stable-fog --out-dir out --sigma 0.05,0,0.07   (try other media)
//
// In the viewer, K shows the solution's image and J the difference; click a pixel for its history.
#include <algorithm>
#include <cmath>
#include <limits>

#include "raster/labs/stable_fog.hpp"

namespace {

using namespace raster;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Medium (sigma, q, b, height), PanelRays, the vertex formats, the panels' media and the scene that
// draws the two pixel shaders below are the lab's scaffolding:
// raster/lecture/include/raster/labs/stable_fog.hpp.
using fog_lab::LitVertex;
using fog_lab::Medium;
using fog_lab::PanelRays;
using fog_lab::SkyVertex;
using fog_lab::StableFogScene;

// ---- The fog functions ----------------------------------------------------------------------------
// tau is the optical depth per unit sigma: the distance s for constant fog, τ(s) for height fog; it
// may be +infinity (the sky).

// LAB 1: black fog — "zero source term" (q = 0): the medium only takes light away. Return the share
// of L0 that reaches the eye over optical depth tau, e^{−σ·τ}, per channel. What must it be for a
// channel with σ = 0, even when tau = ∞ (what is 0·∞ in floating point)?
// As handed out everything is transmitted: no fog at all. The top right panel is black fog.
glm::vec3 transmittance(glm::vec3 sigma, float tau) {
    (void)sigma, (void)tau;
    return glm::vec3(1.0f);
}

// LAB 2: the constant fog's closed form, its second term: the light the medium adds over optical
// depth tau, (q/σ)·(1 − e^{−σ·τ}), per channel. In stable form: finite for σ = 0 (its limit as σ → 0),
// for very thin fog (σ·τ ~ 1e-6: what is 1 − e^{−x} in float then?) and for tau = ∞.
// As handed out the medium adds nothing: the top left panel fades to black instead of to the fog.
glm::vec3 inScattered(glm::vec3 sigma, glm::vec3 q, float tau) {
    (void)sigma, (void)q, (void)tau;
    return glm::vec3(0.0f);
}

// The radiance reaching the eye from a surface of radiance L0 seen through optical depth tau.
glm::vec3 fogged(glm::vec3 L0, const Medium& m, float tau) {
    return L0 * transmittance(m.sigma, tau) + inScattered(m.sigma, m.q, tau);
}

// LAB 4: the height fog's optical depth. σ(y) = σ·e^{b·y} and q(y) = q·e^{b·y} (b < 0: thinner
// higher up) along the ray y(t) = y0 + dy·t (dy: the y of its unit direction) give the constant fog's
// form over τ(s) = ∫0..s e^{b·y(t)} dt instead of s:
//   τ(s) = (e^{b·(y0 + dy·s)} − e^{b·y0}) / (b·dy)
// Return it in a form that stays finite and accurate: for a level ray (dy = 0: the limit as b·dy → 0),
// for s = ∞ (the sky: finite only when the ray rises into thinner fog), and for a camera high in thin
// fog looking down (e^{b·y0} rounds to 0 and e^{b·dy·s} to ∞ in float; their product does not).
// As handed out τ = s: the bottom right panel is constant fog.
float opticalDepth(float y0, float dy, float s, float b) {
    (void)y0, (void)dy, (void)b;
    return s;
}

// The height fog: the constant fog's form over τ(s) instead of s,
//   L = L0·e^{−σ·τ(s)} + (q/σ)·(1 − e^{−σ·τ(s)})
// — the whole σ·τ(s) = σ/(b·dy)·(e^{b(y0 + dy·s)} − e^{b·y0}) in the exponent.
glm::vec3 heightFog(glm::vec3 L0, const Medium& m, float y0, float dy, float s) {
    return fogged(L0, m, opticalDepth(y0, dy, s, m.b));
}

// ---- The pixel shaders (the scene: raster/labs/stable_fog.hpp) ------------------------------------

// The radiance at the eye along the panel's ray through (px, py) from a surface L0 at distance s.
glm::vec3 throughTheMedium(glm::vec3 L0, const Medium& m, const PanelRays& rays, float px, float py,
                           float s) {
    if (!m.height) return fogged(L0, m, s);
    return heightFog(L0, m, rays.eye.y, rays.direction(px, py).y, s);
}

// A diffuse surface, L0 = albedo·(0.2 + 0.8·max(0, n·l)), seen through the panel's medium.
struct PsFogged {
    Medium medium;
    PanelRays rays;
    glm::vec3 albedo{0.7f};
    glm::vec4 operator()(const LitVertex& in) const {
        const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
        const glm::vec3 L0 =
            albedo * (0.2f + 0.8f * std::max(0.0f, glm::dot(glm::normalize(in.normal), light)));
        const float s = glm::length(in.worldPos - rays.eye);
        return {throughTheMedium(L0, medium, rays, in.position.x, in.position.y, s), 1.0f};
    }
};

// LAB 3: the sky, drawn where no surface is. The lecture: "the background should be infinitely far
// away" and shine nothing of its own (L0 = 0): what reaches the eye along the pixel's ray is what the
// medium adds over s = ∞ (throughTheMedium, at the pixel centre in.position.x, in.position.y).
// As handed out the sky is black: coloured fog does not hide the background (the bottom left panel).
struct PsSky {
    Medium medium;
    PanelRays rays;
    glm::vec4 operator()(const SkyVertex& in) const {
        (void)in;
        return {0.0f, 0.0f, 0.0f, 1.0f};
    }
};

using FogLab = StableFogScene<PsFogged, PsSky>;

}  // namespace

RASTER_LAB("stable-fog", "Lab: fog in the pixel shader, in stable form (lecture 11, part 2)", FogLab,
           fog_lab::kCamera)
