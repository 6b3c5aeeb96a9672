// The sprite-methods lab's scene (labs/sprite-methods/): everything but the student's shaders. The
// lab's file (and its solution, which fills the file's places) defines the shaders and registers
//
//   SpriteMethodsScene<VsSpriteClassic, VsSpriteOwn, GsSprite, VsTree, PsTextured>
//
// which builds the meadow, the firs and the rows of sprites and draws them through those shaders.
// What the scene hands each shader, by aggregate initialisation in this order of members:
//   Classic{view, viewProj}            (a): reads SpriteCornerIn, returns Corner
//   Own{view, proj}                    (b): reads SpriteCornerIn, returns Corner
//   Gs{viewProj, proj}                 (c): reads Point<SpritePoint>, appends Corner to a
//                                      TriangleStream<Corner, 4> (VsSpritePoint before it)
//   Tree{viewProj, eye, axis}          the firs: reads TreeCornerIn, returns Corner
//   Ps{texture, sampler}               every draw's pixel shader: reads Corner
// The vertex formats, the input layouts, the textures and the hash live here once, and the library's
// own `sprites` scene (src/scene_sprites.cpp) draws its quads from the same SpriteCornerIn and its
// textures with proceduralTexture and targetTexture.
//
// The scene: four rows of sprites scrolling to the right over a meadow with firs, (a) red, (b) green,
// (c) blue, then the three once more, each writing one colour channel; the camera swings about the
// target's vertical. The clock (scenes.hpp): a frame shows the whole 1/60 s steps that fit in the
// scene's time, so it is a function of the options and that time alone.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "raster/lab.hpp"

