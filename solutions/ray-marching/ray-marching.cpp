// BEGIN NOTE
// Lab: ray marching through a metaball medium (lecture, part 1: "Sugármenetelés") - THE SOLUTION.
//
// The benchmark scene `media` (six metaballs lit by a directional light with shadow rays, a
// Henyey–Greenstein phase function and an ambient term) marched back to front, as the lecture writes
// the recurrence, in two panels: left with the lecture's Euler step, right with the exponential step.
// This is labs/ray-marching/ray-marching.cpp with every `LAB n` place filled in; its image is the one
// the student's is compared with (raster view ray-marching, K and J).
// STAND-IN
//> // Lab: ray marching through a metaball medium (lecture, part 1: "Sugármenetelés").
//> //
//> // The benchmark scene `media` (six metaballs lit by a directional light with shadow rays, a
//> // Henyey–Greenstein phase function and an ambient term) marched back to front, as the lecture writes
//> // the recurrence, in two panels: left with the lecture's Euler step, right with the exponential step.
//> //
//> // As handed out, this file compiles and runs, but neither step moves the light, the phase function is
//> // isotropic, the medium is one ball of constant density and nothing casts a shadow: both panels show
//> // the background. Fill in the five places marked `LAB n`, in order (labs/ray-marching/README.md has
//> // the table):
//> //   LAB 1  eulerStep (left panel)        LAB 2  exponentialStep (right panel)
//> //   LAB 3  henyeyGreenstein              LAB 4  density (the six metaballs)
//> //   LAB 5  shadowTransmittance (the shadow ray)
//> // The grader also marches with few steps (large μ·Δs) and from another light direction.
//> //
//> //   cmake --build build-lab --target raster_tool && build-lab/bin/raster view ray-marching
//> //
//> // In the viewer, K shows the solution's image and J the difference; click a pixel for its history.
// END NOTE
//
// Options: --count N sets the view ray's steps (default 64); --seed S picks the light's direction
// (0: the `media` scene's, else a fixed direction of the upper hemisphere drawn from S).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "raster/lab.hpp"
#include "raster/media/scatter_march.hpp"

namespace {

using namespace raster;

constexpr float kPi = 3.14159265358979f;

// ---- The integrator steps: dL/ds = −μ·L + q over one step of Δs, μ and q constant ----------------

// LAB 1: the lecture's forward Euler step, L + Δs·(q − μ·L).
// BEGIN LAB 1
// slide: euler-step
float eulerStep(float L, float mu, float q, float ds) {
    return L + ds * (q - mu * L);
}
// end slide: euler-step
// STAND-IN
//> // As handed out the step changes nothing: the left panel shows only the background.
//> float eulerStep(float L, float mu, float q, float ds) {
    //> (void)mu, (void)q, (void)ds;
    //> return L;
//> }
// END LAB 1

// BEGIN LAB 2
// slide: exponential-step
// LAB 2: the exponential step, exact for constant μ and q: L·e^{−μΔs} + (q/μ)·(1 − e^{−μΔs}), in a
// form that stays finite for μ → 0 (the limit L + q·Δs).
float exponentialStep(float L, float mu, float q, float ds) {
    const float x = mu * ds;
    if (x == 0.0f) return L + q * ds;
    return L * std::exp(-x) + q * ds * (-std::expm1(-x) / x);
}
// end slide: exponential-step
// STAND-IN
//> // LAB 2: the exponential step, exact for constant μ and q: L·e^{−μΔs} + (q/μ)·(1 − e^{−μΔs}), in a
//> // form that stays finite for μ → 0 (the limit L + q·Δs). It must stay right where μ·Δs is large.
//> // As handed out the step changes nothing: the right panel shows only the background.
//> float exponentialStep(float L, float mu, float q, float ds) {
    //> (void)mu, (void)q, (void)ds;
    //> return L;
//> }
// END LAB 2

// LAB 3: Henyey–Greenstein, per steradian: (1 − g²) / (4π·(1 + g² − 2g·cos θ)^{3/2}).
// BEGIN LAB 3
// slide: henyey-greenstein
float henyeyGreenstein(float g, float cos_theta) {
    const float base = 1.0f + g * g - 2.0f * g * cos_theta;
    return (1.0f - g * g) / (4.0f * kPi * base * std::sqrt(base));
}
// end slide: henyey-greenstein
// STAND-IN
//> // cos θ = d·l, the view ray's direction (from the eye) against the direction towards the light.
//> // (Check the exponent against the lecture's notes: the slide has an erratum.)
//> // As handed out it is isotropic, 1/(4π): the medium is as bright seen against the light as with it.
//> float henyeyGreenstein(float g, float cos_theta) {
    //> (void)g, (void)cos_theta;
    //> return 1.0f / (4.0f * kPi);
//> }
// END LAB 3

struct Ball {
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
};
using Balls = std::array<Ball, 6>;

// LAB 4: the metaball density ρ(x) = Σ_k (1 − u_k)² over the balls with u_k = |x − c_k|²/r_k² < 1.
// BEGIN LAB 4
float density(const Balls& balls, const glm::vec3& x) {
    float rho = 0.0f;
    for (const Ball& ball : balls) {
        const glm::vec3 v = x - ball.centre;
        const float u = glm::dot(v, v) / (ball.radius * ball.radius);
        if (u < 1.0f) rho += (1.0f - u) * (1.0f - u);
    }
    return rho;
}
// STAND-IN
//> // As handed out: one ball of radius 0.8 m and density 1 in the middle of the box, the balls unused.
//> float density(const Balls& balls, const glm::vec3& x) {
    //> (void)balls;
    //> return glm::dot(x, x) < 0.64f ? 1.0f : 0.0f;
//> }
// END LAB 4

// ---- The medium and its light (the lab's own, but for LAB 5) ----------------------------------------

struct Medium {
    Balls balls{};
    glm::vec3 lo{-1.2f, -0.8f, -1.2f}, hi{1.2f, 1.2f, 1.2f};  // the box of medium, metres
    float extinctionScale = 4.0f;                              // μ = 4·ρ, 1/m
    glm::vec3 toLight{0.0f, 1.0f, 0.0f};                       // unit, towards the light
    glm::vec3 sun{14.0f, 13.0f, 11.0f}, ambient{0.10f, 0.12f, 0.18f};
    float g = 0.4f, albedo = 0.9f;
    uint32_t steps = 64, shadowSteps = 6;
};

// The ray o + t·d meets the box for t in [first, second] (first > second where it misses).
std::pair<float, float> boxInterval(const Medium& m, const glm::vec3& o, const glm::vec3& d) {
    float t_near = -INFINITY, t_far = INFINITY;
    for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / d[a];
        float t_lo = (m.lo[a] - o[a]) * inv, t_hi = (m.hi[a] - o[a]) * inv;
        if (t_lo > t_hi) std::swap(t_lo, t_hi);
        t_near = std::max(t_near, t_lo), t_far = std::min(t_far, t_hi);
    }
    return {t_near, t_far};
}

