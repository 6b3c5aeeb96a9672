// The pixel shader stage through the pipeline: perspective-correct interpolation, SV_Position,
// discard, multiple render targets, derivatives and mip selection, early depth and blend no-ops.
#include "raster/stages/8_pixel_shader.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <random>
#include <cmath>
#include <optional>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shader_context.hpp"
#include "raster/shaders/basic.hpp"
#include "raster/texture.hpp"

#include "eight_only.hpp"

namespace raster {
namespace {

using shaders::PositionOnly;
using shaders::PsConstant;
using shaders::VsTransform;

const glm::vec4 kClear(0.1f, 0.2f, 0.3f, 1.0f);
const glm::vec4 kWhite(1.0f);

// NDC of pixel coordinates (x right, y down) on a w×h viewport.
glm::vec2 ndcOf(double px, double py, double w, double h) {
    return {float(px / w * 2.0 - 1.0), float(1.0 - py / h * 2.0)};
}

// Two triangles covering the pixel rectangle [x0, x1) × [y0, y1) of a w×h viewport at depth z.
std::vector<glm::vec3> quad(float x0, float y0, float x1, float y1, float w, float h, float z) {
    const glm::vec2 a = ndcOf(x0, y0, w, h), b = ndcOf(x1, y1, w, h);
    return {{a.x, b.y, z}, {a.x, a.y, z}, {b.x, b.y, z}, {b.x, b.y, z}, {a.x, a.y, z}, {b.x, a.y, z}};
}

struct Fixture {
    Context ctx;
    RenderTarget color;
    DepthTarget depth;
    InputLayout layout;
    VertexBuffer vb;
    uint32_t width, height;
    Fixture(uint32_t w, uint32_t h, Format format = Format::R8G8B8A8_UNORM, const ContextOptions& options = {})
        : ctx(options), color(w, h, format), depth(w, h), width(w), height(h) {
        color.clear(kClear);
        depth.clear(1.0f);
        ctx.setRenderTargets(&color, &depth);
        ctx.setViewport({0, 0, float(w), float(h), 0, 1});
        RasterizerState none;
        none.cullMode = CullMode::None;
        ctx.setRasterizerState(none);
        ctx.setPrimitiveTopology(Topology::TriangleList);
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
        setLayout(desc);
    }
    template <size_t N>
    void setLayout(const InputElementDesc (&desc)[N]) {
        layout = InputLayout(desc);
        ctx.setInputLayout(&layout);
    }
    template <class T>
    void setVertices(const std::vector<T>& v) {
        vb = VertexBuffer::create(v);
        ctx.setVertexBuffer(0, &vb);
    }
    // A quad over [x0, x1) × [y0, y1) drawn with ps.
    template <class PS>
    void drawQuad(const PS& ps, float x0, float y0, float x1, float y1, float z) {
        setVertices(quad(x0, y0, x1, y1, float(width), float(height), z));
        ctx.draw(VsTransform{}, ps, 6);
    }
};

// ---- Perspective-correct interpolation ------------------------------------------------------------

struct ClipWorldVertex {
    glm::vec4 clip;
    glm::vec3 world;
};
struct ClipWorldIn {
    glm::vec4 clip;
    glm::vec3 world;
    RASTER_INPUT_SIGNATURE(ClipWorldIn, RASTER_INPUT(clip, "POSITION", 0), RASTER_INPUT(world, "WORLD", 0))
};
struct WorldVertex {
    glm::vec4 position;
    glm::vec3 world;
};
struct VsClipWorld {
    WorldVertex operator()(const ClipWorldIn& in) const { return {in.clip, in.world}; }
};
struct PsWorld {
    glm::vec4 operator()(const WorldVertex& in) const { return glm::vec4(in.world, 0.0f); }
};
struct PsSvPosition {
    glm::vec4 operator()(const WorldVertex& in) const { return in.position; }
};

// A triangle with very different w per vertex under a real projection (60°, square, near 0.1,
// far 100; the camera at the origin looking down −z, so world = view space). Its vertices are
// chosen on screen at whole pixels, so snapping to 16.8 changes nothing, and lifted to depth w.
struct PerspectiveTriangle {
    static constexpr int kSize = 64;
    glm::dmat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0), 1.0, 0.1, 100.0);
    glm::dvec2 screen[3] = {{40, 2}, {63, 62}, {36, 50}};
    double w[3] = {0.5, 20.0, 4.0};
    glm::dvec3 world[3];
    glm::dvec4 clip[3];

    PerspectiveTriangle() {
        for (int k = 0; k < 3; ++k) {
            const double nx = screen[k].x / kSize * 2 - 1, ny = 1 - screen[k].y / kSize * 2;
            world[k] = {nx * w[k] / proj[0][0], ny * w[k] / proj[1][1], -w[k]};
            clip[k] = proj * glm::dvec4(world[k], 1.0);
        }
    }
    std::vector<ClipWorldVertex> vertices() const {
        std::vector<ClipWorldVertex> v;
        for (int k = 0; k < 3; ++k) v.push_back({glm::vec4(clip[k]), glm::vec3(world[k])});
        return v;
    }
    // The point of the triangle's plane seen through pixel (i, j)'s centre.
    glm::dvec3 hit(int i, int j) const {
        const double nx = (i + 0.5) / kSize * 2 - 1, ny = 1 - (j + 0.5) / kSize * 2;
        const glm::dvec3 d(nx / proj[0][0], ny / proj[1][1], -1.0);
        const glm::dvec3 n = glm::cross(world[1] - world[0], world[2] - world[0]);
        return d * (glm::dot(n, world[0]) / glm::dot(n, d));
    }
    // Screen-space barycentrics of pixel (i, j)'s centre.
    glm::dvec3 screenBarycentrics(int i, int j) const {
        const glm::dvec2 p(i + 0.5, j + 0.5);
        auto cross2 = [](glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; };
        const double area = cross2(screen[1] - screen[0], screen[2] - screen[0]);
        return {cross2(screen[1] - p, screen[2] - p) / area, cross2(screen[2] - p, screen[0] - p) / area,
                cross2(screen[0] - p, screen[1] - p) / area};
    }
    double ndcZ(int k) const { return clip[k].z / clip[k].w; }
};

