// The ray-marching lab's scene (raster/labs/ray_marching.hpp): the box, the march that calls the
// student's functions, the balls, the light and the full-image triangle.
#include <algorithm>
#include <cmath>
#include <vector>

#include "raster/labs/ray_marching.hpp"
#include "raster/media/scatter_march.hpp"
#include "raster/teaching_draw.hpp"

namespace raster::ray_lab {

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

namespace {

// The lab's places in the library's loop of single scattering (raster/media/scatter_march.hpp: the one
// the `media` benchmark scene runs): what it marches through, how the light scatters and how a step
// moves L are the student's functions.
struct Places {
    const Answers& answers;
    const Medium& m;
    bool euler;  // the step: Euler's (left panel) or the exponential one (right panel)

    Float8 extinction8(Float8 x, Float8 y, Float8 z) const {
        Float8 mu(0.0f);
        for (int l = 0; l < 8; ++l) mu.set(l, m.extinctionScale * answers.density(m.balls, {x[l], y[l], z[l]}));
        return mu;
    }
    float phase(float cos_theta) const { return answers.henyeyGreenstein(m.g, cos_theta); }
    // The shadow ray from each sample of `lanes` (bit l: lane l), one that scatters.
    Float8 shadowTransmittance8(const std::array<Float8, 3>& x, uint32_t lanes, const media::LightAtPoint*) const {
        Float8 t(1.0f);
        for (int l = 0; l < 8; ++l)
            if (lanes >> l & 1u) t.set(l, answers.shadowTransmittance(m, {x[0][l], x[1][l], x[2][l]}));
        return t;
    }
    float step(float L, float mu, float q, float ds) const {
        return euler ? answers.eulerStep(L, mu, q, ds) : answers.exponentialStep(L, mu, q, ds);
    }
};

}  // namespace

glm::vec3 march(const Answers& answers, const Medium& m, const glm::vec3& eye, const glm::vec3& d,
                glm::vec3 L, bool euler) {
    const auto [t_near, t_far] = boxInterval(m, eye, d);
    const float t0 = std::max(t_near, 0.0f);
    if (!(t0 < t_far)) return L;
    const media::VolumeLight light{m.toLight, m.sun, m.ambient, m.g, m.albedo};
    return media::marchTowardsTheEye(Places{answers, m, euler}, light, eye, d, t0, t_far, m.steps, L);
}

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

glm::vec3 lightDirection(uint32_t seed) {
    constexpr float kPi = 3.14159265358979f;
    if (seed == 0) return glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    const float u = std::fmod(0.5f + float(seed) * 0.7548777f, 1.0f),
                v = std::fmod(0.5f + float(seed) * 0.5698403f, 1.0f);
    const float y = 0.2f + 0.8f * v, r = std::sqrt(1.0f - y * y), phi = 2.0f * kPi * u;
    return {r * std::cos(phi), y, r * std::sin(phi)};
}

namespace {

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

// Each pixel's view ray through its panel (left: Euler, right: exponential), marched over the background.
struct PsMarch {
    const Answers* answers = nullptr;
    const Medium* medium = nullptr;
    glm::vec3 eye{0.0f}, ahead{0.0f, 0.0f, -1.0f}, right{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};
    glm::vec2 panel{1.0f};  // one panel's size, pixels
    glm::vec3 background{0.08f, 0.10f, 0.16f};
    glm::vec4 operator()(const RayVertex& in) const {
        const bool euler = in.position.x < panel.x;
        const float px = euler ? in.position.x : in.position.x - panel.x;
        const float nx = 2.0f * px / panel.x - 1.0f, ny = 1.0f - 2.0f * in.position.y / panel.y;
        const glm::vec3 d = glm::normalize(ahead + nx * right + ny * up);
        return {glm::clamp(march(*answers, *medium, eye, d, background, euler), 0.0f, 1.0f), 1.0f};
    }
};

}  // namespace

RayMarchingScene::RayMarchingScene(const SceneOptions& o, Answers answers) : answers_(answers) {
    medium_.balls = sceneBalls();
    medium_.toLight = lightDirection(o.seed);
    medium_.steps = std::max(1u, o.count.value_or(64u));
    const SceneCamera camera = o.camera.value_or(kCamera);
    const float tan_y = std::tan(glm::radians(o.fovDegrees.value_or(60.0f)) * 0.5f);
    panel_ = glm::vec2(float(std::max(1u, o.width / 2)), float(std::max(1u, o.height)));
    eye_ = camera.eye;
    ahead_ = glm::normalize(camera.target - camera.eye);
    right_ = glm::normalize(glm::cross(ahead_, glm::vec3(0, 1, 0)));
    up_ = glm::cross(right_, ahead_) * tan_y;
    right_ *= tan_y * panel_.x / panel_.y;
    const std::vector<glm::vec2> triangle = {{-1, -1}, {3, -1}, {-1, 3}};
    triangle_ = VertexBuffer::create(triangle);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0}};
    layout_ = InputLayout(desc);
}

void RayMarchingScene::render(Context& context, RenderTarget& color, DepthTarget& depth) {
    beginSceneFrame(context, color, depth);
    context.setBlendState(BlendState::opaque());
    context.setPrimitiveTopology(Topology::TriangleList);
    context.setDepthStencilState(DepthStencilState::disabled());
    context.setInputLayout(&layout_);
    context.setVertexBuffer(0, &triangle_);
    context.draw(VsRay{}, PsMarch{&answers_, &medium_, eye_, ahead_, right_, up_, panel_}, 3);
}

}  // namespace raster::ray_lab
