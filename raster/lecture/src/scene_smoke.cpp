// The `smoke` scene: grey smoke from a particle system (raster/particles.hpp: a disc emitter on the
// ground, buoyancy, wind, curl-noise turbulence, size, colour and opacity over life), blended "over"
// and so sorted back to front every frame (raster/particle_sort.hpp), soft against the opaque ground
// and a box the wind blows it through (soft_particles.hpp). Drawn at full resolution, or off-screen
// at 1/k resolution and composited, with or without the edge fix (OffscreenParticles): the off-screen
// path is meant to be fast, so this file instantiates the template pipeline.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "raster/particle_sort.hpp"
#include "raster/particles.hpp"
#include "raster/pipeline_impl.hpp"
#include "scene_list.hpp"
#include "smoke_shaders.hpp"
#include "smoke_world.hpp"

namespace raster {

namespace {

static_assert(WidePixelShader<shaders::PsSmokeParticle> && WidePixelShader<shaders::PsComposite>);

constexpr float kLifespanMin = 3.0f, kLifespanMax = 4.5f;
constexpr float kAliveShare = 0.75f;  // of the slots, in the steady state (as the fire's)

// "Over" onto an opaque frame: rgb = s.rgb·s.a + d.rgb·(1 − s.a), the frame's alpha kept at 1.
// (BlendState::alphaBlend blends alpha too, which would leave the saved PNG partly transparent.)
BlendState overOpaque() {
    BlendState b;
    RenderTargetBlendDesc& t = b.renderTarget[0];
    t.blendEnable = true;
    t.srcBlend = Blend::SrcAlpha, t.destBlend = Blend::InvSrcAlpha;
    t.srcBlendAlpha = Blend::Zero, t.destBlendAlpha = Blend::One;
    return b;
}
// Into the off-screen target, cleared to (0, 0, 0, 1): rgb accumulates the premultiplied colour as
// "over" does, a the transmittance, a·(1 − s.a) per particle (the chapter's separate alpha blend).
BlendState offscreenAccumulate() {
    BlendState b = overOpaque();
    b.renderTarget[0].destBlendAlpha = Blend::InvSrcAlpha;
    return b;
}
// The composite: frame.rgb = frame.rgb·T + colour, T the sampled transmittance; alpha kept.
BlendState compositeOver() {
    BlendState b = overOpaque();
    b.renderTarget[0].srcBlend = Blend::One, b.renderTarget[0].destBlend = Blend::SrcAlpha;
    return b;
}

// World units, seconds. Ground y = 0; the box stands downwind of the emitter, the wind (+x) blows
// the rising plume through it.
constexpr glm::vec3 kEmitterCentre{-1.1f, 0.05f, -0.5f};
// The box's front face is nearer the camera than the plume's middle: part of the smoke passes
// through the box, part behind it (its silhouette is then an occluder edge against smoke).
constexpr glm::vec3 kBoxCentre{0.1f, 0.45f, -0.05f}, kBoxHalf{0.3f, 0.45f, 0.3f};

Emitter smokeEmitter(uint32_t count) {
    Emitter e = Emitter::disc(kEmitterCentre, {0, 1, 0}, 0.25f);
    e.rate = kAliveShare * float(count) / (0.5f * (kLifespanMin + kLifespanMax));
    e.velocity = {{0, 1, 0}, 0.35f, 0.25f, 0.4f};
    e.lifespanMin = kLifespanMin, e.lifespanMax = kLifespanMax;
    e.sizeMin = 0.08f, e.sizeMax = 0.12f;
    e.sizeOverLife = Curve{{0.0f, 0.5f}, {0.3f, 1.0f}, {1.0f, 2.2f}};  // puffs spread as they rise
    e.colourOverLife =
        ColourGradient{{0.0f, glm::vec3(0.22f)}, {0.4f, glm::vec3(0.45f)}, {1.0f, glm::vec3(0.7f)}};
    // More particles, each fainter, so that the plume's density does not depend on the count.
    const float gain = std::min(1.0f, float(kDefaultSmokeCount) / float(std::max(count, 1u)));
    e.opacityOverLife = Curve{{0.0f, 0.0f}, {0.1f, 0.6f * gain}, {0.6f, 0.4f * gain}, {1.0f, 0.0f}};
    return e;
}

}  // namespace

ParticleSystemDesc smokeDesc(uint32_t count, uint64_t seed) {
    ParticleSystemDesc desc;
    desc.maxParticles = std::max(count, 1u);
    desc.seed = seed;
    desc.maxStepsPerAdvance = UINT32_MAX;  // a frame is a function of its clock (scenes.hpp)
    Emitter emitter = smokeEmitter(count);
    if (count == 0) emitter.rate = 0.0f;
    desc.emitters = {emitter};
    desc.effectors = {
        Buoyancy{{0, 1, 0}, 0.35f, 0.2f},                       // warm smoke rises, less as it cools
        Wind{{1.0f, 0.0f, 0.0f}, 0.8f},                         // carried toward the box
        Turbulence{0.3f, 1.4f, {0.0f, -0.25f, 0.0f}, 0.0f, 0},  // eddies ~0.7 units across
    };
    return desc;
}

namespace {

using shaders::LitIn;

// An axis-aligned box's six faces (two triangles each), normals outward scaled by the albedo.
void pushBox(std::vector<LitIn>& v, glm::vec3 c, glm::vec3 h, float albedo) {
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f);
            n[axis] = sign;
            const int a = (axis + 1) % 3, b = (axis + 2) % 3;
            glm::vec3 corner[4];
            for (int k = 0; k < 4; ++k) {
                glm::vec3 p = n;
                p[a] = (k & 1) ? 1.0f : -1.0f;
                p[b] = (k & 2) ? 1.0f : -1.0f;
                corner[k] = c + p * h;
            }
            for (int k : {0, 1, 2, 2, 1, 3}) v.push_back({corner[k], n * albedo});
        }
}

