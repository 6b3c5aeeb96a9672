// The lecture's sprites and billboards (lecture 11, part 3) as two animated scenes, drawn through the
// teaching pipeline (their speed is no goal; the file compiles its shaders only):
//   sprites  four rows of alpha-tested sprites scrolling across the image, top to bottom: (a) classic
//            transforms (red), (b) own transform (green), (c) opened by the geometry shader (blue),
//            and turned to the eye point (yellow). (a), (b) and (c) are one quad in exact arithmetic
//            (src/lecture/sprite_shaders.hpp); the fourth row stretches near the left and right edges,
//            markedly at a wide field of view (--fov 120, docs/PARTICLES.md's figure).
//   forest   trees as axis billboards (turning about the vertical only) and shrubs as billboard clouds
//            (three crossed static quads), alpha tested with depth writes (no sorting), on a chequered
//            ground, the camera orbiting the forest once a minute.
// Both textures are generated here (no binary assets). The clock (scenes.hpp): a frame shows the whole
// 1/60 s steps that fit in the scene's time, so it is a function of the options and that time alone.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "lecture/sprite_shaders.hpp"
#include "raster/teaching_draw.hpp"
#include "scene_list.hpp"

namespace raster {

namespace {

using shaders::FireParticleIn;
using shaders::SpriteQuadIn;
using shaders::StaticBillboardIn;

constexpr double kStepsPerSecond = 60.0;

// The scene time the frame shows: the whole steps that fit, with ParticleSystem::advance's tolerance.
float steppedTime(double time) {
    return float(std::floor(time * kStepsPerSecond + 1e-4) / kStepsPerSecond);
}

// What both scenes share: a clock that only advance() moves, and an opaque, depth-written frame.
class ClockedScene : public Scene {
  public:
    explicit ClockedScene(const SceneOptions& o) : time_(o.time.value_or(0.0)) {}
    bool animated() const override { return true; }
    double time() const override { return time_; }

  protected:
    void advanceBy(double seconds) override { time_ += seconds; }
    // The time the frame shows (steppedTime).
    float frameTime() const { return steppedTime(time_); }
    // Clears colour to `background` and depth to 1; opaque writes, depth test Less and depth writes.
    static void beginOpaqueFrame(Context& context, RenderTarget& color, DepthTarget& depth,
                                 glm::vec4 background) {
        beginSceneFrame(context, color, depth);
        context.clearRenderTarget(color, background);
        context.setBlendState(BlendState::opaque());
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
    }