struct PerspectiveFixture : Fixture {
    PerspectiveTriangle tri;
    PerspectiveFixture() : Fixture(PerspectiveTriangle::kSize, PerspectiveTriangle::kSize, Format::R32G32B32A32_FLOAT) {
        color.clear(glm::vec4(-1000.0f));
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0},
                                         {"WORLD", 0, Format::R32G32B32_FLOAT, 0, 16}};
        setLayout(desc);
        setVertices(tri.vertices());
    }
    bool covered(int i, int j) const { return color.load(i, j).x != -1000.0f; }
};

TEST(PixelShader, InterpolationIsPerspectiveCorrect) {
    PerspectiveFixture f;
    for (int k = 0; k < 3; ++k) ASSERT_DOUBLE_EQ(f.tri.clip[k].w, f.tri.w[k]);
    f.ctx.draw(VsClipWorld{}, PsWorld{}, 3);
    int pixels = 0;
    double worstPerspective = 0, worstScreenLinear = 0;
    for (int j = 0; j < PerspectiveTriangle::kSize; ++j) {
        for (int i = 0; i < PerspectiveTriangle::kSize; ++i) {
            if (!f.covered(i, j)) continue;
            ++pixels;
            const glm::dvec3 exact = f.tri.hit(i, j);
            const glm::vec4 got = f.color.load(i, j);
            // World x and z (= −w) are linear in world space and bounded away from 0 here.
            const double relX = std::abs(got.x - exact.x) / std::abs(exact.x);
            const double relZ = std::abs(got.z - exact.z) / std::abs(exact.z);
            EXPECT_LE(relX, 1e-4) << "pixel " << i << "," << j << ": " << got.x << " vs " << exact.x;
            EXPECT_LE(relZ, 1e-4) << "pixel " << i << "," << j << ": " << got.z << " vs " << exact.z;
            worstPerspective = std::max({worstPerspective, relX, relZ});
            // What interpolating linearly in screen space would have given.
            const glm::dvec3 b = f.tri.screenBarycentrics(i, j);
            const double linearX = b.x * f.tri.world[0].x + b.y * f.tri.world[1].x + b.z * f.tri.world[2].x;
            worstScreenLinear = std::max(worstScreenLinear, std::abs(linearX - exact.x) / std::abs(exact.x));
        }
    }
    EXPECT_GT(pixels, 300);
    EXPECT_EQ(uint64_t(pixels), f.ctx.drawStatistics().psInvocations);
    // Screen-linear interpolation is wrong by far more than the tolerance (over 50 % somewhere).
    EXPECT_GT(worstScreenLinear, 0.5) << "the test triangle does not distinguish the two interpolations";
    EXPECT_LT(worstPerspective, 1e-4);
}

TEST(PixelShader, SvPositionIsPixelCentreDepthAndW) {
    PerspectiveFixture f;
    f.ctx.draw(VsClipWorld{}, PsSvPosition{}, 3);
    int pixels = 0;
    for (int j = 0; j < PerspectiveTriangle::kSize; ++j) {
        for (int i = 0; i < PerspectiveTriangle::kSize; ++i) {
            if (!f.covered(i, j)) {
                EXPECT_EQ(f.depth.load(i, j), 1.0f);
                continue;
            }
            ++pixels;
            const glm::vec4 p = f.color.load(i, j);
            EXPECT_EQ(p.x, float(i) + 0.5f);
            EXPECT_EQ(p.y, float(j) + 0.5f);
            EXPECT_EQ(p.z, f.depth.load(i, j)) << "z is the depth written, pixel " << i << "," << j;
            // Depth is linear in screen space.
            const glm::dvec3 b = f.tri.screenBarycentrics(i, j);
            const double z = b.x * f.tri.ndcZ(0) + b.y * f.tri.ndcZ(1) + b.z * f.tri.ndcZ(2);
            EXPECT_NEAR(p.z, z, 1e-6) << i << "," << j;
            // w is the view depth of the point seen, −z_view.
            const double w = -f.tri.hit(i, j).z;
            EXPECT_LE(std::abs(p.w - w) / w, 1e-4) << i << "," << j << ": " << p.w << " vs " << w;
        }
    }
    EXPECT_GT(pixels, 300);
}

// ---- Discard -------------------------------------------------------------------------------------------

struct PsCheckerDiscard {
    std::optional<glm::vec4> operator()(const PositionOnly& in) const {
        const int x = int(in.position.x), y = int(in.position.y);
        if ((x + y) % 2 == 1) return std::nullopt;
        return kWhite;
    }
};