std::vector<LitIn> smokeGeometry() {
    std::vector<LitIn> v;
    const glm::vec3 up(0.0f, 0.55f, 0.0f);  // the ground: albedo 0.55
    const glm::vec3 g[4] = {{-4, 0, -5}, {4, 0, -5}, {-4, 0, 2.5f}, {4, 0, 2.5f}};
    for (int k : {0, 2, 1, 1, 2, 3}) v.push_back({g[k], up});
    pushBox(v, kBoxCentre, kBoxHalf, 0.8f);
    return v;
}

}  // namespace

SmokeGround::SmokeGround(const glm::mat4& view_proj) {
    vs.viewProj = view_proj;
    const std::vector<LitIn> solid = smokeGeometry();
    vertices = VertexBuffer::create(solid);
    count = uint32_t(solid.size());
    const InputElementDesc lit[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                    {"NORMAL", 0, Format::R32G32B32_FLOAT, 0, 12}};
    layout = InputLayout(lit);
}

void SmokeGround::render(Context& context, RenderTarget& color, DepthTarget& depth) const {
    beginSceneFrame(context, color, depth);
    context.setBlendState(BlendState::opaque());
    context.setDepthStencilState({true, true, ComparisonFunc::Less});
    context.setPrimitiveTopology(Topology::TriangleList);
    context.setInputLayout(&layout);
    context.setVertexBuffer(0, &vertices);
    context.draw(vs, ps, count);
}

