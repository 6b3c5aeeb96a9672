// The slides' diagrams (slides/README.md), drawn through the pipeline as flat-coloured triangles in
// clip space, one figure a scene:
//   phase-polar        the phase functions of raster/media/phase_functions.hpp as polar plots: in the
//                      direction at angle θ from the light's travel (+x, the light arrives from the
//                      left along the grey axis), the distance p(cos θ) from the scattering point.
//                      Left panel, one scale: isotropic (grey circle), Rayleigh (blue), Henyey–Greenstein
//                      g = 0.3 (orange) and g = −0.3 (green). Right panel, its own scale (HG 0.7's forward
//                      peak is 19 times isotropic's): isotropic, HG g = 0.7 (orange) and g = −0.7 (green).
//   media-march-steps  ray marching, the steps along one ray: the `media` scene's view ray through the
//                      image centre marched in kMarchSteps steps (raster/media/metaball_march.hpp, no
//                      empty-space skipping). Along s from the box's entry t0 (left) to its exit t1
//                      (right): the step boundaries (grey ticks), each sample's extinction μ_i·Δs as a
//                      bar (blue, over the step it stands for), the sample points (white dots), the
//                      transmittance T before each step (white line, 1 at the top) and the radiance
//                      gathered so far, L_i (orange line, its final value at the top).
// Drawn through the teaching pipeline (raster/teaching_draw.hpp): figures, compiled in seconds.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "raster/media/metaball_march.hpp"
#include "raster/media/phase_functions.hpp"
#include "raster/teaching_draw.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

struct PlotIn {
    glm::vec2 position;  // clip-space x, y (w = 1)
    glm::vec3 colour;
    RASTER_INPUT_SIGNATURE(PlotIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(colour, "COLOR", 0))
};
struct PlotVertex {
    glm::vec4 position;
    glm::vec3 colour;
};
struct VsPlot {
    PlotVertex operator()(const PlotIn& in) const { return {glm::vec4(in.position, 0.0f, 1.0f), in.colour}; }
};
struct PsPlot {
    glm::vec4 operator()(const PlotVertex& in) const { return {in.colour, 1.0f}; }
};

constexpr glm::vec3 kBackground{0.07f, 0.08f, 0.11f}, kAxis{0.45f, 0.47f, 0.52f}, kWhite{0.95f, 0.95f, 0.92f};
constexpr glm::vec3 kIsotropic{0.75f, 0.75f, 0.75f}, kBlue{0.35f, 0.6f, 1.0f};
constexpr glm::vec3 kOrange{1.0f, 0.6f, 0.15f}, kGreen{0.4f, 0.85f, 0.4f};
constexpr float kPi = 3.14159265358979f;
constexpr uint32_t kCurveSegments = 360;
constexpr uint32_t kMarchSteps = 24;

// Triangles in pixel coordinates (x right, y down, the image's), stored in clip space.
class Plot {
  public:
    Plot(float width, float height) : width_(width), height_(height) {}
    void rect(glm::vec2 a, glm::vec2 b, glm::vec3 c) {
        quad({a.x, a.y}, {b.x, a.y}, {b.x, b.y}, {a.x, b.y}, c);
    }
    // A segment `thickness` pixels wide, its ends squared off.
    void line(glm::vec2 a, glm::vec2 b, float thickness, glm::vec3 c) {
        const glm::vec2 d = b - a;
        const float length = std::sqrt(d.x * d.x + d.y * d.y);
        if (length <= 0.0f) return;
        const glm::vec2 n = glm::vec2(-d.y, d.x) * (0.5f * thickness / length);
        const glm::vec2 t = d * (0.5f * thickness / length);
        quad(a - n - t, b - n + t, b + n + t, a + n - t, c);
    }
    void polyline(const std::vector<glm::vec2>& points, float thickness, glm::vec3 c) {
        for (size_t k = 1; k < points.size(); ++k) line(points[k - 1], points[k], thickness, c);
    }
    void dot(glm::vec2 centre, float radius, glm::vec3 c) {
        constexpr int kSides = 12;
        for (int k = 0; k < kSides; ++k) {
            const float a0 = 2.0f * kPi * float(k) / kSides, a1 = 2.0f * kPi * float(k + 1) / kSides;
            add(centre, c), add(centre + radius * glm::vec2(std::cos(a0), std::sin(a0)), c);
            add(centre + radius * glm::vec2(std::cos(a1), std::sin(a1)), c);
        }
    }
    const std::vector<PlotIn>& triangles() const { return triangles_; }