TEST(PixelShader, DiscardKeepsColourAndDepth) {
    Fixture f(16, 16);
    f.drawQuad(PsCheckerDiscard{}, 0, 0, 16, 16, 0.5f);
    const PipelineStatistics s = f.ctx.drawStatistics();
    EXPECT_EQ(s.psInvocations, 256u);
    EXPECT_EQ(s.fragmentsDiscarded, 128u);
    for (uint32_t y = 0; y < 16; ++y) {
        for (uint32_t x = 0; x < 16; ++x) {
            const bool kept = (x + y) % 2 == 0;
            EXPECT_EQ(f.color.load(x, y), kept ? kWhite : f.color.load(0, 1)) << x << "," << y;
            EXPECT_EQ(f.depth.load(x, y), kept ? 0.5f : 1.0f) << x << "," << y;
        }
    }
    EXPECT_NE(f.color.load(0, 1), kWhite);
    // A quad behind then fills exactly the discarded pixels: their depth was never written.
    const glm::vec4 red(1, 0, 0, 1);
    f.drawQuad(PsConstant{red}, 0, 0, 16, 16, 0.7f);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 128u);
    EXPECT_EQ(f.ctx.drawStatistics().fragmentsEarlyDepthKilled, 128u);
    for (uint32_t y = 0; y < 16; ++y)
        for (uint32_t x = 0; x < 16; ++x) EXPECT_EQ(f.color.load(x, y), (x + y) % 2 ? red : kWhite) << x << "," << y;
}

// ---- Multiple render targets --------------------------------------------------------------------------

struct PsTwoTargets {
    std::array<glm::vec4, 2> operator()(const PositionOnly& in) const {
        return {glm::vec4(1, 0, 0, 1), glm::vec4(in.position.x, in.position.y, in.position.z, 2.0f)};
    }
};

TEST(PixelShader, MultipleRenderTargetsGetTheirOwnColour) {
    Fixture f(8, 8);
    RenderTarget second(8, 8, Format::R32G32B32A32_FLOAT);
    second.clear(glm::vec4(-1.0f));
    RenderTarget* const targets[] = {&f.color, &second};
    f.ctx.setRenderTargets(targets, &f.depth);
    f.drawQuad(PsTwoTargets{}, 2, 0, 8, 8, 0.25f);
    for (uint32_t y = 0; y < 8; ++y) {
        for (uint32_t x = 0; x < 8; ++x) {
            if (x < 2) {
                EXPECT_EQ(second.load(x, y), glm::vec4(-1.0f));
                EXPECT_NE(f.color.load(x, y), glm::vec4(1, 0, 0, 1));
                continue;
            }
            EXPECT_EQ(f.color.load(x, y), glm::vec4(1, 0, 0, 1)) << x << "," << y;
            EXPECT_EQ(second.load(x, y), glm::vec4(float(x) + 0.5f, float(y) + 0.5f, 0.25f, 2.0f)) << x << "," << y;
        }
    }
    // A write mask per target with independent blending.
    BlendState masks;
    masks.independentBlendEnable = true;
    masks.renderTarget[1].renderTargetWriteMask = 0x8;  // alpha only
    f.ctx.setBlendState(masks);
    second.clear(glm::vec4(-1.0f));
    f.depth.clear(1.0f);
    f.drawQuad(PsTwoTargets{}, 0, 0, 8, 8, 0.25f);
    EXPECT_EQ(second.load(5, 5), glm::vec4(-1, -1, -1, 2));
    EXPECT_EQ(f.color.load(0, 0), glm::vec4(1, 0, 0, 1));
}

// ---- Derivatives -----------------------------------------------------------------------------------------

struct UvIn {
    glm::vec3 position;
    glm::vec2 uv;
    RASTER_INPUT_SIGNATURE(UvIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(uv, "TEXCOORD", 0))
};
struct UvVertexData {
    glm::vec3 position;
    glm::vec2 uv;
};
struct UvVertex {
    glm::vec4 position;
    glm::vec2 uv;
};
struct VsUv {
    UvVertex operator()(const UvIn& in) const { return {glm::vec4(in.position, 1.0f), in.uv}; }
};
struct PsDerivatives {
    glm::vec4 operator()(const UvVertex& in) const { return glm::vec4(ddx(in.uv), ddy(in.uv)); }
};
struct PsUvPlain {
    glm::vec4 operator()(const UvVertex& in) const { return glm::vec4(in.uv, 0.0f, 1.0f); }
};
struct PsSample {
    const Texture2D* texture = nullptr;
    SamplerState sampler;
    glm::vec4 operator()(const UvVertex& in) const { return texture->Sample(sampler, in.uv); }
};

// A full-target quad whose uv is the pixel position times `scale`.
struct UvFixture : Fixture {
    UvFixture(uint32_t size, float scale) : Fixture(size, size, Format::R32G32B32A32_FLOAT) {
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                         {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, 12}};
        setLayout(desc);
        ctx.setDepthStencilState(DepthStencilState::disabled());  // the tests draw the same plane again
        const float s = float(size);
        const std::vector<glm::vec3> p = quad(0, 0, s, s, s, s, 0.5f);
        std::vector<UvVertexData> v;
        for (const glm::vec3& q : p) {
            const glm::vec2 pixel((q.x + 1.0f) / 2.0f * s, (1.0f - q.y) / 2.0f * s);
            v.push_back({q, pixel * scale});
        }
        setVertices(v);
    }
    template <class PS>
    void draw(const PS& ps) {
        ctx.draw(VsUv{}, ps, 6);
    }
};