// LAB 5: the shadow ray: the transmittance e^{−τ} from x towards the light through the medium, τ the
// optical depth Σ μ_j·Δl over m.shadowSteps midpoint samples from x to where the ray leaves the box.
// BEGIN LAB 5
float shadowTransmittance(const Medium& m, const glm::vec3& x) {
    const float dl = boxInterval(m, x, m.toLight).second / float(m.shadowSteps);
    float tau = 0.0f;
    for (uint32_t j = 0; j < m.shadowSteps; ++j)
        tau += m.extinctionScale * density(m.balls, x + (float(j) + 0.5f) * dl * m.toLight) * dl;
    return std::exp(-tau);
}
// STAND-IN
//> // boxInterval(m, x, m.toLight).second is the distance to the box's side along the light.
//> // As handed out nothing casts a shadow: the medium is lit everywhere as on its sunny side.
//> float shadowTransmittance(const Medium& m, const glm::vec3& x) {
    //> (void)m, (void)x;
    //> return 1.0f;
//> }
// END LAB 5

// The radiance reaching the eye along d: N steps back to front from the box's far side (background
// L_bg) to its near side, each sampled at its midpoint, with source q = μ·albedo·(p·T_l·E + A). The
// loop is the library's (raster/media/scatter_march.hpp: the one the `media` benchmark scene runs);
// what it marches through, how the light scatters and how a step moves L are this file's places.
struct Places {
    const Medium& m;
    bool euler;  // the step: Euler's (left panel) or the exponential one (right panel)

    Float8 extinction8(Float8 x, Float8 y, Float8 z) const {
        Float8 mu(0.0f);
        for (int l = 0; l < 8; ++l) mu.set(l, m.extinctionScale * density(m.balls, {x[l], y[l], z[l]}));
        return mu;
    }
    float phase(float cos_theta) const { return henyeyGreenstein(m.g, cos_theta); }
    // The shadow ray from each sample of `lanes` (bit l: lane l), one that scatters.
    Float8 shadowTransmittance8(const std::array<Float8, 3>& x, uint32_t lanes, const media::LightAtPoint*) const {
        Float8 t(1.0f);
        for (int l = 0; l < 8; ++l)
            if (lanes >> l & 1u) t.set(l, shadowTransmittance(m, {x[0][l], x[1][l], x[2][l]}));
        return t;
    }
    float step(float L, float mu, float q, float ds) const {
        return euler ? eulerStep(L, mu, q, ds) : exponentialStep(L, mu, q, ds);
    }
};

glm::vec3 march(const Medium& m, const glm::vec3& eye, const glm::vec3& d, glm::vec3 L, bool euler) {
    const auto [t_near, t_far] = boxInterval(m, eye, d);
    const float t0 = std::max(t_near, 0.0f);
    if (!(t0 < t_far)) return L;
    const media::VolumeLight light{m.toLight, m.sun, m.ambient, m.g, m.albedo};
    return media::marchTowardsTheEye(Places{m, euler}, light, eye, d, t0, t_far, m.steps, L);
}