  private:
    void add(glm::vec2 p, glm::vec3 c) {
        triangles_.push_back({{2.0f * p.x / width_ - 1.0f, 1.0f - 2.0f * p.y / height_}, c});
    }
    void quad(glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec2 d, glm::vec3 colour) {
        for (const glm::vec2& p : {a, b, c, a, c, d}) add(p, colour);
    }
    float width_, height_;
    std::vector<PlotIn> triangles_;
};

// p(cos θ) per steradian of one curve.
struct PhaseCurve {
    float (*p)(float g, float cos_theta);
    float g;
    glm::vec3 colour;
};
float isotropicCurve(float, float) { return media::isotropic<float>(); }
float rayleighCurve(float, float c) { return media::rayleigh(c); }
float hgCurve(float g, float c) { return media::henyeyGreenstein(g, c); }

// One panel: the curves about `centre`, the largest value of any of them `radius` pixels out.
void polarPanel(Plot& plot, glm::vec2 centre, float radius, const std::vector<PhaseCurve>& curves) {
    float largest = 0.0f;
    for (const PhaseCurve& curve : curves)
        for (uint32_t k = 0; k <= kCurveSegments; ++k)
            largest = std::max(largest, curve.p(curve.g, std::cos(2.0f * kPi * float(k) / kCurveSegments)));
    const float thin = std::max(1.0f, radius / 120.0f);
    plot.line(centre - glm::vec2(1.15f * radius, 0.0f), centre + glm::vec2(1.15f * radius, 0.0f), thin, kAxis);
    plot.line(centre - glm::vec2(0.0f, 1.05f * radius), centre + glm::vec2(0.0f, 1.05f * radius), thin, kAxis);
    // The incoming light's arrowhead, on the axis left of the scattering point, pointing along +x.
    const glm::vec2 tip = centre - glm::vec2(0.9f * radius, 0.0f), back = glm::vec2(0.08f * radius, 0.0f);
    plot.line(tip, tip - back + glm::vec2(0.0f, 0.05f * radius), 2.0f * thin, kWhite);
    plot.line(tip, tip - back - glm::vec2(0.0f, 0.05f * radius), 2.0f * thin, kWhite);
    for (const PhaseCurve& curve : curves) {
        std::vector<glm::vec2> points;
        for (uint32_t k = 0; k <= kCurveSegments; ++k) {
            const float theta = 2.0f * kPi * float(k) / kCurveSegments;
            const float r = curve.p(curve.g, std::cos(theta)) / largest * radius;
            points.push_back(centre + r * glm::vec2(std::cos(theta), -std::sin(theta)));
        }
        plot.polyline(points, 2.5f * thin, curve.colour);
    }
    plot.dot(centre, 3.0f * thin, kWhite);
}

Plot phasePolarPlot(float w, float h) {
    Plot plot(w, h);
    const float radius = 0.42f * std::min(0.5f * w, h);
    polarPanel(plot, {0.25f * w, 0.5f * h}, radius,
               {{isotropicCurve, 0.0f, kIsotropic}, {rayleighCurve, 0.0f, kBlue}, {hgCurve, 0.3f, kOrange},
                {hgCurve, -0.3f, kGreen}});
    polarPanel(plot, {0.75f * w, 0.5f * h}, radius,
               {{isotropicCurve, 0.0f, kIsotropic}, {hgCurve, 0.7f, kOrange}, {hgCurve, -0.7f, kGreen}});
    return plot;
}

// The march of the `media` scene's centre ray, every sample recorded.
struct CentreRayMarch {
    std::vector<media::MarchSample> samples;
    float t0 = 0.0f, t1 = 0.0f;
};
CentreRayMarch centreRayMarch() {
    const media::MetaballVolume volume =
        media::makeMetaballVolume(media::mediaSceneMetaballs(), media::mediaSceneBox(), 4.0f, 1);
    const glm::vec3 eye = kMediaMarchCamera.eye, d = glm::normalize(kMediaMarchCamera.target - eye);
    media::MarchSettings settings;
    settings.steps = kMarchSteps, settings.skip = media::SkipMethod::none;
    CentreRayMarch march;
    media::marchMetaballs(volume, media::mediaSceneLight(), settings, eye, d,
                          [&](const media::MarchSample& s) { march.samples.push_back(s); });
    const auto [t_near, t_far] = media::slabInterval(volume.box, eye, d);
    march.t0 = std::max(t_near, 0.0f), march.t1 = t_far;
    return march;
}