namespace raster::sprite_lab {

// ---- What the input assembler hands over, and what the shaders pass on -----------------------------

// One corner of a sprite's quad, for (a) and (b): six a sprite (two triangles).
struct SpriteCornerIn {
    glm::vec3 centre;  // world space
    float size;        // world units: half the quad's width
    glm::vec4 tint;
    glm::vec2 corner;  // (±1, ±1): which corner
    RASTER_INPUT_SIGNATURE(SpriteCornerIn, RASTER_INPUT(centre, "POSITION", 0), RASTER_INPUT(size, "SIZE", 0),
                           RASTER_INPUT(tint, "COLOR", 0), RASTER_INPUT(corner, "TEXCOORD", 0))
};

// One sprite as a point, for (c): the geometry shader makes the quad.
struct SpritePointIn {
    glm::vec3 centre;
    float size;
    glm::vec4 tint;
    RASTER_INPUT_SIGNATURE(SpritePointIn, RASTER_INPUT(centre, "POSITION", 0), RASTER_INPUT(size, "SIZE", 0),
                           RASTER_INPUT(tint, "COLOR", 0))
};

// What (c)'s vertex shader passes to the geometry shader.
struct SpritePoint {
    glm::vec4 position;  // the centre, world space, w = 1
    float size;
    glm::vec4 tint;
};

// One corner of a fir: six a fir; x in {−1, 1} across, y in {0, 1} from the foot up.
struct TreeCornerIn {
    glm::vec3 base;    // world space: the foot of the trunk
    glm::vec2 extent;  // world units: half the width, the height
    glm::vec2 corner;
    RASTER_INPUT_SIGNATURE(TreeCornerIn, RASTER_INPUT(base, "POSITION", 0), RASTER_INPUT(extent, "SIZE", 0),
                           RASTER_INPUT(corner, "TEXCOORD", 0))
};

struct GroundIn {
    glm::vec3 position;
    glm::vec2 tex;
    RASTER_INPUT_SIGNATURE(GroundIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(tex, "TEXCOORD", 0))
};

// What every pixel shader here reads: clip-space position, texture coordinate, tint.
struct Corner {
    glm::vec4 position;
    glm::vec2 tex;
    glm::vec4 tint;
};

// The corners in gsBillboard's order, as its strip's two triangles (v0 v1 v2) and (v1 v3 v2), so that
// a quad drawn as a triangle list is cut along the same diagonal as (c)'s.
inline constexpr glm::vec2 kSpriteCorners[6] = {{1, 1}, {1, -1}, {-1, 1}, {1, -1}, {-1, -1}, {-1, 1}};

// The lecture's gsBillboard texture coordinates: (1,1) → (1,0), (1,−1) → (1,1), (−1,1) → (0,0),
// (−1,−1) → (0,1).
inline glm::vec2 spriteTexCoord(glm::vec2 corner) {
    return {0.5f * (corner.x + 1.0f), 0.5f * (1.0f - corner.y)};
}

// (c)'s vertex shader: the centre, size and tint passed on to the geometry shader.
struct VsSpritePoint {
    SpritePoint operator()(const SpritePointIn& in) const {
        return {glm::vec4(in.centre, 1.0f), in.size, in.tint};
    }
};

// The meadow: world position to clip space, its texture coordinate, no tint.
struct VsGround {
    glm::mat4 viewProj{1.0f};
    Corner operator()(const GroundIn& in) const {
        return {viewProj * glm::vec4(in.position, 1.0f), in.tex, glm::vec4(1.0f)};
    }
};

// ---- Textures and the seeded placement (src/sprite_lab.cpp) ----------------------------------------

// A hash of three integers to [0, 1) (a fixed function, the same on every machine).
float hash01(uint32_t a, uint32_t b, uint32_t c);

// RGBA8 texels, row 0 on top, from texel(i, j, u, v): the texel (i, j) and its centre (u, v) in [0, 1]².
template <class F>
Texture2D proceduralTexture(uint32_t width, uint32_t height, F texel) {
    std::vector<uint8_t> rgba(size_t(width) * height * 4);
    for (uint32_t j = 0; j < height; ++j)
        for (uint32_t i = 0; i < width; ++i) {
            const glm::u8vec4 c =
                texel(i, j, (float(i) + 0.5f) / float(width), (float(j) + 0.5f) / float(height));
            for (int k = 0; k < 4; ++k) rgba[4 * (size_t(j) * width + i) + k] = c[k];
        }
    return Texture2D::fromRgba8(width, height, rgba);
}

// A target, 64×64: white and grey rings and a dark cross (|x| or |y| below crossHalfWidth, in units of
// the disc's radius) in a disc, transparent outside it.
Texture2D targetTexture(float crossHalfWidth);
// The lab's fir, 64×128: a trunk under three tiers of needles, transparent around; a rim of
// half-transparent needles (alpha 96) along the crown's outline, which the alpha test removes.
Texture2D firTexture();
// The meadow's 2×2 chequer.
Texture2D meadowTexture();
// `trees` firs on the meadow behind the rows and beside them (not in front of them), from the seed:
// six corners a fir.
std::vector<TreeCornerIn> plantTrees(uint32_t seed, int trees);
// The meadow: one quad 32 m wide, textured in 2 m squares.
std::vector<GroundIn> meadowQuad();

// The input layouts of the formats above (offsets by offsetof).
InputLayout spriteCornerLayout();
InputLayout spritePointLayout();
InputLayout treeCornerLayout();
InputLayout groundLayout();

// A blend state that writes only colour channel `channel` (0 red, 1 green, 2 blue).
BlendState channelOnly(int channel);

// ---- The scene -------------------------------------------------------------------------------------

inline constexpr float kStepsPerSecond = 60.0f;
inline constexpr int kRows = 4;             // (a), (b), (c), and the three overlaid
inline constexpr uint32_t kMaxPerRow = 64;  // the options' count: sprites per row
inline constexpr uint32_t kDefaultPerRow = 7;
inline constexpr float kRowSpan = 11.2f;       // world units along x that a row's sprites share, and wrap in
inline constexpr float kScrollSpeed = 0.4f;    // world units per second
inline constexpr float kSwingDegrees = 20.0f;  // the camera swings about the target's vertical by ± this
inline constexpr float kSwingSeconds = 16.0f;  // one swing there and back
inline constexpr int kTrees = 12;
inline constexpr glm::vec4 kRowTints[kRows] = {{0.95f, 0.45f, 0.45f, 1.0f},
                                               {0.45f, 0.95f, 0.45f, 1.0f},
                                               {0.5f, 0.6f, 0.95f, 1.0f},
                                               {1.0f, 1.0f, 1.0f, 1.0f}};
// No colour of the scene has a channel equal to one of the targets' greys (255, 150, 40) unless all
// three are, as the fourth row's are where the methods agree: a fringe is a pixel with one or two.
// Where the lab looks from at time 0: to the right of the rows and a little above them.
inline constexpr SceneCamera kCamera{{3.2f, 3.0f, 9.0f}, {0.0f, 2.4f, 0.0f}};
inline constexpr glm::vec4 kSky{140 / 255.0f, 178 / 255.0f, 230 / 255.0f, 1.0f};
inline constexpr float kTargetCross = 0.07f;  // the lab's targets' cross: half-width, disc radii

// Row `row`'s sprites at time t: `per_row` spread over kRowSpan along x, scrolling to the right and
// wrapping; sprite k has the same size in every row (from the seed), so the rows line up.
std::vector<SpritePointIn> rowSprites(int row, float t, uint32_t per_row, uint32_t seed);
// The options' camera swung about the vertical through its target at time t.
SceneCamera swungCamera(const SceneCamera& camera, float t);
// The sprites-per-row count of the options, checked against kMaxPerRow (a named error).
uint32_t spritesPerRow(const SceneOptions& options);

template <class Classic, class Own, class Gs, class Tree, class Ps>
class SpriteMethodsScene final : public LabScene {
  public:
    explicit SpriteMethodsScene(const SceneOptions& o)
        : camera_(o.camera.value_or(kCamera)),
          proj_(sceneProjection(o)),
          time_(o.time.value_or(0.0)),
          per_row_(spritesPerRow(o)),
          seed_(o.seed),
          target_(targetTexture(kTargetCross)),
          fir_(firTexture()),
          ground_texture_(meadowTexture()),
          corner_layout_(spriteCornerLayout()),
          point_layout_(spritePointLayout()),
          tree_layout_(treeCornerLayout()),
          ground_layout_(groundLayout()),
          trees_(VertexBuffer::create(plantTrees(seed_, kTrees))),
          ground_(VertexBuffer::create(meadowQuad())) {}