TEST(PixelShader, DdxDdyOfScreenLinearUv) {
    UvFixture f(32, 1.0f / 8.0f);
    f.draw(PsDerivatives{});
    for (uint32_t y = 0; y < 32; ++y) {
        for (uint32_t x = 0; x < 32; ++x) {
            const glm::vec4 g = f.color.load(x, y);
            EXPECT_NEAR(g.x, 0.125f, 1e-6f) << x << "," << y;  // du/dx
            EXPECT_NEAR(g.y, 0.0f, 1e-6f) << x << "," << y;    // dv/dx
            EXPECT_NEAR(g.z, 0.0f, 1e-6f) << x << "," << y;    // du/dy
            EXPECT_NEAR(g.w, 0.125f, 1e-6f) << x << "," << y;  // dv/dy
        }
    }
    const PipelineStatistics s = f.ctx.drawStatistics();
    EXPECT_EQ(s.psInvocations, 32u * 32u);
    EXPECT_GT(s.derivativeReplays, 0u);
    EXPECT_GT(s.helperInvocations, 0u) << "quads on the diagonal are half covered by each triangle";

    f.draw(PsUvPlain{});
    EXPECT_EQ(f.ctx.drawStatistics().derivativeReplays, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().helperInvocations, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 32u * 32u);
    EXPECT_NEAR(f.color.load(9, 3).x, 9.5f / 8.0f, 1e-6f);
}

// 64×64 float texture with a mip chain whose levels tell themselves apart: R is a 1-texel checker,
// G a 2-texel one, B a 4-texel one. Box filtering turns a checker into 0.5 once a texel covers a
// whole period, so level 0 has R in {0, 1}; level 1 R = 0.5 and G in {0, 1}; level 2 R = G = 0.5 and
// B in {0, 1} (B = (X + Y) & 1 at level 2's texel (X, Y)); level 3 and above are all 0.5.
Texture2D levelCheckerTexture() {
    std::vector<float> rgba;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            rgba.insert(rgba.end(), {float((x + y) & 1), float((x / 2 + y / 2) & 1), float((x / 4 + y / 4) & 1), 1.0f});
    return Texture2D::fromRgba32f(64, 64, rgba, true);
}

int levelOf(const glm::vec4& c) {
    if (c.r != 0.5f) return 0;
    if (c.g != 0.5f) return 1;
    if (c.b != 0.5f) return 2;
    return 3;
}

TEST(PixelShader, SampleSelectsTheMipLevelFromDerivatives) {
    const Texture2D texture = levelCheckerTexture();
    ASSERT_EQ(texture.mipLevels(), 7u);
    ASSERT_EQ(texture.load(0, 0, 1), glm::vec4(0.5f, 0.0f, 0.0f, 1.0f));
    const PsSample ps{&texture, SamplerState::point(AddressMode::Wrap)};
    // texelsPerPixel → level: 1 → 0, 2 → 1, 4 → 2, 8 → 3.
    for (int level = 0; level <= 3; ++level) {
        const float texelsPerPixel = float(1 << level);
        UvFixture f(32, texelsPerPixel / 64.0f);
        f.draw(ps);
        for (uint32_t y = 0; y < 32; ++y)
            for (uint32_t x = 0; x < 32; ++x)
                ASSERT_EQ(levelOf(f.color.load(x, y)), level) << "pixel " << x << "," << y << " at " << texelsPerPixel
                                                              << " texels per pixel";
        EXPECT_GT(f.ctx.drawStatistics().derivativeReplays, 0u);
        if (level == 2) {
            // Pixel i reads level 2's texel i mod 16 (uv·16 = i + 0.5).
            for (uint32_t y = 0; y < 32; ++y)
                for (uint32_t x = 0; x < 32; ++x) EXPECT_EQ(f.color.load(x, y).b, float((x + y) & 1)) << x << "," << y;
        }
    }
}

TEST(PixelShader, TrilinearBlendsLevelsPointMipPicksTheNearest) {
    // 3 texels per pixel: λ = log2 3 ≈ 1.585. Point mip filter: level round(λ) = 2. Linear: level 1
    // and level 2 blended with weight frac(λ) = 0.585, so G = G1 + (0.5 − G1)·0.585 with G1 in {0, 1}:
    // |G − 0.5| = 0.5·(1 − 0.585).
    const Texture2D texture = levelCheckerTexture();
    const float lambda = std::log2(3.0f);
    SamplerState pointMip = SamplerState::point(AddressMode::Wrap);
    SamplerState linearMip = pointMip;
    linearMip.mipFilter = Filter::Linear;

    UvFixture p(32, 3.0f / 64.0f);
    p.draw(PsSample{&texture, pointMip});
    UvFixture l(32, 3.0f / 64.0f);
    l.draw(PsSample{&texture, linearMip});
    const float expected = 0.5f * (1.0f - (lambda - 1.0f));
    for (uint32_t y = 0; y < 32; ++y) {
        for (uint32_t x = 0; x < 32; ++x) {
            ASSERT_EQ(levelOf(p.color.load(x, y)), 2) << x << "," << y;
            const glm::vec4 c = l.color.load(x, y);
            EXPECT_EQ(c.r, 0.5f);
            EXPECT_NEAR(std::abs(c.g - 0.5f), expected, 1e-3f) << x << "," << y;
        }
    }
}

TEST(PixelShader, HelpersAndReplaysOnlyWhenDerivativesAreAsked) {
    // One level and one filter: Sample takes no derivative.
    std::vector<float> rgba(16 * 16 * 4, 0.5f);
    const Texture2D flat = Texture2D::fromRgba32f(16, 16, rgba);
    const Texture2D mipped = Texture2D::fromRgba32f(16, 16, rgba, true);
    UvFixture f(32, 1.0f / 32.0f);
    f.draw(PsSample{&flat, SamplerState::bilinear()});
    EXPECT_EQ(f.ctx.drawStatistics().derivativeReplays, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().helperInvocations, 0u);
    f.draw(PsSample{&mipped, SamplerState::bilinear()});
    EXPECT_GT(f.ctx.drawStatistics().derivativeReplays, 0u);
    EXPECT_GT(f.ctx.drawStatistics().helperInvocations, 0u);
    f.drawQuad(PsConstant{kWhite}, 0, 0, 32, 32, 0.5f);
    EXPECT_EQ(f.ctx.drawStatistics().derivativeReplays, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().helperInvocations, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 32u * 32u);
}

