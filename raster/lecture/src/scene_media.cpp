// The lecture's part 1 with a closed form (NOTES.md, "Konstans megoldás"): a box of homogeneous medium
// before the fog figures' world (FogWorldData: the checkered ground, the coloured cubes, a sky), in three
// panels side by side — absorption only, emission only, absorption and emission. A pixel that sees the
// box sees the world behind it along a path of length s through the box, and
//   L(s) = L(0)·e^{−μ·s} + q·s·ψ(μ·s),   ψ(x) = (1 − e^{−x})/x, ψ(0) = 1
// (raster/media/homogeneous.hpp: media::transmittance and media::gathered, finite for μ = 0). The
// box's pixel shader finds s per pixel (the view ray's entry and exit through the box's slabs) and
// hands the output merger both terms at once:
// SV_Target0 = q·s·ψ(μ·s) and SV_Target1 = e^{−μ·s}, blended as src·1 + dst·src1 (dual-source), so the
// world drawn before is attenuated and the emission added in one draw.
//
// Drawn through the teaching pipeline (raster/teaching_draw.hpp): a figure, compiled in seconds.
#include <algorithm>
#include <array>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "raster/media/homogeneous.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/shaders/fog.hpp"
#include "raster/teaching_draw.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

// The box, world units: above the ground, in front of the lattice's first row (cubes at x = ±2, z = −2).
constexpr glm::vec3 kBoxMin{-1.0f, 0.4f, -0.6f}, kBoxMax{1.0f, 1.8f, 1.2f};
// The panels' medium by default: the same μ and q in all three (absorption only keeps μ, emission only
// keeps q): grey absorption of 0.8/m (e^{−1.6} ≈ 0.2 through 2 m), a blue glow that tends to
// q/μ = (0.2, 0.35, 0.6) through a thick box.
constexpr glm::vec3 kBoxSigma{0.8f, 0.8f, 0.8f}, kBoxSource{0.16f, 0.28f, 0.48f};
// The box's edges, drawn over the medium so that its shape reads.
constexpr glm::vec4 kEdgeColour{0.95f, 0.95f, 0.9f, 1.0f};
// The sky behind the world, no medium: a gradient from the horizon to the zenith.
constexpr glm::vec3 kHorizon{0.80f, 0.83f, 0.86f}, kZenith{0.36f, 0.52f, 0.78f};

// The world's vertex format, what its vertex shader passes on and the shader (raster/shaders/fog.hpp).
using shaders::LitIn;
using shaders::LitVertex;
using shaders::VsLit;
// The world without a medium: diffuse, L0 = albedo·(ambient + (1 − ambient)·max(0, n·l)), PsFog's light.
struct PsSurface {
    glm::vec3 albedo{0.7f};
    glm::vec4 operator()(const LitVertex& in) const {
        const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
        const float lambert = std::max(0.0f, glm::dot(glm::normalize(in.normal), light));
        return {albedo * (0.2f + 0.8f * lambert), 1.0f};
    }
};
// The sky: the gradient along the pixel's view ray (shaders::VsSky's attribute).
struct PsGradientSky {
    glm::vec4 operator()(const shaders::SkyVertex& in) const {
        const float up = std::clamp(in.ray.y / glm::length(in.ray), 0.0f, 1.0f);
        return {glm::mix(kHorizon, kZenith, std::sqrt(up)), 1.0f};
    }
};

// The path length through the box of the ray from `eye` through `point` (a point on the box's
// surface): the slabs' entry and exit, the part in front of the eye.
float pathThroughBox(const glm::vec3& eye, const glm::vec3& point) {
    const glm::vec3 dir = glm::normalize(point - eye);
    float t_in = 0.0f, t_out = std::numeric_limits<float>::infinity();
    for (int k = 0; k < 3; ++k) {
        if (dir[k] == 0.0f) continue;  // parallel to the slab: the point on the surface lies within it
        const float a = (kBoxMin[k] - eye[k]) / dir[k], b = (kBoxMax[k] - eye[k]) / dir[k];
        t_in = std::max(t_in, std::min(a, b));
        t_out = std::min(t_out, std::max(a, b));
    }
    return std::max(0.0f, t_out - t_in);
}

// The box's medium over the pixel's path: SV_Target0 the emission q·s·ψ(μ·s), SV_Target1 the
// transmittance e^{−μ·s}, per channel.
struct PsMediumBox {
    glm::vec3 mu{0.0f}, q{0.0f};  // extinction 1/m, source radiance per metre
    glm::vec3 eye{0.0f};
    std::array<glm::vec4, 2> operator()(const LitVertex& in) const {
        const float s = pathThroughBox(eye, in.worldPos);
        glm::vec3 emitted, transmitted;
        for (int c = 0; c < 3; ++c) {
            transmitted[c] = media::transmittance(mu[c], s);
            emitted[c] = media::gathered(mu[c], q[c], s);
        }
        return {glm::vec4(emitted, 1.0f), glm::vec4(transmitted, 1.0f)};
    }
};

// The box as 12 triangles, outward faces counter-clockwise seen from outside.
std::vector<LitIn> boxTriangles() {
    std::vector<LitIn> v;
    const auto p = [](int x, int y, int z) {
        return glm::vec3(x ? kBoxMax.x : kBoxMin.x, y ? kBoxMax.y : kBoxMin.y, z ? kBoxMax.z : kBoxMin.z);
    };
    const auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n) {
        for (const glm::vec3& q : {a, b, c, a, c, d}) v.push_back({q, n});
    };
    quad(p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1), {1, 0, 0});
    quad(p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0), {-1, 0, 0});
    quad(p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0), {0, 1, 0});
    quad(p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1), {0, -1, 0});
    quad(p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1), {0, 0, 1});
    quad(p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0), {0, 0, -1});
    return v;
}