  private:
    double time_ = 0.0;
};

// A deterministic hash of two integers to [0, 1) (no library random generator: their streams are not
// specified across standard libraries).
float hash01(uint32_t a, uint32_t b) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 15, h *= 0x2C1B3C6Du, h ^= h >> 12, h *= 0x297A2D39u, h ^= h >> 15;
    return float(h >> 8) * (1.0f / 16777216.0f);
}

using sprite_lab::proceduralTexture;  // RGBA8 texels from a function of the texel and its centre (u, v)

// ---- sprites ---------------------------------------------------------------------------------------

// A target: white and grey rings, a dark cross, transparent outside the disc (alpha-tested away): the
// sprite-methods lab's, with a narrower cross.
Texture2D makeSpriteTexture() { return sprite_lab::targetTexture(0.06f); }

constexpr int kSpriteRows = 4, kSpritesPerRow = 9;
constexpr float kSpriteScrollSeconds = 12.0f;  // a sprite crosses the image in this time
constexpr float kSpriteDepth = 6.0f;           // the default camera's distance to the sprites' plane z = 0
constexpr glm::vec4 kRowTints[kSpriteRows] = {{1.0f, 0.45f, 0.45f, 1.0f},
                                              {0.45f, 1.0f, 0.45f, 1.0f},
                                              {0.5f, 0.6f, 1.0f, 1.0f},
                                              {1.0f, 0.9f, 0.3f, 1.0f}};

class SpritesScene final : public ClockedScene {
  public:
    explicit SpritesScene(const SceneOptions& o)
        : ClockedScene(o), camera_(o.camera.value_or(kSpritesCamera)) {
        proj_ = sceneProjection(o);
        view_ = sceneView(camera_);
        const glm::mat4 view_proj = proj_ * view_;
        classic_ = {view_proj, glm::transpose(glm::mat3(view_))};
        own_ = {view_, proj_};
        gs_.viewProj = view_proj;
        gs_.projScale = {proj_[0][0], proj_[1][1]};
        facing_ = {view_proj, camera_.eye, glm::vec3(view_[0][1], view_[1][1], view_[2][1])};
        texture_ = makeSpriteTexture();
        ps_.texture = &texture_;
        quad_layout_ = shaders::spriteQuadLayout();
        point_layout_ = shaders::spritePointLayout();
    }
    std::string_view name() const override { return "sprites"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginOpaqueFrame(context, color, depth, {0.08f, 0.09f, 0.14f, 1.0f});
        const float t = frameTime();
        std::vector<SpriteQuadIn> quads[kSpriteRows];
        std::vector<FireParticleIn> points;
        for (int row = 0; row < kSpriteRows; ++row)
            for (int k = 0; k < kSpritesPerRow; ++k) {
                const FireParticleIn s = sprite(row, k, t);
                if (row == 2)
                    points.push_back(s);
                else
                    for (const glm::vec2 c : shaders::kSpriteCorners)
                        quads[row].push_back({s.position, s.size, s.colour, c});
            }
        drawQuads(context, quads[0], classic_);
        drawQuads(context, quads[1], own_);
        drawQuads(context, quads[3], facing_);
        const VertexBuffer buffer = VertexBuffer::create(points);
        context.setInputLayout(&point_layout_);
        context.setVertexBuffer(0, &buffer);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(shaders::VsFireParticle{}, gs_, ps_, uint32_t(points.size()));
    }

  private:
    // Sprite k of a row at time t, placed in the default camera's image (so a wider field of view
    // spreads the rows to its edges): x scrolls across [−1, 1] of the image's width and wraps.
    FireParticleIn sprite(int row, int k, float t) const {
        const float half_width = kSpriteDepth / proj_[0][0], half_height = kSpriteDepth / proj_[1][1];
        float s = (float(k) + 0.5f) / float(kSpritesPerRow) + t / kSpriteScrollSeconds;
        s -= std::floor(s);
        const float y = 0.62f - 0.413f * float(row);
        const glm::vec3 centre((2.0f * s - 1.0f) * half_width, y * half_height, 0.0f);
        return {centre, 0.16f * half_height, kRowTints[row]};
    }
    template <class VS>
    void drawQuads(Context& context, const std::vector<SpriteQuadIn>& quads, const VS& vs) {
        const VertexBuffer buffer = VertexBuffer::create(quads);
        context.setInputLayout(&quad_layout_);
        context.setVertexBuffer(0, &buffer);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.draw(vs, ps_, uint32_t(quads.size()));
    }