// ---- Early depth and blend no-ops ------------------------------------------------------------------

TEST(PixelShader, OccludedFragmentsNeverRunTheShader) {
    Fixture f(16, 16);
    f.drawQuad(PsConstant{kWhite}, 0, 0, 16, 16, 0.3f);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 256u);
    const RenderTarget before = f.color;
    f.drawQuad(PsConstant{glm::vec4(1, 0, 0, 1)}, 4, 4, 12, 12, 0.6f);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 0u);
    // The tile's farthest depth (0.3) is nearer than the quad's nearest (0.6): both triangles are
    // skipped whole in the (only) tile, before any fragment is made.
    EXPECT_EQ(f.ctx.drawStatistics().tilesOccluded, 2u);
    EXPECT_EQ(f.ctx.drawStatistics().fragmentsEarlyDepthKilled, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().helperInvocations, 0u);
    EXPECT_TRUE(f.color == before);
    // At the tile's farthest depth exactly, LessEqual passes: no tile is skipped (a triangle's
    // nearest depth carries a 2^-20 margin, so equality is never skipped under Less either).
    f.ctx.setDepthStencilState({true, false, ComparisonFunc::LessEqual});
    f.drawQuad(PsConstant{glm::vec4(0, 1, 0, 1)}, 4, 4, 12, 12, 0.3f);
    EXPECT_EQ(f.ctx.drawStatistics().tilesOccluded, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 64u);
    EXPECT_EQ(f.color.load(4, 4), glm::vec4(0, 1, 0, 1));
    f.ctx.setDepthStencilState({true, true, ComparisonFunc::Less});
    // In front, it runs and is not killed.
    f.drawQuad(PsConstant{glm::vec4(1, 0, 0, 1)}, 4, 4, 12, 12, 0.2f);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 64u);
    EXPECT_EQ(f.ctx.drawStatistics().fragmentsEarlyDepthKilled, 0u);
    EXPECT_EQ(f.color.load(4, 4), glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(f.color.load(3, 4), kWhite);
}

// Where the tile is only partly in front, the test is made per fragment, and the image is the
// reference pipeline's (which never skips a tile).
TEST(PixelShader, PartlyOccludedTilesAreTestedPerFragment) {
    for (const bool reference : {false, true}) {
        Fixture f(16, 16, Format::R8G8B8A8_UNORM, ContextOptions{1, reference});
        f.drawQuad(PsConstant{kWhite}, 0, 0, 8, 16, 0.3f);  // the left half only: the tile's far depth stays 1
        f.drawQuad(PsConstant{glm::vec4(1, 0, 0, 1)}, 4, 4, 12, 12, 0.6f);
        EXPECT_EQ(f.ctx.drawStatistics().tilesOccluded, 0u) << reference;
        EXPECT_EQ(f.ctx.drawStatistics().fragmentsEarlyDepthKilled + f.ctx.drawStatistics().fragmentsLateDepthKilled,
                  32u)
            << reference;
        EXPECT_EQ(f.ctx.drawStatistics().psInvocations, reference ? 64u : 32u);
        EXPECT_EQ(f.color.load(5, 5), kWhite) << reference;
        EXPECT_EQ(f.color.load(9, 5), glm::vec4(1, 0, 0, 1)) << reference;
    }
}

TEST(PixelShader, ZeroAlphaAdditiveFragmentsAreBlendNoOps) {
    Fixture f(16, 16);
    f.color.clear({0.2f, 0.4f, 0.6f, 0.8f});
    f.ctx.setBlendState(BlendState::additive());
    f.ctx.setDepthStencilState(DepthStencilState::readOnly());
    const RenderTarget before = f.color;
    for (const float alpha : {0.0f, -1.0f, -0.0f}) {
        f.drawQuad(PsConstant{glm::vec4(1, 1, 1, alpha)}, 0, 0, 16, 16, 0.5f);
        EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 256u) << alpha;
        EXPECT_EQ(f.ctx.drawStatistics().fragmentsBlendNoOp, 256u) << alpha;
        EXPECT_TRUE(f.color == before) << alpha;
    }
    // A visible alpha is not a no-op: red 51/255 + 1·0.25 = 0.45 → byte 114.75 → 115.
    f.drawQuad(PsConstant{glm::vec4(1, 1, 1, 0.25f)}, 0, 0, 8, 16, 0.5f);
    EXPECT_EQ(f.ctx.drawStatistics().fragmentsBlendNoOp, 0u);
    EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 8u * 16u);
    EXPECT_EQ(f.color.rgba8()[0], 115);
    EXPECT_EQ(f.color.rgba8()[4 * 8], before.rgba8()[4 * 8]);
}