// The `media` scene's six balls (SCENES.md): c_j = frac(0.5 + (k+1)·a_j), centre
// ((2c1−1)·0.7, (2c2−1)·0.45 + 0.2, (2c3−1)·0.7), radius 0.35 + 0.3·c3.
Balls sceneBalls() {
    constexpr double kA[3] = {0.8191725133961645, 0.6710436067037894, 0.5497004779019704};
    Balls balls;
    for (int k = 0; k < 6; ++k) {
        double c[3];
        for (int j = 0; j < 3; ++j) c[j] = std::fmod(0.5 + (k + 1) * kA[j], 1.0);
        balls[k] = {glm::vec3(float((2 * c[0] - 1) * 0.7), float((2 * c[1] - 1) * 0.45 + 0.2),
                              float((2 * c[2] - 1) * 0.7)),
                    float(0.35 + 0.3 * c[2])};
    }
    return balls;
}

// Seed 0: the `media` scene's light; else a direction of the upper hemisphere (y ≥ 0.2) from the seed.
glm::vec3 lightDirection(uint32_t seed) {
    if (seed == 0) return glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    const float u = std::fmod(0.5f + float(seed) * 0.7548777f, 1.0f), v = std::fmod(0.5f + float(seed) * 0.5698403f, 1.0f);
    const float y = 0.2f + 0.8f * v, r = std::sqrt(1.0f - y * y), phi = 2.0f * kPi * u;
    return {r * std::cos(phi), y, r * std::sin(phi)};
}

struct RayIn {
    glm::vec2 ndc;
    RASTER_INPUT_SIGNATURE(RayIn, RASTER_INPUT(ndc, "POSITION", 0))
};
struct RayVertex {
    glm::vec4 position;
};
struct VsRay {
    RayVertex operator()(const RayIn& in) const { return {glm::vec4(in.ndc, 0.5f, 1.0f)}; }
};

// Each pixel's view ray through its panel (left: Euler, right: exponential), marched over L_bg.
struct PsMarch {
    Medium medium;
    glm::vec3 eye{0.0f}, ahead{0.0f, 0.0f, -1.0f}, right{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};
    glm::vec2 panel{1.0f};  // one panel's size, pixels
    glm::vec3 background{0.08f, 0.10f, 0.16f};
    glm::vec4 operator()(const RayVertex& in) const {
        const bool euler = in.position.x < panel.x;
        const float px = euler ? in.position.x : in.position.x - panel.x;
        const float nx = 2.0f * px / panel.x - 1.0f, ny = 1.0f - 2.0f * in.position.y / panel.y;
        const glm::vec3 d = glm::normalize(ahead + nx * right + ny * up);
        return {glm::clamp(march(medium, eye, d, background, euler), 0.0f, 1.0f), 1.0f};
    }
};

const SceneCamera kMarchLabCamera{{0.0f, 0.6f, 3.6f}, {0.0f, 0.1f, 0.0f}};

class MarchLab final : public LabScene {
  public:
    explicit MarchLab(const SceneOptions& o) {
        ps_.medium.balls = sceneBalls();
        ps_.medium.toLight = lightDirection(o.seed);
        ps_.medium.steps = std::max(1u, o.count.value_or(64u));
        const SceneCamera camera = o.camera.value_or(kMarchLabCamera);
        const float tan_y = std::tan(glm::radians(o.fovDegrees.value_or(60.0f)) * 0.5f);
        ps_.panel = glm::vec2(float(std::max(1u, o.width / 2)), float(std::max(1u, o.height)));
        ps_.eye = camera.eye;
        ps_.ahead = glm::normalize(camera.target - camera.eye);
        ps_.right = glm::normalize(glm::cross(ps_.ahead, glm::vec3(0, 1, 0)));
        ps_.up = glm::cross(ps_.right, ps_.ahead) * tan_y;
        ps_.right *= tan_y * ps_.panel.x / ps_.panel.y;
        const std::vector<glm::vec2> triangle = {{-1, -1}, {3, -1}, {-1, 3}};
        triangle_ = VertexBuffer::create(triangle);
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0}};
        layout_ = InputLayout(desc);
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        context.setBlendState(BlendState::opaque());
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setDepthStencilState(DepthStencilState::disabled());
        context.setInputLayout(&layout_);
        context.setVertexBuffer(0, &triangle_);
        context.draw(VsRay{}, ps_, 3);
    }

  private:
    PsMarch ps_;
    VertexBuffer triangle_;
    InputLayout layout_;
};

}  // namespace

RASTER_LAB("ray-marching", "Lab: ray marching through a metaball medium (lecture, part 1)", MarchLab,
           kMarchLabCamera)
