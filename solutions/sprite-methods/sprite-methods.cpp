// BEGIN NOTE
// Lab: sprites three ways and a billboard about an axis (lecture 11, part 3) - THE SOLUTION.
//
// Rows of camera-facing sprites floating over a meadow with firs: (a) classic transforms (red),
// (b) the sprite's own transform (green), (c) opened after projection by the geometry shader (blue),
// and a fourth row where the three methods draw the same sprites into one colour channel each
// (a red, b green, c blue): grey targets where they agree, coloured fringes where one is off. The
// firs are billboards that turn about the vertical only. Everything is alpha tested. This is
// labs/sprite-methods/sprite-methods.cpp with every `LAB n` place filled in; its image is the one the
// student's is compared with (raster view sprite-methods, K and J).
// STAND-IN
//> // Lab: sprites three ways and a billboard about an axis (lecture 11, part 3).
//> //
//> // Rows of camera-facing sprites floating over a meadow with firs: (a) classic transforms (red),
//> // (b) the sprite's own transform (green), (c) opened after projection by the geometry shader (blue),
//> // and a fourth row where your three methods draw the same sprites into one colour channel each
//> // (a red, b green, c blue): grey targets where they agree, coloured fringes where one is off. The
//> // firs are billboards that turn about the vertical only. Everything is alpha tested.
//> //
//> // As handed out, this file compiles and runs but draws the sprites lying flat or not at all, the
//> // firs turned away and every quad's transparent corners black. Fill in the five places marked
//> // `LAB n`, in order; each one changes the picture:
//> //   LAB 1  (a): the rotation that turns the sprite's quad to face the camera (classic transforms).
//> //   LAB 2  (b): the corner's offset, added to the centre in camera space.
//> //   LAB 3  (c): the geometry shader's four corners, offset in clip space.
//> //   LAB 4  the firs' right vector: turn about the vertical axis to face the eye.
//> //   LAB 5  the alpha test: discard the texels that are not opaque enough.
//> //
//> //   cmake --build build --target raster_tool && build/bin/raster view sprite-methods
//> //
//> // In the viewer, Space plays and pauses the time ('.' and ',' step it), K shows the solution's image
//> // and J the difference from it; click a pixel for its history. Look at labs/sprite-methods/README.md
//> // for what each step should show.
// END NOTE
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <string>
#include <vector>

#include "raster/lab.hpp"

namespace {

using namespace raster;

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

// The lecture's gsBillboard texture coordinates: (1,1) → (1,0), (1,−1) → (1,1), (−1,1) → (0,0),
// (−1,−1) → (0,1).
glm::vec2 spriteTexCoord(glm::vec2 corner) {
    return {0.5f * (corner.x + 1.0f), 0.5f * (1.0f - corner.y)};
}

// ---- (a) classic transforms ------------------------------------------------------------------------

// BEGIN LAB 1
// STAND-IN
//> // The columns are where the quad's x, y and z go: x stays, y to −z, z (its normal) to +y.
//> const glm::mat3 kLyingFlat(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
//>
// END LAB 1
// The sprite's model is a quad in its plane z = 0, facing +z. Its model matrix turns that plane to
// the camera's and moves it to the centre; then the usual view and projection (viewProj = P·V).
struct VsSpriteClassic {
    glm::mat4 view{1.0f};      // V: world to camera
    glm::mat4 viewProj{1.0f};  // P·V