// The eight-wide depth and barycentrics convert edge functions with a bit trick; they must give
// the scalar code's bits for any edge value up to the documented bound, negative ones included.
TEST(PixelShaderWide, DepthAndBarycentricsAreTheScalarBits) {
    std::mt19937_64 rng(7);
    const int64_t kBound = int64_t(1) << 50;
    std::uniform_int_distribution<int64_t> any(-kBound, kBound);
    std::uniform_int_distribution<int64_t> small(-1000, 1000);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int trial = 0; trial < 2000; ++trial) {
        TriangleSetup t{};
        t.area2 = 1 + (trial % 3 == 0 ? small(rng) * small(rng) * 1000 + 2000000 : (any(rng) >> 3) | 1);
        if (t.area2 < 0) t.area2 = -t.area2;
        t.invArea2 = 1.0 / double(t.area2);
        for (int k = 0; k < 3; ++k) t.z[k] = unit(rng), t.invW[k] = 0.5f + unit(rng);
        int64_t e[3][8];
        for (auto& edge : e)
            for (int64_t& v : edge) v = trial % 2 ? any(rng) : small(rng);
        const float lo = trial % 5 == 0 ? 0.25f : 0.0f, hi = trial % 7 == 0 ? 0.75f : 1.0f;
        const Float8 z = interpolateDepthWide(t, e, lo, hi);
        const TriangleInterpolant<float> ti(t);
        Float8 b[3];
        barycentricsWide(ti, e, b);
        for (int l = 0; l < 8; ++l) {
            const float expect = interpolateDepth<float>(t, e[0][l], e[1][l], e[2][l], lo, hi);
            ASSERT_EQ(std::bit_cast<uint32_t>(z[l]), std::bit_cast<uint32_t>(expect)) << "trial " << trial << " lane " << l;
            const Barycentrics<float> scalar = barycentrics(ti, e[0][l], e[1][l], e[2][l]);
            for (int k = 0; k < 3; ++k)
                ASSERT_EQ(std::bit_cast<uint32_t>(b[k][l]), std::bit_cast<uint32_t>(scalar.b[k]))
                    << "trial " << trial << " lane " << l << " weight " << k;
        }
    }
}

// A triangle of one depth takes interpolateDepth's shortcut; inside the triangle (every edge
// function >= 0, summing to area2) the formula gives the same bits, for depths of any size and sign
// and for clamped ones, at the edge-function sizes of the documented bound.
TEST(PixelShaderWide, FlatDepthIsTheFormulasBitsInsideTheTriangle) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const float depths[] = {1.0f, 0.5f, 0.999999940f, 1e-30f, 1e-44f, -0.25f, 3e38f, 0.1f, 1.5f};
    int checked = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        TriangleSetup t{};
        const int64_t bits = 8 + trial % 43;  // area2 from 2^8 to 2^50
        t.area2 = (int64_t(1) << bits) + int64_t(unit(rng) * double(int64_t(1) << (bits - 1)));
        t.invArea2 = 1.0 / double(t.area2);
        const float z = trial % 3 == 0 ? float(unit(rng)) : depths[trial % std::size(depths)];
        for (int k = 0; k < 3; ++k) t.z[k] = z;
        const float lo = trial % 5 == 0 ? 0.25f : 0.0f, hi = trial % 7 == 0 ? 0.75f : 1.0f;
        int64_t e[3][8];
        for (int l = 0; l < 8; ++l) {
            // A point inside: e0 + e1 + e2 = area2, each >= 0; now and then on a vertex or an edge.
            const int64_t a = l == 0 ? 0 : int64_t(unit(rng) * double(t.area2));
            const int64_t b = l == 1 ? t.area2 - a : int64_t(unit(rng) * double(t.area2 - a));
            e[0][l] = a, e[1][l] = b, e[2][l] = t.area2 - a - b;
        }
        t.flatDepth = false;
        const Float8 formula = interpolateDepthWide(t, e, lo, hi);
        t.flatDepth = true;
        const Float8 flat = interpolateDepthWide(t, e, lo, hi);
        for (int l = 0; l < 8; ++l) {
            ASSERT_EQ(std::bit_cast<uint32_t>(flat[l]), std::bit_cast<uint32_t>(formula[l]))
                << "trial " << trial << " z " << z << " lane " << l;
            ASSERT_EQ(std::bit_cast<uint32_t>(interpolateDepth<float>(t, e[0][l], e[1][l], e[2][l], lo, hi)),
                      std::bit_cast<uint32_t>(formula[l]));
            ++checked;
        }
    }
    EXPECT_EQ(checked, 32000);
}

// setupTriangle marks a triangle flat only for three identical finite non-zero depths.
TEST(PixelShaderWide, SetupMarksFlatDepthOnlyForOneFiniteNonZeroDepth) {
    const auto flat = [](float z0, float z1, float z2) {
        const ScreenVertex s[3] = {{0, 0, z0, 1}, {2560, 0, z1, 1}, {0, 2560, z2, 1}};
        const uint32_t idx[3] = {0, 1, 2};
        RasterizerState rs;
        rs.cullMode = CullMode::None;
        TriangleSetup t;
        EXPECT_EQ(setupTriangle(s, idx, 0, rs, PixelRect{0, 0, 63, 63}, t), SetupResult::Ok);
        return t.flatDepth;
    };
    EXPECT_TRUE(flat(1, 1, 1));
    EXPECT_TRUE(flat(0.3f, 0.3f, 0.3f));
    EXPECT_FALSE(flat(0.3f, 0.3f, std::nextafter(0.3f, 1.0f)));
    EXPECT_FALSE(flat(0.0f, 0.0f, 0.0f)) << "zero: the formula's sign of zero depends on the lane";
    EXPECT_FALSE(flat(0.0f, -0.0f, 0.0f));
    EXPECT_FALSE(flat(std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                      std::numeric_limits<float>::infinity()));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(flat(nan, nan, nan));
}

// ---- Deferred shading of opaque draws ---------------------------------------------------------------