    bool animated() const override { return true; }
    double time() const override { return time_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        context.clearRenderTarget(color, kSky);
        context.setBlendState(BlendState::opaque());
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
        context.setPrimitiveTopology(Topology::TriangleList);
        const float t = float(std::floor(time_ * kStepsPerSecond + 1e-4) / kStepsPerSecond);
        const SceneCamera camera = swungCamera(camera_, t);
        const glm::mat4 view = sceneView(camera), view_proj = proj_ * view;
        // Draw 0: the meadow; draw 1: the firs.
        Ps ps{&ground_texture_, SamplerState::point(AddressMode::Wrap)};
        bind(context, ground_layout_, ground_);
        context.draw(VsGround{view_proj}, ps, 6);
        ps = {&fir_};
        bind(context, tree_layout_, trees_);
        context.draw(Tree{view_proj, camera.eye, {0, 1, 0}}, ps, 6 * kTrees);
        // Draws 2-4: the rows (a), (b), (c); draws 5-7: the three once more, one channel each.
        ps = {&target_};
        const Classic classic{view, view_proj};
        const Own own{view, proj_};
        const Gs gs{view_proj, proj_};
        drawCorners(context, rowSprites(0, t, per_row_, seed_), classic, ps);
        drawCorners(context, rowSprites(1, t, per_row_, seed_), own, ps);
        drawPoints(context, rowSprites(2, t, per_row_, seed_), gs, ps);
        const std::vector<SpritePointIn> overlay = rowSprites(3, t, per_row_, seed_);
        context.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        context.setBlendState(channelOnly(0));
        drawCorners(context, overlay, classic, ps);
        context.setBlendState(channelOnly(1));
        drawCorners(context, overlay, own, ps);
        context.setBlendState(channelOnly(2));
        drawPoints(context, overlay, gs, ps);
    }

  protected:
    void advanceBy(double seconds) override { time_ += seconds; }

  private:
    static void bind(Context& context, const InputLayout& layout, const VertexBuffer& buffer) {
        context.setInputLayout(&layout);
        context.setVertexBuffer(0, &buffer);
    }
    template <class VS>
    void drawCorners(Context& context, const std::vector<SpritePointIn>& sprites, const VS& vs,
                     const Ps& ps) {
        std::vector<SpriteCornerIn> corners;
        for (const SpritePointIn& s : sprites)
            for (const glm::vec2 c : kSpriteCorners) corners.push_back({s.centre, s.size, s.tint, c});
        const VertexBuffer buffer = VertexBuffer::create(corners);
        bind(context, corner_layout_, buffer);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.draw(vs, ps, uint32_t(corners.size()));
    }
    void drawPoints(Context& context, const std::vector<SpritePointIn>& sprites, const Gs& gs, const Ps& ps) {
        const VertexBuffer buffer = VertexBuffer::create(sprites);
        bind(context, point_layout_, buffer);
        context.setPrimitiveTopology(Topology::PointList);
        context.draw(VsSpritePoint{}, gs, ps, uint32_t(sprites.size()));
    }

    SceneCamera camera_;
    glm::mat4 proj_;
    double time_;
    uint32_t per_row_, seed_;
    Texture2D target_, fir_, ground_texture_;
    InputLayout corner_layout_, point_layout_, tree_layout_, ground_layout_;
    VertexBuffer trees_, ground_;
};

}  // namespace raster::sprite_lab