    Corner operator()(const SpriteCornerIn& in) const {
        // BEGIN LAB 1
        // LAB 1: V's rotation R turns the world to the camera; the quad must be turned by R's inverse
        // so that V undoes it: R⁻¹ = Rᵀ for a rotation (the slide's "inverse transpose" is (R⁻¹)ᵀ = R,
        // which would turn the quad twice).
        const glm::mat3 rotation = glm::transpose(glm::mat3(view));
        // STAND-IN
        //> // LAB 1: turn the quad so that it faces the camera. The view matrix's upper 3×3, R, turns
        //> // the world to the camera; which rotation of the quad does V then undo? (The slide says "the
        //> // inverse transpose of the view rotation": work out what that is for a rotation before you
        //> // trust it.) As handed out the quad is turned to lie flat, facing up: seen from the side.
        //> const glm::mat3 rotation = kLyingFlat;
        // END LAB 1
        glm::mat4 model(rotation);
        model[3] = glm::vec4(in.centre, 1.0f);
        const glm::vec4 local(in.size * in.corner.x, in.size * in.corner.y, 0.0f, 1.0f);
        return {viewProj * (model * local), spriteTexCoord(in.corner), in.tint};
    }
};

// ---- (b) its own transform -------------------------------------------------------------------------

struct VsSpriteOwn {
    glm::mat4 view{1.0f}, proj{1.0f};

    Corner operator()(const SpriteCornerIn& in) const {
        glm::vec4 corner = view * glm::vec4(in.centre, 1.0f);  // the centre in camera space
        // BEGIN LAB 2
        // slide: own-transform
        // LAB 2: add the corner's offset in camera space, where x is the screen's right and y its up.
        corner.x += in.size * in.corner.x;
        corner.y += in.size * in.corner.y;
        // end slide: own-transform
        // STAND-IN
        //> // LAB 2: add the corner's offset, (±size, ±size) from in.size and in.corner, in camera space,
        //> // where x is the screen's right and y its up. As handed out nothing is added: the six corners
        //> // sit on the centre, two triangles of no area, and the row is empty.
        // END LAB 2
        return {proj * corner, spriteTexCoord(in.corner), in.tint};
    }
};

// ---- (c) opened after projection ------------------------------------------------------------------

struct VsSpritePoint {
    SpritePoint operator()(const SpritePointIn& in) const {
        return {glm::vec4(in.centre, 1.0f), in.size, in.tint};
    }
};

struct GsSprite {
    glm::mat4 viewProj{1.0f}, proj{1.0f};

    void operator()(const Point<SpritePoint>& in, TriangleStream<Corner, 4>& stream) const {
        const SpritePoint& p = in[0];
        const glm::vec4 c = viewProj * p.position;
        // BEGIN LAB 3
        // LAB 3: the offset (±size, ±size, 0, 0) in camera space is (±size·P[0][0], ±size·P[1][1], 0, 0)
        // in clip space; added before the division by w, it shrinks with distance as the quad does.
        const float bx = p.size * proj[0][0], by = p.size * proj[1][1];
        stream.Append({c + glm::vec4(bx, by, 0, 0), {1, 0}, p.tint});
        stream.Append({c + glm::vec4(bx, -by, 0, 0), {1, 1}, p.tint});
        stream.Append({c + glm::vec4(-bx, by, 0, 0), {0, 0}, p.tint});
        stream.Append({c + glm::vec4(-bx, -by, 0, 0), {0, 1}, p.tint});
        // STAND-IN
        //> // LAB 3: open the sprite after the projection: emit the corners c + (±bx, ±by, 0, 0) as a
        //> // triangle strip in the lecture's order, (+x, +y) uv (1, 0), (+x, −y) uv (1, 1), (−x, +y)
        //> // uv (0, 0), (−x, −y) uv (0, 1). What must bx and by be for the quad to be (b)'s, p.size world
        //> // units wide in camera space? (What does P do to a camera-space offset (x, y, 0, 0)?)
        //> // As handed out the four corners sit on the centre: nothing is drawn.
        //> stream.Append({c, {1, 0}, p.tint});
        //> stream.Append({c, {1, 1}, p.tint});
        //> stream.Append({c, {0, 0}, p.tint});
        //> stream.Append({c, {0, 1}, p.tint});
        // END LAB 3
    }
};

// ---- The firs: billboards turning about the vertical ----------------------------------------------

struct VsTree {
    glm::mat4 viewProj{1.0f};
    glm::vec3 eye{0.0f};      // world space
    glm::vec3 axis{0, 1, 0};  // unit, world space: the trunk's direction