struct ColorIn {
    glm::vec3 position;
    glm::vec4 color;
    RASTER_INPUT_SIGNATURE(ColorIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0))
};
template <class T>
struct ColorVertexT {
    glm::vec<4, T> position;
    glm::vec<4, T> color;
};
struct VsColor {
    ColorVertexT<float> operator()(const ColorIn& in) const { return {glm::vec4(in.position, 1.0f), in.color}; }
};
// Eight wide (written over its scalar type), so opaque draws of it may be shaded deferred.
struct PsVertexColor {
    using Input = ColorVertexT<float>;
    template <class T>
    glm::vec<4, T> operator()(const ColorVertexT<T>& in) const {
        return {in.color.x, in.color.y, in.color.z * (T(1.0f) - in.position.z), in.color.w};
    }
};
static_assert(WidePixelShader<PsVertexColor>);
static_assert(PairPixelShader<PsVertexColor>);
// The same shader for float and Float8 only: the pipeline shades its triangles one 4×2 block per call.
using PsVertexColorEightOnly = EightOnly<PsVertexColor>;
static_assert(WidePixelShader<PsVertexColorEightOnly> && !PairPixelShader<PsVertexColorEightOnly>);
// Colour from the pixel's position, so that any two blocks differ: a pair call that mixed up its
// halves, or shaded a block at its neighbour's place, shows.
struct PsPosition {
    using Input = ColorVertexT<float>;
    template <class T>
    glm::vec<4, T> operator()(const ColorVertexT<T>& in) const {
        return {in.position.x * T(1.0f / 160.0f), in.position.y * T(1.0f / 70.0f), in.color.z * in.position.z, T(1.0f)};
    }
};
using PsPositionEightOnly = EightOnly<PsPosition>;
static_assert(PairPixelShader<PsPosition> && !PairPixelShader<PsPositionEightOnly>);

struct ColorFixture : Fixture {
    std::vector<ColorIn> vertices;
    ColorFixture(uint32_t w, uint32_t h) : Fixture(w, h) {
        const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                         {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, 12}};
        setLayout(desc);
    }
    void addQuad(float x0, float y0, float x1, float y1, float z, glm::vec4 c) {
        for (const glm::vec3& p : quad(x0, y0, x1, y1, float(width), float(height), z)) vertices.push_back({p, c});
    }
    // Draws vertices [first, first + count) in one draw.
    template <class PS = PsVertexColor>
    void drawRange(size_t first, size_t count, const PS& ps = {}) {
        const std::vector<ColorIn> part(vertices.begin() + long(first), vertices.begin() + long(first + count));
        setVertices(part);
        ctx.draw(VsColor{}, ps, uint32_t(count));
    }
};

TEST(DeferredShading, OverdrawInOneOpaqueDrawIsNeverShaded) {
    // Four full-target quads drawn back to front: every fragment passes the depth test, and only
    // the nearest quad's are shaded; the image is the one four separate draws give.
    ColorFixture one(32, 32), apart(32, 32);
    for (ColorFixture* f : {&one, &apart}) {
        for (int q = 0; q < 4; ++q)
            f->addQuad(0, 0, 32, 32, 0.8f - 0.2f * float(q), glm::vec4(0.25f * float(q), 0.5f, 1.0f, 1.0f));
        f->ctx.setDepthStencilState({true, true, ComparisonFunc::Less});
    }
    one.drawRange(0, 24);
    const PipelineStatistics s = one.ctx.drawStatistics();
    EXPECT_EQ(s.psInvocations, 32u * 32u);
    EXPECT_EQ(s.fragmentsOverdrawSkipped, 3u * 32u * 32u);
    EXPECT_EQ(s.fragmentsEarlyDepthKilled, 0u);
    uint64_t shaded_apart = 0;
    for (int q = 0; q < 4; ++q) {
        apart.drawRange(size_t(6 * q), 6);
        shaded_apart += apart.ctx.drawStatistics().psInvocations;
        EXPECT_EQ(apart.ctx.drawStatistics().fragmentsOverdrawSkipped, 0u);
    }
    EXPECT_EQ(shaded_apart, 4u * 32u * 32u);
    EXPECT_TRUE(one.color == apart.color);
    EXPECT_TRUE(one.depth == apart.depth);
    const glm::vec4 c = one.color.load(5, 7);
    EXPECT_NEAR(c.x, 0.75f, 1.0f / 255.0f);
    EXPECT_NEAR(c.z, 1.0f - 0.2f, 1.0f / 255.0f);
}

TEST(DeferredShading, EqualDepthsKeepTheDepthFunctionsOrder) {
    // Two coplanar quads, red then green: under Less the first stays (the second fails), under
    // LessEqual the second replaces it, exactly as in order.
    for (const ComparisonFunc func : {ComparisonFunc::Less, ComparisonFunc::LessEqual}) {
        ColorFixture f(16, 16);
        f.addQuad(0, 0, 16, 16, 0.5f, glm::vec4(1, 0, 0, 1));
        f.addQuad(0, 0, 16, 16, 0.5f, glm::vec4(0, 1, 0, 1));
        f.ctx.setDepthStencilState({true, true, func});
        f.drawRange(0, 12);
        const bool less = func == ComparisonFunc::Less;
        EXPECT_EQ(f.color.load(3, 3), less ? glm::vec4(1, 0, 0, 1) : glm::vec4(0, 1, 0, 1));
        const PipelineStatistics s = f.ctx.drawStatistics();
        EXPECT_EQ(s.psInvocations, 256u);
        EXPECT_EQ(s.fragmentsEarlyDepthKilled, less ? 256u : 0u);
        EXPECT_EQ(s.fragmentsOverdrawSkipped, less ? 0u : 256u);
    }
}