    SceneCamera camera_;
    glm::mat4 proj_, view_;
    shaders::VsSpriteClassic classic_;
    shaders::VsSpriteOwn own_;
    shaders::GsFireParticle gs_;
    shaders::VsSpriteFacingEye facing_;
    shaders::PsAlphaTested ps_;
    Texture2D texture_;
    InputLayout quad_layout_, point_layout_;
};

// ---- forest ----------------------------------------------------------------------------------------

// The palette: every pixel of the forest is one of these (point sampling, alpha test, no blending).
constexpr glm::u8vec4 kTrunk{92, 64, 40, 255}, kNeedlesDark{28, 84, 44, 255}, kNeedlesLight{58, 128, 60, 255};
constexpr glm::u8vec4 kLeavesDark{70, 110, 30, 255}, kLeavesLight{120, 160, 50, 255};
constexpr glm::u8vec4 kGroundA{96, 120, 70, 255}, kGroundB{84, 106, 62, 255};
constexpr glm::vec4 kSky{140 / 255.0f, 178 / 255.0f, 230 / 255.0f, 1.0f};  // RGBA8 (140, 178, 230)

// A fir, 128×256: a trunk and three tiers of needles, transparent around; texels within 1.5 texels of the
// crown's outline have alpha 96 (a soft edge that the alpha test removes).
Texture2D makeTreeTexture() {
    return proceduralTexture(128, 256, [](uint32_t i, uint32_t j, float u, float v) -> glm::u8vec4 {
        const float x = std::abs(u - 0.5f);
        // Each tier widens downwards from its top; the tiers overlap.
        float width = -1.0f;
        for (int tier = 0; tier < 3; ++tier) {
            const float top = 0.03f + 0.22f * float(tier), bottom = top + 0.36f;
            if (v >= top && v <= bottom)
                width = std::max(width, (0.2f + 0.08f * float(tier)) * (v - top) / 0.36f + 0.04f);
        }
        const float outside = (x - width) * 128.0f;  // texels beyond the outline
        if (width > 0.0f && outside <= 0.0f)
            return hash01(i / 2, j / 2) < 0.3f ? kNeedlesLight : kNeedlesDark;
        if (x < 0.05f && v > 0.7f && v < 0.98f) return kTrunk;
        if (width > 0.0f && outside < 1.5f) return {kNeedlesDark.r, kNeedlesDark.g, kNeedlesDark.b, 96};
        return {0, 0, 0, 0};
    });
}

// A shrub's leaves, 64×64: a ragged dome, transparent around.
Texture2D makeShrubTexture() {
    return proceduralTexture(64, 64, [](uint32_t i, uint32_t j, float u, float v) -> glm::u8vec4 {
        const float x = (u - 0.5f) / 0.48f, y = (v - 0.62f) / 0.38f;
        const float ragged = 0.85f + 0.15f * hash01(i / 3, j / 3 + 1000);
        if (x * x + y * y > ragged * ragged || v > 0.98f) return {0, 0, 0, 0};
        return hash01(i, j + 500) < 0.35f ? kLeavesLight : kLeavesDark;
    });
}

constexpr int kTrees = 70, kShrubs = 24;
constexpr float kForestRadius = 7.5f;
constexpr float kOrbitSeconds = 60.0f;  // one turn of the camera about the forest's vertical axis

// A point of the forest floor: uniform in the disc of radius kForestRadius (hashed, so a fixed set).
glm::vec3 forestSpot(uint32_t kind, uint32_t k) {
    const float r = kForestRadius * std::sqrt(hash01(kind, 2 * k)), a = 6.2831853f * hash01(kind, 2 * k + 1);
    return {r * std::cos(a), 0.0f, r * std::sin(a)};
}

class ForestScene final : public ClockedScene {
  public:
    explicit ForestScene(const SceneOptions& o)
        : ClockedScene(o), camera_(o.camera.value_or(kForestCamera)), proj_(sceneProjection(o)) {
        trees_tex_ = makeTreeTexture();
        shrubs_tex_ = makeShrubTexture();
        ground_tex_ = proceduralTexture(2, 2, [](uint32_t i, uint32_t j, float, float) {
            return (i + j) % 2 == 0 ? kGroundA : kGroundB;
        });
        std::vector<shaders::AxisBillboardIn> trees;
        for (uint32_t k = 0; k < kTrees; ++k) {
            const float height = 2.4f + 2.2f * hash01(7, k);
            for (const glm::vec2 c : shaders::kSpriteCorners)
                trees.push_back({forestSpot(1, k),
                                 {0.36f * height, height},
                                 glm::vec4(1.0f),
                                 {c.x, 0.5f * (c.y + 1.0f)}});
        }
        std::vector<StaticBillboardIn> shrubs;
        for (uint32_t k = 0; k < kShrubs; ++k) {
            const float size = 0.5f + 0.4f * hash01(9, k);
            const auto cloud = shaders::billboardCloud(forestSpot(2, k), size, 1.2f * size, 3,
                                                       3.0f * hash01(11, k), glm::vec4(1.0f));
            shrubs.insert(shrubs.end(), cloud.begin(), cloud.end());
        }
        std::vector<StaticBillboardIn> ground;
        shaders::appendStaticBillboard(ground, {0, 0, 0}, {40, 0, 0}, {0, 0, -40}, glm::vec4(1.0f));
        for (StaticBillboardIn& g : ground)
            g.tex = {g.position.x / 4.0f, g.position.z / 4.0f};  // 2 m squares
        tree_vertices_ = trees;
        trees_ = VertexBuffer::create(trees), shrubs_ = VertexBuffer::create(shrubs),
        ground_ = VertexBuffer::create(ground);
        counts_ = {uint32_t(trees.size()), uint32_t(shrubs.size()), uint32_t(ground.size())};
        tree_layout_ = shaders::axisBillboardLayout();
        static_layout_ = shaders::staticBillboardLayout();
    }
    std::string_view name() const override { return "forest"; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginOpaqueFrame(context, color, depth, kSky);
        context.setPrimitiveTopology(Topology::TriangleList);
        // The camera turned about the vertical through the origin by the orbit's angle at this time.
        const float angle = 6.2831853f * frameTime() / kOrbitSeconds;
        const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0, 1, 0)));
        const SceneCamera camera{turn * camera_.eye, turn * camera_.target};
        const glm::mat4 view_proj = proj_ * sceneView(camera);
        // Nearest first, so that the early depth test rejects what they hide before it is shaded: the
        // trees from the nearest, the shrubs, then the ground (1.6 million pixel shader calls instead of 2.7 at
        // 1280×720). Opaque writes under depth Less: the order shows only where two depths are equal.
        shaders::PsAlphaTested ps;
        ps.texture = &trees_tex_;
        sortTreesNearestFirst(camera.eye);
        context.setInputLayout(&tree_layout_);
        context.setVertexBuffer(0, &trees_);
        context.draw(shaders::VsAxisBillboard{view_proj, camera.eye, {0, 1, 0}}, ps, counts_[0]);
        ps.texture = &shrubs_tex_;
        drawStatic(context, shrubs_, counts_[1], view_proj, ps);
        ps.sampler = SamplerState::point(AddressMode::Wrap);
        ps.texture = &ground_tex_;
        drawStatic(context, ground_, counts_[2], view_proj, ps);
    }

  private:
    // Refills the trees' buffer in the order of their distance to the eye (ties by index: deterministic).
    void sortTreesNearestFirst(glm::vec3 eye) {
        std::vector<std::pair<float, uint32_t>> order;
        for (uint32_t k = 0; k < kTrees; ++k) {
            const glm::vec3 d = tree_vertices_[6 * k].base - eye;
            order.push_back({glm::dot(d, d), k});
        }
        std::sort(order.begin(), order.end());
        std::vector<shaders::AxisBillboardIn> sorted;
        for (const auto& [distance, k] : order)
            sorted.insert(sorted.end(), tree_vertices_.begin() + 6 * k, tree_vertices_.begin() + 6 * (k + 1));
        trees_.update(std::span<const shaders::AxisBillboardIn>(sorted));
    }
    void drawStatic(Context& context, const VertexBuffer& buffer, uint32_t count, const glm::mat4& view_proj,
                    const shaders::PsAlphaTested& ps) {
        context.setInputLayout(&static_layout_);
        context.setVertexBuffer(0, &buffer);
        context.draw(shaders::VsStaticBillboard{view_proj}, ps, count);
    }

    SceneCamera camera_;
    glm::mat4 proj_;
    Texture2D trees_tex_, shrubs_tex_, ground_tex_;
    std::vector<shaders::AxisBillboardIn> tree_vertices_;  // six a tree, in k order
    VertexBuffer trees_, shrubs_, ground_;
    std::array<uint32_t, 3> counts_{};
    InputLayout tree_layout_, static_layout_;
};

}  // namespace

std::unique_ptr<Scene> makeSpritesScene(const SceneOptions& options) {
    return std::make_unique<SpritesScene>(options);
}
std::unique_ptr<Scene> makeForestScene(const SceneOptions& options) {
    return std::make_unique<ForestScene>(options);
}

}  // namespace raster