Plot marchStepsPlot(float w, float h) {
    Plot plot(w, h);
    const CentreRayMarch march = centreRayMarch();
    const float left = 0.06f * w, right = 0.94f * w, top = 0.08f * h, axis = 0.9f * h;
    const float thin = std::max(1.0f, h / 360.0f);
    const float ds = (march.t1 - march.t0) / float(kMarchSteps);
    const auto x_of = [&](float s) { return left + (s - march.t0) / (march.t1 - march.t0) * (right - left); };
    const auto y_of = [&](float v) { return axis - v * (axis - top); };  // v in [0, 1]
    float largest_step = 0.0f, final_radiance = 0.0f;
    glm::vec3 gathered{0.0f};
    for (const media::MarchSample& s : march.samples) largest_step = std::max(largest_step, s.opticalStep);
    for (const media::MarchSample& s : march.samples) gathered += s.added;
    final_radiance = std::max({gathered.x, gathered.y, gathered.z, 1e-6f});
    for (const media::MarchSample& s : march.samples) {  // bars: μ_i·Δs over the sample's step
        const float x0 = x_of(march.t0 + float(s.index) * ds), x1 = x_of(march.t0 + float(s.index + 1) * ds);
        if (largest_step > 0.0f)
            plot.rect({x0 + thin, y_of(0.8f * s.opticalStep / largest_step)}, {x1 - thin, axis}, kBlue * 0.7f);
    }
    plot.line({left, axis}, {right, axis}, 2.0f * thin, kAxis);
    for (uint32_t i = 0; i <= kMarchSteps; ++i) {
        const float x = x_of(march.t0 + float(i) * ds);
        plot.line({x, axis - 6.0f * thin}, {x, axis + 6.0f * thin}, thin, kAxis);
    }
    std::vector<glm::vec2> transmittance, radiance;
    glm::vec3 so_far{0.0f};
    for (const media::MarchSample& s : march.samples) {
        const float x = x_of(march.t0 + float(s.index) * ds);
        transmittance.push_back({x, y_of(s.transmittance)});
        radiance.push_back({x, y_of(std::max({so_far.x, so_far.y, so_far.z}) / final_radiance)});
        so_far += s.added;
    }
    if (!march.samples.empty()) {
        const media::MarchSample& last = march.samples.back();
        transmittance.push_back({x_of(march.t1), y_of(last.transmittance * std::exp(-last.opticalStep))});
        radiance.push_back({x_of(march.t1), y_of(1.0f)});
    }
    plot.polyline(transmittance, 2.0f * thin, kWhite);
    plot.polyline(radiance, 2.0f * thin, kOrange);
    for (const media::MarchSample& s : march.samples) plot.dot({x_of(s.s), axis}, 4.0f * thin, kWhite);
    return plot;
}

class SlideFigureScene final : public Scene {
  public:
    SlideFigureScene(std::string_view name, const SceneOptions& o) : name_(name) {
        const float w = float(o.width), h = float(o.height);
        Plot plot = name == "phase-polar" ? phasePolarPlot(w, h) : marchStepsPlot(w, h);
        count_ = uint32_t(plot.triangles().size());
        vertices_ = VertexBuffer::create(plot.triangles());
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32_FLOAT, 0, 0},
                                         {"COLOR", 0, Format::R32G32B32_FLOAT, 0, 8}};
        layout_ = InputLayout(desc);
    }
    std::string_view name() const override { return name_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        context.clearRenderTarget(color, {kBackground.x, kBackground.y, kBackground.z, 1.0f});
        context.setBlendState(BlendState::opaque());
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setDepthStencilState(DepthStencilState::disabled());
        context.setInputLayout(&layout_);
        context.setVertexBuffer(0, &vertices_);
        context.draw(VsPlot{}, PsPlot{}, count_);
    }

  private:
    std::string name_;
    VertexBuffer vertices_;
    InputLayout layout_;
    uint32_t count_ = 0;
};

}  // namespace

std::vector<std::string_view> slideFigureNames() { return {"phase-polar", "media-march-steps"}; }

std::unique_ptr<Scene> makeSlideFigureScene(std::string_view name, const SceneOptions& options) {
    return std::make_unique<SlideFigureScene>(name, options);
}

}  // namespace raster