    Corner operator()(const TreeCornerIn& in) const {
        // BEGIN LAB 4
        // LAB 4: the quad keeps the axis and turns about it to face the eye: its right vector is
        // normal to the axis and to the direction to the eye. (From a point on the axis line any
        // right vector normal to the axis will do.)
        glm::vec3 side = glm::cross(axis, eye - in.base);
        if (!(glm::length(side) > 1e-12f)) side = glm::cross(axis, glm::vec3(1, 0, 0));
        const glm::vec3 right = glm::normalize(side);
        // STAND-IN
        //> // LAB 4: the quad keeps the axis (the trunk stays upright) and turns about it to face the
        //> // eye: its right vector, of unit length, must be normal to the axis and to the direction
        //> // from the foot to the eye. (And when the eye is on the axis line?) As handed out it is the
        //> // world's z axis: seen from the front, each fir is edge-on, a thin sliver.
        //> const glm::vec3 right(0.0f, 0.0f, 1.0f);
        // END LAB 4
        const glm::vec3 world =
            in.base + (in.corner.x * in.extent.x) * right + (in.corner.y * in.extent.y) * axis;
        return {viewProj * glm::vec4(world, 1.0f),
                {0.5f * (in.corner.x + 1.0f), 1.0f - in.corner.y},
                glm::vec4(1.0f)};
    }
};

struct VsGround {
    glm::mat4 viewProj{1.0f};
    Corner operator()(const GroundIn& in) const {
        return {viewProj * glm::vec4(in.position, 1.0f), in.tex, glm::vec4(1.0f)};
    }
};

// ---- The pixel shader: the alpha test -----------------------------------------------------------

// BEGIN LAB 5
// LAB 5: the texel times the tint, but only where it is opaque enough: discard (std::nullopt) where
// its alpha times the tint's is below one half, and write the rest opaque (alpha 1).
std::optional<glm::vec4> alphaTested(glm::vec4 texel, glm::vec4 tint) {
    if (texel.w * tint.w < 0.5f) return std::nullopt;
    return glm::vec4(texel.x * tint.x, texel.y * tint.y, texel.z * tint.z, 1.0f);
}
// STAND-IN
//> // LAB 5: the alpha test. Return std::nullopt (the fragment is discarded: no colour, no depth) where the
//> // texel's alpha times the tint's is below one half; write the rest opaque (alpha 1), as now. As handed
//> // out nothing is discarded: each quad's transparent texels are drawn black and hide what is behind.
//> std::optional<glm::vec4> alphaTested(glm::vec4 texel, glm::vec4 tint) {
    //> return glm::vec4(texel.x * tint.x, texel.y * tint.y, texel.z * tint.z, 1.0f);
//> }
// END LAB 5

struct PsTextured {
    using Input = Corner;
    const Texture2D* texture = nullptr;
    SamplerState sampler = SamplerState::point(AddressMode::Clamp);
    std::optional<glm::vec4> operator()(const Corner& in) const {
        return alphaTested(texture->Sample(sampler, in.tex), in.tint);
    }
};

// ---- The scene (no LAB place below) ----------------------------------------------------------------

constexpr float kStepsPerSecond = 60.0f;
constexpr int kRows = 4;             // (a), (b), (c), and the three overlaid
constexpr uint32_t kMaxPerRow = 64;  // the options' count: sprites per row
constexpr uint32_t kDefaultPerRow = 7;
constexpr float kRowSpan = 11.2f;       // world units along x that a row's sprites share, and wrap in
constexpr float kScrollSpeed = 0.4f;    // world units per second
constexpr float kSwingDegrees = 20.0f;  // the camera swings about the target's vertical by ± this
constexpr float kSwingSeconds = 16.0f;  // one swing there and back
constexpr int kTrees = 12;
constexpr glm::vec4 kRowTints[kRows] = {{0.95f, 0.45f, 0.45f, 1.0f},
                                        {0.45f, 0.95f, 0.45f, 1.0f},
                                        {0.5f, 0.6f, 0.95f, 1.0f},
                                        {1.0f, 1.0f, 1.0f, 1.0f}};
// No colour of the scene has a channel equal to one of the targets' greys (255, 150, 40) unless all
// three are, as the fourth row's are where the methods agree: a fringe is a pixel with one or two.
// Where the lab looks from at time 0: to the right of the rows and a little above them.
constexpr SceneCamera kCamera{{3.2f, 3.0f, 9.0f}, {0.0f, 2.4f, 0.0f}};
constexpr glm::vec4 kSky{140 / 255.0f, 178 / 255.0f, 230 / 255.0f, 1.0f};

// A hash of three integers to [0, 1) (a fixed function, the same on every machine).
float hash01(uint32_t a, uint32_t b, uint32_t c) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
    h ^= h >> 15, h *= 0x2C1B3C6Du, h ^= h >> 12, h *= 0x297A2D39u, h ^= h >> 15;
    return float(h >> 8) * (1.0f / 16777216.0f);
}