namespace {

class SmokeScene final : public Scene {
  public:
    SmokeScene(const SceneOptions& o, const OffscreenParticles& mode)
        : mode_(mode), system_(smokeDesc(o.count.value_or(kDefaultSmokeCount), o.seed)),
          ground_(sceneProjection(o) * sceneView(o.camera.value_or(kSmokeCamera))) {
        const SceneCamera camera = o.camera.value_or(kSmokeCamera);
        const glm::mat4 proj = sceneProjection(o);
        const glm::mat4 view_proj = proj * sceneView(camera);
        eye_ = camera.eye;
        ahead_ = camera.target - camera.eye;
        gs_.viewProj = view_proj;
        gs_.projScale = {proj[0][0], proj[1][1]};
        ps_.inverseFadeDistance = 1.0f / mode.fadeDistance;
        ps_.soft = mode.soft;
        const std::vector<glm::vec3> screen = {{-1, -1, 0}, {3, -1, 0}, {-1, 3, 0}};  // one triangle
        screen_ = VertexBuffer::create(screen);
        const InputElementDesc position[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        screen_layout_ = InputLayout(position);
        const auto elements = particleInputLayout();
        particle_layout_ = InputLayout(elements);
        const uint32_t slots = system_.capacity();
        allocateOrThrow("the upload of " + std::to_string(slots) + " smoke particles",
                        byteCount(slots, 2 * sizeof(Particle) + sizeof(uint32_t)),
                        [&] { staging_.resize(slots), sorted_.resize(slots), order_.resize(slots); });
        particles_ = VertexBuffer::create(std::vector<Particle>{});
        edge_particles_ = VertexBuffer::create(std::vector<Particle>{});
        time_ = o.time.value_or(kDefaultSmokeTime);
        system_.advance(time_);
    }
    std::string_view name() const override { return "smoke"; }
    bool animated() const override { return true; }
    double time() const override { return time_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        ground_.render(context, color, depth);
        if (uploadSorted() == 0) return;
        if (mode_.factor == 1) {
            drawParticles(context, DepthTexture(depth), overOpaque());  // into the frame, against its depth
            return;
        }
        renderOffscreen(context, color, depth);
    }

  protected:
    void advanceBy(double seconds) override {
        system_.advance(seconds);
        time_ += seconds;
    }

  private:
    // The living particles, sorted back to front along the view direction, into the vertex buffer.
    size_t uploadSorted() {
        const size_t alive = system_.writeVertices(std::span<Particle>(staging_));
        const std::span<const Particle> living(staging_.data(), alive);
        const std::span<uint32_t> order(order_.data(), alive);
        sortBackToFront(living, eye_, ahead_, order, SortMethod::Automatic, &sort_scratch_);
        for (size_t i = 0; i < alive; ++i) sorted_[i] = staging_[order[i]];
        particles_.update(std::span<const Particle>(sorted_.data(), alive));
        alive_ = alive;
        return alive;
    }

    // The particles into the bound targets, depth test Less without depth writes, soft against
    // `scene_depth` (the depth at the bound targets' resolution).
    void drawParticles(Context& context, const DepthTexture& scene_depth, const BlendState& blend) {
        ps_.sceneDepth = scene_depth;
        context.setInputLayout(&particle_layout_);
        context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        context.setBlendState(blend);
        context.setVertexBuffer(0, &particles_);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(shaders::VsFireParticle{}, gs_, ps_, uint32_t(alive_));
    }

    void renderOffscreen(Context& context, RenderTarget& color, DepthTarget& depth);
    // The edge fix's mask as a depth target: the scene's depth on the pixels of edge texels, 0 elsewhere.
    void buildEdgeStencil(const DepthTarget& depth);
    // The edge fix's particles: those of the sorted upload whose quad's screen rectangle touches an
    // edge texel (a summed-area table of the mask answers each in four reads), in the same order,
    // into edge_particles_. Returns how many. The others would only be rasterised to be rejected.
    uint32_t uploadEdgeParticles(uint32_t width, uint32_t height);

    OffscreenParticles mode_;
    ParticleSystem system_;
    glm::vec3 eye_{0.0f}, ahead_{0.0f, 0.0f, -1.0f};
    SmokeGround ground_;
    VertexBuffer screen_, particles_;
    InputLayout screen_layout_, particle_layout_;
    std::vector<Particle> staging_, sorted_;  // maxParticles each: what Map would return, and sorted
    std::vector<uint32_t> order_;
    SortScratch sort_scratch_;
    size_t alive_ = 0;
    shaders::GsFireParticle gs_;
    shaders::PsSmokeParticle ps_;
    shaders::VsTransform vs_screen_;  // identity: the triangle is given in clip space
    shaders::PsComposite ps_composite_;
    // Off-screen: the low-resolution targets and the composite's texture, kept from frame to frame.
    DepthTarget farthest_, stencil_;
    std::vector<uint8_t> edge_;        // depthEdgeMask of the low-resolution texels
    std::vector<uint32_t> edge_sums_;  // its summed-area table, (low_w + 1) × (low_h + 1)
    std::vector<Particle> edge_staging_;
    VertexBuffer edge_particles_;
    RenderTarget low_;
    Texture2D low_texture_;
    double time_ = 0.0;
};

void SmokeScene::buildEdgeStencil(const DepthTarget& depth) {
    const uint32_t k = mode_.factor, w = depth.width(), h = depth.height();
    const DepthTarget nearest = downsampleDepth(depth, k, DepthDownsample::Nearest);
    edge_ = depthEdgeMask(nearest, farthest_, ps_.linearizer, mode_.edgeStep);
    const std::vector<uint8_t>& edge = edge_;
    if (stencil_.width() != w || stencil_.height() != h) stencil_ = DepthTarget(w, h);
    const uint32_t low_w = farthest_.width();
    for (uint32_t y = 0; y < h; ++y) {
        const uint8_t* edge_row = &edge[size_t(y / k) * low_w];
        const float* in = depth.data() + size_t(y) * w;
        float* out = stencil_.data() + size_t(y) * w;
        for (uint32_t x = 0; x < w; ++x) out[x] = edge_row[x / k] ? in[x] : 0.0f;
    }
}

uint32_t SmokeScene::uploadEdgeParticles(uint32_t width, uint32_t height) {
    const uint32_t low_w = farthest_.width(), low_h = farthest_.height(), k = mode_.factor;
    edge_sums_.assign(size_t(low_w + 1) * (low_h + 1), 0);
    for (uint32_t y = 0; y < low_h; ++y)
        for (uint32_t x = 0; x < low_w; ++x)
            edge_sums_[size_t(y + 1) * (low_w + 1) + x + 1] =
                edge_[size_t(y) * low_w + x] + edge_sums_[size_t(y) * (low_w + 1) + x + 1] +
                edge_sums_[size_t(y + 1) * (low_w + 1) + x] - edge_sums_[size_t(y) * (low_w + 1) + x];
    const auto texel = [](float ndc, uint32_t pixels, uint32_t factor, uint32_t texels) {
        const float t = std::floor((0.5f * ndc + 0.5f) * float(pixels) / float(factor));
        return int64_t(std::clamp(t, -1.0f, float(texels)));
    };
    edge_staging_.clear();
    for (size_t i = 0; i < alive_; ++i) {
        const Particle& p = sorted_[i];
        const glm::vec4 c = gs_.viewProj * glm::vec4(p.position, 1.0f);
        if (!(c.w > 0.0f)) {  // at or behind the eye: the clipper decides, keep it
            edge_staging_.push_back(p);
            continue;
        }
        const float hx = p.size * gs_.projScale.x / c.w, hy = p.size * gs_.projScale.y / c.w;
        const float cx = c.x / c.w, cy = -c.y / c.w;  // screen y grows downward
        const int64_t x0 = std::max<int64_t>(texel(cx - hx, width, k, low_w), 0);
        const int64_t x1 = std::min<int64_t>(texel(cx + hx, width, k, low_w), int64_t(low_w) - 1);
        const int64_t y0 = std::max<int64_t>(texel(cy - hy, height, k, low_h), 0);
        const int64_t y1 = std::min<int64_t>(texel(cy + hy, height, k, low_h), int64_t(low_h) - 1);
        if (x0 > x1 || y0 > y1) continue;  // off screen
        const auto sum = [&](int64_t x, int64_t y) {
            return int64_t(edge_sums_[size_t(y) * (low_w + 1) + size_t(x)]);
        };
        if (sum(x1 + 1, y1 + 1) - sum(x0, y1 + 1) - sum(x1 + 1, y0) + sum(x0, y0) > 0)
            edge_staging_.push_back(p);
    }
    edge_particles_.update(std::span<const Particle>(edge_staging_));
    return uint32_t(edge_staging_.size());
}

void SmokeScene::renderOffscreen(Context& context, RenderTarget& color, DepthTarget& depth) {
    // 1. The depth, k×k → 1 by the farthest; 2. the particles at that resolution.
    farthest_ = downsampleDepth(depth, mode_.factor, DepthDownsample::Farthest);
    const uint32_t low_w = farthest_.width(), low_h = farthest_.height();
    if (low_.width() != low_w || low_.height() != low_h)
        low_ = RenderTarget(low_w, low_h, Format::R32G32B32A32_FLOAT);
    context.clearRenderTarget(low_, {0, 0, 0, 1});
    context.setRenderTargets(&low_, &farthest_);
    context.setViewport({0, 0, float(low_w), float(low_h), 0, 1});
    drawParticles(context, DepthTexture(farthest_), offscreenAccumulate());
    // 3. The composite, upsampled bilinearly: everywhere, or (edge fix) where the stencil is 0, the
    // full-screen triangle's depth, which the test Equal keeps.
    low_texture_ = Texture2D::fromRgba32f(low_w, low_h,
                                          std::span<const float>(low_.rgba32f(), size_t(4) * low_w * low_h));
    ps_composite_.particles = &low_texture_;
    // uv = SV_Position / (k · the low size): pixel x + ½ lands at (x + ½)/k texels, so texel i's centre
    // is under full-resolution pixel k·i + k/2 − ½ whether or not k divides the width.
    const float k = float(mode_.factor);
    ps_composite_.inverseSize = {1.0f / (k * float(low_w)), 1.0f / (k * float(low_h))};
    if (mode_.edgeFix) buildEdgeStencil(depth);
    context.setRenderTargets(&color, mode_.edgeFix ? &stencil_ : nullptr);
    context.setViewport({0, 0, float(color.width()), float(color.height()), 0, 1});
    context.setDepthStencilState(mode_.edgeFix ? DepthStencilState::readOnly(ComparisonFunc::Equal)
                                               : DepthStencilState{false, false, ComparisonFunc::Always});
    context.setBlendState(compositeOver());
    context.setInputLayout(&screen_layout_);
    context.setVertexBuffer(0, &screen_);
    context.setPrimitiveTopology(Topology::TriangleList);
    context.draw(vs_screen_, ps_composite_, 3);
    // 4. The edge fix: the particles again at full resolution, only where the stencil holds the
    // scene's depth (Less fails against 0), soft against the full-resolution depth.
    if (mode_.edgeFix) {
        const uint32_t count = uploadEdgeParticles(color.width(), color.height());
        if (count > 0) {
            ps_.sceneDepth = DepthTexture(depth);
            context.setInputLayout(&particle_layout_);
            context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
            context.setBlendState(overOpaque());
            context.setVertexBuffer(0, &edge_particles_);
            context.setPrimitiveTopology(Topology::PointList);
            context.draw(shaders::VsFireParticle{}, gs_, ps_, count);
        }
    }
    context.setRenderTargets(&color, &depth);
}

}  // namespace

std::unique_ptr<Scene> makeSmokeScene(const SceneOptions& options, const OffscreenParticles& offscreen) {
    RASTER_REQUIRE(offscreen.factor >= 1 && offscreen.factor <= 16, InvalidArgument,
                   "off-screen particle factor " + std::to_string(offscreen.factor) + " is outside 1..16");
    RASTER_REQUIRE(
        std::isfinite(offscreen.fadeDistance) && offscreen.fadeDistance > 0.0f, InvalidArgument,
        "soft particle fade distance " + std::to_string(offscreen.fadeDistance) + " must be finite and > 0");
    RASTER_REQUIRE(std::isfinite(offscreen.edgeStep) && offscreen.edgeStep > 0.0f, InvalidArgument,
                   "edge step " + std::to_string(offscreen.edgeStep) + " must be finite and > 0");
    return std::make_unique<SmokeScene>(options, offscreen);
}

std::unique_ptr<Scene> makeSmokeScene(const SceneOptions& options) {
    return makeSmokeScene(options, {});
}

}  // namespace raster