// The box's 12 edges as a line list.
std::vector<glm::vec3> boxEdges() {
    std::vector<glm::vec3> v;
    const auto p = [](int x, int y, int z) {
        return glm::vec3(x ? kBoxMax.x : kBoxMin.x, y ? kBoxMax.y : kBoxMin.y, z ? kBoxMax.z : kBoxMin.z);
    };
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            v.push_back(p(0, a, b)), v.push_back(p(1, a, b));
            v.push_back(p(a, 0, b)), v.push_back(p(a, 1, b));
            v.push_back(p(a, b, 0)), v.push_back(p(a, b, 1));
        }
    return v;
}

// L = src·1 + dst·src1: the emission added, what is behind multiplied by the transmittance (colour);
// alpha stays the world's.
BlendState emitAndTransmit() {
    BlendState blend;
    RenderTargetBlendDesc& rt = blend.renderTarget[0];
    rt.blendEnable = true;
    rt.srcBlend = Blend::One, rt.destBlend = Blend::Src1Color, rt.blendOp = BlendOp::Add;
    rt.srcBlendAlpha = Blend::Zero, rt.destBlendAlpha = Blend::One, rt.blendOpAlpha = BlendOp::Add;
    return blend;
}

class MediaClosedFormScene final : public Scene {
  public:
    explicit MediaClosedFormScene(const SceneOptions& o) : world_(o.cubes) {
        SceneOptions panel = o;
        panel.width = std::max(1u, o.width / 3);
        const SceneCamera camera = o.camera.value_or(kMediaCamera);
        const glm::mat4 view_proj = sceneProjection(panel) * sceneView(camera);
        vs_.viewProj = view_proj;
        vs_sky_.eye = camera.eye, vs_sky_.invViewProj = glm::inverse(view_proj);
        const glm::vec3 sigma = o.fogSigma.value_or(kBoxSigma), source = o.fogSource.value_or(kBoxSource);
        const glm::vec3 none(0.0f);
        const std::array<std::pair<glm::vec3, glm::vec3>, 3> panels{
            {{sigma, none}, {none, source}, {sigma, source}}};
        for (size_t k = 0; k < 3; ++k) boxes_[k] = {panels[k].first, panels[k].second, camera.eye};
        const std::vector<LitIn> box = boxTriangles();
        box_ = VertexBuffer::create(box);
        box_count_ = uint32_t(box.size());
        edges_ = VertexBuffer::create(boxEdges());
        const InputElementDesc position[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        edge_layout_ = InputLayout(position);
        vs_edges_.viewProj = view_proj;
        panel_width_ = float(panel.width);
    }
    std::string_view name() const override { return "media-closed-form"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);
        context.setPrimitiveTopology(Topology::TriangleList);
        for (int k = 0; k < 3; ++k) {
            context.setViewport(
                {panel_width_ * float(k), 0.0f, panel_width_, float(color.height()), 0.0f, 1.0f});
            context.setBlendState(BlendState::opaque());
            context.setDepthStencilState({true, true, ComparisonFunc::Less});
            context.setInputLayout(&world_.layout);
            context.setVertexBuffer(0, &world_.lit);
            for (const FogWorldData::Part& part : world_.parts)
                if (part.count > 0) context.draw(vs_, PsSurface{part.albedo}, part.count, part.first);
            context.setDepthStencilState({true, true, ComparisonFunc::LessEqual});
            context.setInputLayout(&world_.skyLayout);
            context.setVertexBuffer(0, &world_.sky);
            context.draw(vs_sky_, PsGradientSky{}, 3);
            // The box: its faces turned to the eye (one fragment a pixel), tested against the world, not
            // written (the depth of a medium is no surface).
            RasterizerState rs;
            rs.cullMode = CullMode::Back;
            context.setRasterizerState(rs);
            context.setBlendState(emitAndTransmit());
            context.setDepthStencilState({true, false, ComparisonFunc::Less});
            context.setInputLayout(&world_.layout);
            context.setVertexBuffer(0, &box_);
            context.draw(vs_, boxes_[k], box_count_);
            rs.cullMode = CullMode::None;
            context.setRasterizerState(rs);
            context.setBlendState(BlendState::opaque());
            context.setPrimitiveTopology(Topology::LineList);
            context.setInputLayout(&edge_layout_);
            context.setVertexBuffer(0, &edges_);
            context.draw(vs_edges_, shaders::PsConstant{kEdgeColour}, 24);
            context.setPrimitiveTopology(Topology::TriangleList);
        }
    }

  private:
    FogWorldData world_;
    VertexBuffer box_, edges_;
    InputLayout edge_layout_;
    uint32_t box_count_ = 0;
    shaders::VsTransform vs_edges_;
    float panel_width_ = 1.0f;
    VsLit vs_;
    shaders::VsSky vs_sky_;
    std::array<PsMediumBox, 3> boxes_;
};

}  // namespace

std::unique_ptr<Scene> makeMediaClosedFormScene(const SceneOptions& options) {
    return std::make_unique<MediaClosedFormScene>(options);
}

}  // namespace raster