TEST(DeferredShading, RandomTrianglesGiveTheInOrderImage) {
    // Sixty random overlapping triangles at random depths, in one draw and one per draw (a draw of
    // one triangle is shaded in order), on targets whose size is not a multiple of the tile; at
    // 150 pixels the last tile column is not a multiple of 4 wide and is shaded in order.
    for (const uint32_t width : {160u, 150u}) {
        ColorFixture one(width, 70), apart(width, 70);
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> coord(-1.2f, 1.2f), depth(0.0f, 1.0f), unit(0.0f, 1.0f);
        for (int i = 0; i < 60; ++i) {
            const glm::vec4 c(unit(rng), unit(rng), unit(rng), 1.0f);
            for (int k = 0; k < 3; ++k) {
                const ColorIn v{{coord(rng), coord(rng), depth(rng)}, c};
                one.vertices.push_back(v);
                apart.vertices.push_back(v);
            }
        }
        for (ColorFixture* f : {&one, &apart}) f->ctx.setDepthStencilState({true, true, ComparisonFunc::Less});
        one.drawRange(0, one.vertices.size());
        const PipelineStatistics s = one.ctx.drawStatistics();
        EXPECT_GT(s.fragmentsOverdrawSkipped, 0u) << width;
        uint64_t shaded_apart = 0;
        for (size_t i = 0; i < apart.vertices.size(); i += 3) {
            apart.drawRange(i, 3);
            shaded_apart += apart.ctx.drawStatistics().psInvocations;
        }
        EXPECT_TRUE(one.color == apart.color) << width;
        EXPECT_TRUE(one.depth == apart.depth) << width;
        // Deferred, each pixel is shaded at most once: exactly the pixels some fragment reached
        // (under Less from a cleared 1.0, those whose depth changed).
        uint64_t reached = 0;
        for (uint32_t y = 0; y < 70; ++y)
            for (uint32_t x = 0; x < width; ++x) reached += one.depth.load(x, y) != 1.0f ? 1 : 0;
        if (width % 4 == 0) {
            EXPECT_EQ(s.psInvocations, reached);
        }
        EXPECT_GE(s.psInvocations, reached);
        EXPECT_GT(shaded_apart, s.psInvocations) << width;

        // Neighbouring blocks of one triangle are shaded two per call (Float8x2) in both the deferred
        // pass and in-order draws of one triangle; one block per call must give the same image and
        // the same counts, helper lanes included.
        ColorFixture one2(width, 70), one8(width, 70), apart2(width, 70), apart8(width, 70);
        for (ColorFixture* f : {&one2, &one8, &apart2, &apart8}) {
            f->vertices = one.vertices;
            f->ctx.setDepthStencilState({true, true, ComparisonFunc::Less});
        }
        one2.drawRange(0, one2.vertices.size(), PsPosition{});
        one8.drawRange(0, one8.vertices.size(), PsPositionEightOnly{});
        const PipelineStatistics s2 = one2.ctx.drawStatistics(), s8 = one8.ctx.drawStatistics();
        EXPECT_TRUE(one2.color == one8.color) << width;
        EXPECT_EQ(s2.psInvocations, s8.psInvocations) << width;
        EXPECT_EQ(s2.helperInvocations, s8.helperInvocations) << width;
        EXPECT_EQ(s2.fragmentsOverdrawSkipped, s8.fragmentsOverdrawSkipped) << width;
        EXPECT_EQ(s2.fragmentsEarlyDepthKilled, s8.fragmentsEarlyDepthKilled) << width;
        uint64_t shaded_pairs = 0, shaded_apart8 = 0, helpers_pairs = 0, helpers_apart8 = 0;
        for (size_t i = 0; i < apart8.vertices.size(); i += 3) {
            apart2.drawRange(i, 3, PsPosition{});
            shaded_pairs += apart2.ctx.drawStatistics().psInvocations;
            helpers_pairs += apart2.ctx.drawStatistics().helperInvocations;
            apart8.drawRange(i, 3, PsPositionEightOnly{});
            shaded_apart8 += apart8.ctx.drawStatistics().psInvocations;
            helpers_apart8 += apart8.ctx.drawStatistics().helperInvocations;
        }
        EXPECT_TRUE(apart2.color == apart8.color) << width;
        EXPECT_TRUE(apart2.color == one2.color) << width;
        EXPECT_EQ(shaded_pairs, shaded_apart) << width;
        EXPECT_EQ(shaded_apart8, shaded_apart) << width;
        EXPECT_EQ(helpers_pairs, helpers_apart8) << width;
        EXPECT_GT(helpers_pairs, 0u) << width;
    }
}

TEST(DeferredShading, NotTakenWhenBlendingOrWithoutDepthWrites) {
    for (const bool blend : {true, false}) {
        ColorFixture f(16, 16);
        f.addQuad(0, 0, 16, 16, 0.6f, glm::vec4(0.2f, 0, 0, 1));
        f.addQuad(0, 0, 16, 16, 0.4f, glm::vec4(0.2f, 0, 0, 1));
        if (blend) {
            f.ctx.setBlendState(BlendState::additive());
            f.ctx.setDepthStencilState({true, true, ComparisonFunc::Less});
        } else {
            f.ctx.setDepthStencilState(DepthStencilState::readOnly(ComparisonFunc::Less));
        }
        f.drawRange(0, 12);
        EXPECT_EQ(f.ctx.drawStatistics().psInvocations, 512u) << (blend ? "additive" : "no depth write");
        EXPECT_EQ(f.ctx.drawStatistics().fragmentsOverdrawSkipped, 0u);
    }
}

}  // namespace
}  // namespace raster