// RGBA8 texels, row 0 on top, from a function of the texel (i, j) and its centre (u, v) in [0, 1]².
template <class F>
Texture2D makeTexture(uint32_t width, uint32_t height, F texel) {
    std::vector<uint8_t> rgba;
    rgba.reserve(size_t(width) * height * 4);
    for (uint32_t j = 0; j < height; ++j)
        for (uint32_t i = 0; i < width; ++i) {
            const glm::u8vec4 c =
                texel(i, j, (float(i) + 0.5f) / float(width), (float(j) + 0.5f) / float(height));
            rgba.insert(rgba.end(), {c.r, c.g, c.b, c.a});
        }
    return Texture2D::fromRgba8(width, height, rgba);
}

// A target: white and grey rings and a dark cross in a disc, transparent outside it.
Texture2D targetTexture() {
    return makeTexture(64, 64, [](uint32_t, uint32_t, float u, float v) -> glm::u8vec4 {
        const float x = 2.0f * u - 1.0f, y = 2.0f * v - 1.0f, r = std::sqrt(x * x + y * y);
        if (r > 1.0f) return {0, 0, 0, 0};
        if (std::abs(x) < 0.07f || std::abs(y) < 0.07f) return {40, 40, 40, 255};
        return int(r * 4.0f) % 2 == 0 ? glm::u8vec4(255, 255, 255, 255) : glm::u8vec4(150, 150, 150, 255);
    });
}

// A fir, 64×128: a trunk under three tiers of needles, transparent around; a rim of half-transparent
// needles (alpha 96) along the crown's outline, which the alpha test removes.
Texture2D firTexture() {
    return makeTexture(64, 128, [](uint32_t i, uint32_t j, float u, float v) -> glm::u8vec4 {
        const float x = std::abs(u - 0.5f);
        float half_width = -1.0f;
        for (int tier = 0; tier < 3; ++tier) {
            const float top = 0.04f + 0.24f * float(tier);
            if (v >= top && v <= top + 0.36f)
                half_width = std::max(half_width, 0.05f + (0.22f + 0.07f * float(tier)) * (v - top) / 0.36f);
        }
        const float outside = (x - half_width) * 64.0f;  // texels beyond the crown's outline
        if (half_width > 0.0f && outside <= 0.0f)
            return hash01(i / 2, j / 2, 5) < 0.3f ? glm::u8vec4(58, 128, 60, 255)
                                                  : glm::u8vec4(28, 84, 44, 255);
        if (x < 0.05f && v > 0.7f && v < 0.98f) return {92, 64, 42, 255};
        if (half_width > 0.0f && outside < 1.5f) return {28, 84, 44, 96};
        return {0, 0, 0, 0};
    });
}

class SpritesLab final : public LabScene {
  public:
    explicit SpritesLab(const SceneOptions& o)
        : camera_(o.camera.value_or(kCamera)),
          proj_(sceneProjection(o)),
          time_(o.time.value_or(0.0)),
          per_row_(o.count.value_or(kDefaultPerRow)),
          seed_(o.seed) {
        if (per_row_ > kMaxPerRow)
            throw Error(ErrorCode::InvalidArgument,
                        "sprite-methods: count (sprites per row) must be at most " +
                            std::to_string(kMaxPerRow) + ", not " + std::to_string(per_row_));
        target_ = targetTexture(), fir_ = firTexture();
        ground_texture_ = makeTexture(2, 2, [](uint32_t i, uint32_t j, float, float) {
            return (i + j) % 2 == 0 ? glm::u8vec4(96, 120, 70, 255) : glm::u8vec4(84, 106, 62, 255);
        });
        const InputElementDesc corner[] = {
            {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, centre))},
            {"SIZE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, size))},
            {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, tint))},
            {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(SpriteCornerIn, corner))}};
        const InputElementDesc point[] = {
            {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(SpritePointIn, centre))},
            {"SIZE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(SpritePointIn, size))},
            {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(SpritePointIn, tint))}};
        const InputElementDesc tree[] = {
            {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(TreeCornerIn, base))},
            {"SIZE", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(TreeCornerIn, extent))},
            {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(TreeCornerIn, corner))}};
        const InputElementDesc ground[] = {
            {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(GroundIn, position))},
            {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(GroundIn, tex))}};
        corner_layout_ = InputLayout(corner), point_layout_ = InputLayout(point);
        tree_layout_ = InputLayout(tree), ground_layout_ = InputLayout(ground);
        trees_ = VertexBuffer::create(plantTrees(seed_));
        ground_ = VertexBuffer::create(groundQuad());
    }

    bool animated() const override { return true; }
    double time() const override { return time_; }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        context.clearRenderTarget(color, kSky);
        context.setBlendState(BlendState::opaque());
        context.setDepthStencilState({true, true, ComparisonFunc::Less});
        context.setPrimitiveTopology(Topology::TriangleList);
        const float t = frameTime();
        const SceneCamera camera = cameraAt(t);
        const glm::mat4 view = sceneView(camera), view_proj = proj_ * view;
        // Draw 0: the meadow; draw 1: the firs.
        PsTextured ps{&ground_texture_, SamplerState::point(AddressMode::Wrap)};
        bind(context, ground_layout_, ground_);
        context.draw(VsGround{view_proj}, ps, 6);
        ps = {&fir_};
        bind(context, tree_layout_, trees_);
        context.draw(VsTree{view_proj, camera.eye, {0, 1, 0}}, ps, 6 * kTrees);
        // Draws 2-4: the rows (a), (b), (c); draws 5-7: the three once more, one channel each.
        ps = {&target_};
        const VsSpriteClassic classic{view, view_proj};
        const VsSpriteOwn own{view, proj_};
        const GsSprite gs{view_proj, proj_};
        drawCorners(context, sprites(0, t), classic, ps);
        drawCorners(context, sprites(1, t), own, ps);
        drawPoints(context, sprites(2, t), gs, ps);
        const std::vector<SpritePointIn> overlay = sprites(3, t);
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
    // The whole 1/60 s steps that fit in the clock's time (scenes.hpp): a frame is a function of the
    // options and the time alone.
    float frameTime() const { return float(std::floor(time_ * kStepsPerSecond + 1e-4) / kStepsPerSecond); }

    // The options' camera swung about the vertical through its target.
    SceneCamera cameraAt(float t) const {
        const float yaw = glm::radians(kSwingDegrees) * std::sin(6.2831853f * t / kSwingSeconds);
        const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0)));
        return {camera_.target + turn * (camera_.eye - camera_.target), camera_.target};
    }

    // Row `row`'s sprites at time t: spread over kRowSpan along x, scrolling to the right and wrapping;
    // sprite k has the same size in every row (from the seed), so the rows line up.
    std::vector<SpritePointIn> sprites(int row, float t) const {
        std::vector<SpritePointIn> out;
        for (uint32_t k = 0; k < per_row_; ++k) {
            float s = (float(k) + 0.5f) / float(per_row_) + t * kScrollSpeed / kRowSpan;
            s -= std::floor(s);
            const glm::vec3 centre((s - 0.5f) * kRowSpan, 4.6f - 0.95f * float(row), 0.0f);
            out.push_back({centre, 0.3f + 0.12f * hash01(seed_, k, 1), kRowTints[row]});
        }
        return out;
    }

    // kTrees firs on the meadow behind the rows and beside them (not in front of them), from the seed.
    static std::vector<TreeCornerIn> plantTrees(uint32_t seed) {
        std::vector<TreeCornerIn> out;
        for (uint32_t k = 0, attempt = 0; int(out.size()) < 6 * kTrees; ++attempt) {
            const glm::vec3 base(-10.0f + 20.0f * hash01(seed, attempt, 2), 0.0f,
                                 -10.0f + 13.0f * hash01(seed, attempt, 3));
            if (base.z > -2.5f && std::abs(base.x) < 6.5f) continue;
            const float height = 2.6f + 2.0f * hash01(seed, k++, 4);
            for (const glm::vec2 c : {glm::vec2(1, 1), glm::vec2(1, 0), glm::vec2(-1, 1), glm::vec2(1, 0),
                                      glm::vec2(-1, 0), glm::vec2(-1, 1)})
                out.push_back({base, {0.3f * height, height}, c});
        }
        return out;
    }
    static std::vector<GroundIn> groundQuad() {
        std::vector<GroundIn> out;
        for (const glm::vec2 c : {glm::vec2(1, 1), glm::vec2(1, -1), glm::vec2(-1, 1), glm::vec2(1, -1),
                                  glm::vec2(-1, -1), glm::vec2(-1, 1)})
            out.push_back(
                {{16.0f * c.x, 0.0f, -4.0f - 16.0f * c.y}, {4.0f * c.x, 4.0f * c.y}});  // 2 m squares
        return out;
    }

    // Writes only colour channel `channel` (0 red, 1 green, 2 blue); the others keep what they hold.
    static BlendState channelOnly(int channel) {
        BlendState blend = BlendState::opaque();
        blend.renderTarget[0].renderTargetWriteMask = uint8_t(1u << channel);
        return blend;
    }
    static void bind(Context& context, const InputLayout& layout, const VertexBuffer& buffer) {
        context.setInputLayout(&layout);
        context.setVertexBuffer(0, &buffer);
    }
    template <class VS>
    void drawCorners(Context& context, const std::vector<SpritePointIn>& sprites, const VS& vs,
                     const PsTextured& ps) {
        std::vector<SpriteCornerIn> corners;
        for (const SpritePointIn& s : sprites)  // gsBillboard's strip as two triangles (0 1 2) (1 3 2)
            for (const glm::vec2 c : {glm::vec2(1, 1), glm::vec2(1, -1), glm::vec2(-1, 1), glm::vec2(1, -1),
                                      glm::vec2(-1, -1), glm::vec2(-1, 1)})
                corners.push_back({s.centre, s.size, s.tint, c});
        const VertexBuffer buffer = VertexBuffer::create(corners);
        bind(context, corner_layout_, buffer);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.draw(vs, ps, uint32_t(corners.size()));
    }
    void drawPoints(Context& context, const std::vector<SpritePointIn>& sprites, const GsSprite& gs,
                    const PsTextured& ps) {
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

}  // namespace

RASTER_LAB("sprite-methods", "Lab: sprites three ways and a billboard about an axis (lecture 11, part 3)",
           SpritesLab, kCamera)
