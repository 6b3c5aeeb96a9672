// The eight-wide path (simd.hpp) and the billboard rectangles must give the same bits as the
// scalar path they shortcut.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/scenes.hpp"
#include "lecture/fire_shaders.hpp"
#include "raster/fastpath/transparency.hpp"
#include "raster/pipeline_impl.hpp"
#include "raster/shaders/billboard.hpp"
#include "raster/simd.hpp"
#include "raster/texture.hpp"

#include "eight_only.hpp"

namespace raster {
namespace {

// The lecture's psFire, but only for float: the pipeline must take the scalar path.
struct PsFireScalarOnly {
    shaders::PsFire inner;
    glm::vec4 operator()(const shaders::BillboardCorner& in) const { return inner(in); }
};

// psFire for float and Float8 only: the pipeline shades its rectangles one 4×2 block per call.
using PsFireEightOnly = EightOnly<shaders::PsFire>;

static_assert(WidePixelShader<shaders::PsFire>);
static_assert(PairPixelShader<shaders::PsFire>);
static_assert(!WidePixelShader<PsFireScalarOnly>);
static_assert(WidePixelShader<PsFireEightOnly> && !PairPixelShader<PsFireEightOnly>);
static_assert(sizeof(Wide<shaders::BillboardCorner>) == 6 * sizeof(Float8));
static_assert(sizeof(WidePair<shaders::BillboardCorner>) == 6 * sizeof(Float8x2));

Texture2D checker(bool mipmaps) {
    std::vector<uint8_t> texels(16 * 8 * 4);
    std::mt19937 rng(7);
    for (auto& t : texels) t = uint8_t(rng());
    return Texture2D::fromRgba8(16, 8, texels, mipmaps);
}

TEST(Float8, LaneOperationsMatchScalar) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> d(-100.0f, 100.0f);
    for (int round = 0; round < 100; ++round) {
        Float8 a, b;
        for (int i = 0; i < 8; ++i) a.set(i, d(rng)), b.set(i, d(rng));
        const Float8 s = a + b * a - b / a;
        const Int8 t = toInt(a);
        const uint32_t lt = (a < b).bits();
        for (int i = 0; i < 8; ++i) {
            EXPECT_EQ(s[i], a[i] + b[i] * a[i] - b[i] / a[i]);
            EXPECT_EQ(t[i], int(a[i]));
            EXPECT_EQ((lt >> i) & 1u, uint32_t(a[i] < b[i]));
        }
    }
    EXPECT_EQ(Mask8::fromBits(0xA5).bits(), 0xA5u);
}

TEST(Float8, WideSampleEqualsScalarSampleBitForBit) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> d(-0.7f, 1.7f);
    const Texture2D flat = checker(false), mipped = checker(true);
    const AddressMode modes[] = {AddressMode::Clamp, AddressMode::Wrap, AddressMode::Mirror, AddressMode::Border,
                                 AddressMode::MirrorOnce};
    for (const Texture2D* tex : {&flat, &mipped}) {
        for (AddressMode mode : modes) {
            for (Filter filter : {Filter::Point, Filter::Linear}) {
                SamplerState s = SamplerState::bilinear(mode);
                s.minFilter = s.magFilter = filter;
                s.borderColor = {0.25f, 0.5f, 0.75f, 1.0f};
                for (int round = 0; round < 50; ++round) {
                    glm::vec<2, Float8> uv;
                    for (int i = 0; i < 8; ++i) uv.x.set(i, d(rng)), uv.y.set(i, d(rng));
                    const glm::vec<4, Float8> wide = tex->Sample(s, uv);
                    // Two blocks in one call: each half the bits of its own block's call.
                    glm::vec<2, Float8> uv2;
                    for (int i = 0; i < 8; ++i) uv2.x.set(i, d(rng)), uv2.y.set(i, d(rng));
                    const glm::vec<4, Float8> wide2 = tex->Sample(s, uv2);
                    const glm::vec<4, Float8x2> pair =
                        tex->Sample(s, glm::vec<2, Float8x2>(Float8x2(uv.x, uv2.x), Float8x2(uv.y, uv2.y)));
                    for (int c = 0; c < 4; ++c)
                        for (int i = 0; i < 8; ++i) {
                            ASSERT_EQ(std::bit_cast<uint32_t>(pair[c][i]), std::bit_cast<uint32_t>(wide[c][i]));
                            ASSERT_EQ(std::bit_cast<uint32_t>(pair[c][8 + i]), std::bit_cast<uint32_t>(wide2[c][i]));
                        }
                    for (int i = 0; i < 8; ++i) {
                        glm::vec4 expected;
                        if (tex->mipLevels() == 1) {
                            expected = tex->Sample(s, glm::vec2(uv.x[i], uv.y[i]));
                        } else {
                            const int left = i & ~1, top = i & ~4;
                            expected = tex->SampleGrad(s, glm::vec2(uv.x[i], uv.y[i]),
                                                       {uv.x[left + 1] - uv.x[left], uv.y[left + 1] - uv.y[left]},
                                                       {uv.x[top + 4] - uv.x[top], uv.y[top + 4] - uv.y[top]});
                        }
                        ASSERT_EQ(glm::vec4(wide.x[i], wide.y[i], wide.z[i], wide.w[i]), expected)
                            << "lane " << i << " uv " << uv.x[i] << "," << uv.y[i];
                    }
                }
            }
        }
    }
}

// gsBillboard with its corners turned by 30° on the screen: not a rectangle, so two triangles.
struct GsTilted : shaders::GsBillboard {
    void operator()(const Point<shaders::BillboardVertex>& in,
                    TriangleStream<shaders::BillboardCorner, 4>& stream) const {
        const glm::vec4 c = viewProj * in[0].position;
        const float cs = std::cos(0.5236f), sn = std::sin(0.5236f);
        auto corner = [&](float ox, float oy, glm::vec2 uv) {
            const glm::vec2 o((ox * cs - oy * sn) * billboardSize.x, (ox * sn + oy * cs) * billboardSize.y);
            return shaders::BillboardCorner{c + glm::vec4(o, 0, 0), uv};
        };
        stream.Append(corner(1, 1, {1, 0}));
        stream.Append(corner(1, -1, {1, 1}));
        stream.Append(corner(-1, 1, {0, 0}));
        stream.Append(corner(-1, -1, {0, 1}));
    }
};

// Renders the particle scene's particles with the given pixel shader.
template <class PS>
RenderTarget renderParticles(const PS& ps, PipelineStatistics* stats, bool reference = false,
                             const std::function<void(DepthTarget&)>& prepareDepth = {}, unsigned threads = 2,
                             bool tilted = false, float half_size = 0.08f) {
    SceneOptions o;
    o.width = 320, o.height = 180;
    RenderTarget color(o.width, o.height);
    DepthTarget depth(o.width, o.height);
    color.clear({0, 0, 0, 1});
    depth.clear(1.0f);
    if (prepareDepth) prepareDepth(depth);
    std::vector<glm::vec3> points(3000);
    for (uint32_t i = 0; i < points.size(); ++i) points[i] = particlePosition(i);
    const VertexBuffer vb = VertexBuffer::create(points);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0}};
    const InputLayout layout(desc);
    Context ctx({threads, reference});
    ctx.setRenderTargets(&color, &depth);
    ctx.setViewport({0, 0, float(o.width), float(o.height), 0, 1});
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    ctx.setRasterizerState(rs);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::PointList);
    ctx.setBlendState(BlendState::additive());
    ctx.setDepthStencilState(DepthStencilState::readOnly());
    shaders::GsBillboard gs;
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(60.0f), 320.0f / 180.0f, 0.1f, 100.0f);
    gs.viewProj = proj * glm::lookAtRH(glm::vec3(0, 0.3f, 4), glm::vec3(0), glm::vec3(0, 1, 0));
    gs.billboardSize = {half_size * proj[0][0], half_size * proj[1][1]};
    if (tilted)
        ctx.draw(shaders::VsBillboard{}, GsTilted{gs}, ps, uint32_t(points.size()));
    else
        ctx.draw(shaders::VsBillboard{}, gs, ps, uint32_t(points.size()));
    if (stats) *stats = ctx.drawStatistics();
    return color;
}

TEST(Rectangles, BillboardsAreRecognisedAndWideShadingMatchesScalar) {
    const Texture2D fire = makeFireTexture();
    shaders::PsFire wide;
    wide.billboardTexture = &fire;
    PipelineStatistics wide_stats, scalar_stats, eight_stats, ref_stats;
    const RenderTarget a = renderParticles(wide, &wide_stats);
    const RenderTarget b = renderParticles(PsFireScalarOnly{wide}, &scalar_stats);
    const RenderTarget e = renderParticles(PsFireEightOnly{wide}, &eight_stats);
    EXPECT_EQ(wide_stats.rectanglesRecognized, 3000u);
    EXPECT_EQ(wide_stats.gsPrimitives, 6000u);
    // The eight-wide paths skip the sprites' transparent corners (transparency.hpp), the scalar one
    // shades them.
    EXPECT_GT(wide_stats.fragmentsTransparentSkipped, scalar_stats.psInvocations / 10);
    EXPECT_EQ(scalar_stats.fragmentsTransparentSkipped, 0u);
    EXPECT_EQ(wide_stats.psInvocations + wide_stats.fragmentsTransparentSkipped, scalar_stats.psInvocations);
    EXPECT_EQ(wide_stats.fragmentsBlendNoOp + wide_stats.fragmentsTransparentSkipped,
              scalar_stats.fragmentsBlendNoOp);
    EXPECT_TRUE(a == b) << "eight-wide shading changed the image";
    // Two blocks per call (PsFire) against one (PsFireEightOnly): the same image and the same
    // counts, helper lanes and blend no-ops included.
    EXPECT_TRUE(a == e) << "shading block pairs changed the image";
    EXPECT_EQ(wide_stats.psInvocations, eight_stats.psInvocations);
    EXPECT_EQ(wide_stats.helperInvocations, eight_stats.helperInvocations);
    EXPECT_EQ(wide_stats.fragmentsBlendNoOp, eight_stats.fragmentsBlendNoOp);
    EXPECT_EQ(wide_stats.fragmentsEarlyDepthKilled, eight_stats.fragmentsEarlyDepthKilled);
    EXPECT_EQ(wide_stats.fragmentsTransparentSkipped, eight_stats.fragmentsTransparentSkipped);
    EXPECT_GT(wide_stats.fragmentsBlendNoOp, 0u);
    // The reference pipeline draws the same billboards as two triangles each.
    const RenderTarget r = renderParticles(wide, &ref_stats, true);
    EXPECT_EQ(ref_stats.rectanglesRecognized, 0u);
    EXPECT_EQ(ref_stats.psInvocations, wide_stats.psInvocations + wide_stats.fragmentsTransparentSkipped)
        << "rectangles must cover the same pixels";
    const std::vector<uint8_t> x = a.toRgba8(), y = r.toRgba8();
    int worst = 0;
    for (size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(int(x[i]) - int(y[i])));
    EXPECT_LE(worst, 1);
}

// The eight-wide paths do not shade a block whose pixels are all at the additive blend's ceiling
// (every byte 255), which no fragment can change. White texels at alpha 1 add 255 to every byte, so
// one layer takes a pixel there. What the paths skip and shade must add up to what the scalar path
// (and the reference, less its late depth kills) shades, with the reference's image, for rectangles and for
// triangles (tilted billboards), one or two blocks per call, on any thread count. A row of depth 0 checks
// that depth kills are not counted as skips.
TEST(Rectangles, BlocksAtTheAdditiveCeilingAreCountedNotShaded) {
    const std::vector<uint8_t> texels(4 * 4 * 4, 255);
    const Texture2D white = Texture2D::fromRgba8(4, 4, texels, false);
    shaders::PsFire ps;
    ps.billboardTexture = &white;
    auto wall = [](DepthTarget& d) {
        for (uint32_t x = 0; x < 320; ++x) d.store(x, 91, 0.0f);
    };
    for (const bool tilted : {false, true}) {
        PipelineStatistics ref_stats, scalar_stats;
        const RenderTarget ref = renderParticles(ps, &ref_stats, true, wall, 2, tilted);
        const RenderTarget scalar =
            renderParticles(PsFireScalarOnly{ps}, &scalar_stats, false, wall, 2, tilted);
        EXPECT_TRUE(scalar == ref) << tilted;
        EXPECT_EQ(ref_stats.rectanglesRecognized, 0u);
        EXPECT_EQ(scalar_stats.fragmentsBlendSaturated, 0u)
            << "one pixel at a time, every fragment is shaded";
        // The reference tests depth after the shader.
        EXPECT_EQ(scalar_stats.psInvocations, ref_stats.psInvocations - ref_stats.fragmentsLateDepthKilled)
            << tilted;
        EXPECT_GT(scalar_stats.fragmentsEarlyDepthKilled, 300u) << tilted;
        for (const unsigned threads : {1u, 2u, 3u}) {
            PipelineStatistics pair_stats, eight_stats;
            const RenderTarget pair = renderParticles(ps, &pair_stats, false, wall, threads, tilted);
            const RenderTarget eight =
                renderParticles(PsFireEightOnly{ps}, &eight_stats, false, wall, threads, tilted);
            EXPECT_TRUE(pair == ref) << tilted << " " << threads;
            EXPECT_TRUE(eight == ref) << tilted << " " << threads;
            EXPECT_EQ(pair_stats.rectanglesRecognized, tilted ? 0u : 3000u);
            for (const PipelineStatistics* s : {&pair_stats, &eight_stats}) {
                // Most particles overlap others in this cloud: most fragments come after the first.
                EXPECT_GT(s->fragmentsBlendSaturated, scalar_stats.psInvocations / 3)
                    << tilted << " " << threads;
                EXPECT_EQ(s->psInvocations + s->fragmentsBlendSaturated, scalar_stats.psInvocations)
                    << tilted << " " << threads;
                EXPECT_EQ(s->fragmentsEarlyDepthKilled, scalar_stats.fragmentsEarlyDepthKilled) << tilted;
            }
            // A rectangle's pair is skipped only when both its blocks are at the ceiling; a block
            // alone, or a triangle's block, whenever it is.
            if (tilted)
                EXPECT_EQ(eight_stats.fragmentsBlendSaturated, pair_stats.fragmentsBlendSaturated);
            else
                EXPECT_GT(eight_stats.fragmentsBlendSaturated, pair_stats.fragmentsBlendSaturated);
        }
    }
}

// A pixel shader as it is, less its AlphaSource: the pipeline then shades every pixel.
template <class PS>
struct WithoutAlphaSource {
    using Input = typename PS::Input;
    PS inner;
    template <class In>
    auto operator()(const In& in) const {
        return inner(in);
    }
};
static_assert(AlphaSourcePixelShader<shaders::PsFire> && AlphaSourcePixelShader<PsFireEightOnly>);
static_assert(!AlphaSourcePixelShader<WithoutAlphaSource<shaders::PsFire>>);
static_assert(PairPixelShader<WithoutAlphaSource<shaders::PsFire>>);

// Textures with transparent texels in many shapes: ragged rows, holes, a transparent band, alpha
// next to transparency at every edge, and the fire texture itself.
std::vector<Texture2D> transparencyTextures() {
    std::vector<Texture2D> out;
    out.push_back(makeFireTexture());
    std::mt19937 rng(11);
    for (const auto& [w, h] : {std::pair{13, 9}, std::pair{5, 17}, std::pair{40, 3}}) {
        std::vector<uint8_t> texels(size_t(w * h) * 4);
        for (int y = 0; y < h; ++y) {
            const int first = int(rng() % uint32_t(w + 1)), last = int(rng() % uint32_t(w));
            const bool band = y % 4 == 1;  // a whole transparent row
            for (int x = 0; x < w; ++x) {
                uint8_t* t = &texels[size_t(y * w + x) * 4];
                for (int c = 0; c < 3; ++c) t[c] = uint8_t(rng());
                const bool visible = !band && x >= first && x <= last && rng() % 5 != 0;  // holes too
                t[3] = visible ? uint8_t(1 + rng() % 255) : 0;
            }
        }
        out.push_back(Texture2D::fromRgba8(uint32_t(w), uint32_t(h), texels, false));
    }
    return out;
}

// Billboard pixels whose every texel has alpha 0 are skipped before the shader, and the image is
// the one of shading them all, bit for bit, at sprite sizes from minified to many tiles wide, for
// bilinear and point samples, on any thread count; what was skipped is counted, and adds up to what
// the full draw shades. An address mode other than Clamp skips nothing. The largest sprites also
// reach the additive blend's ceiling.
TEST(Rectangles, TransparentPixelsAreSkippedWithTheSameImage) {
    const std::vector<Texture2D> textures = transparencyTextures();
    auto wall = [](DepthTarget& d) {
        for (uint32_t x = 0; x < 320; ++x) d.store(x, 91, 0.0f);
    };
    for (size_t t = 0; t < textures.size(); ++t) {
        for (const SamplerState& sampler : {SamplerState::bilinear(AddressMode::Clamp),
                                            SamplerState::point(AddressMode::Clamp),
                                            SamplerState::bilinear(AddressMode::Wrap)}) {
            for (const float half_size : {0.02f, 0.08f, 0.7f}) {
                shaders::PsFire ps;
                ps.billboardTexture = &textures[t];
                ps.sampler = sampler;
                const std::string what = "texture " + std::to_string(t) + " size " +
                                         std::to_string(half_size) + " address " +
                                         std::to_string(int(sampler.addressU)) + " filter " +
                                         std::to_string(int(sampler.magFilter));
                PipelineStatistics full_stats;
                const RenderTarget full = renderParticles(WithoutAlphaSource<shaders::PsFire>{ps}, &full_stats,
                                                          false, wall, 2, false, half_size);
                EXPECT_EQ(full_stats.fragmentsTransparentSkipped, 0u) << what;
                for (const unsigned threads : {1u, 3u}) {
                    PipelineStatistics s;
                    const RenderTarget skipped = renderParticles(ps, &s, false, wall, threads, false, half_size);
                    ASSERT_TRUE(skipped == full) << what << " threads " << threads;
                    // Every fragment that passes the depth test is shaded, at the ceiling or transparent.
                    EXPECT_EQ(s.psInvocations + s.fragmentsBlendSaturated + s.fragmentsTransparentSkipped,
                              full_stats.psInvocations + full_stats.fragmentsBlendSaturated)
                        << what;
                    // Where nothing reaches the ceiling (which pairs blocks differently once some are
                    // skipped), every skipped fragment is one the full draw shades to a blend no-op.
                    if (full_stats.fragmentsBlendSaturated == 0 && s.fragmentsBlendSaturated == 0) {
                        EXPECT_EQ(s.fragmentsBlendNoOp + s.fragmentsTransparentSkipped,
                                  full_stats.fragmentsBlendNoOp)
                            << what;
                    }
                    EXPECT_EQ(s.fragmentsEarlyDepthKilled, full_stats.fragmentsEarlyDepthKilled) << what;
                    if (sampler.addressU == AddressMode::Wrap) {
                        EXPECT_EQ(s.fragmentsTransparentSkipped, 0u) << what;
                    } else {  // every texture here has transparent rows or columns to skip
                        EXPECT_GT(s.fragmentsTransparentSkipped, full_stats.psInvocations / 50) << what;
                    }
                }
            }
        }
    }
}

// The skip's interval per row pair holds every pixel whose footprint, computed from the float
// coordinates as the sampler does, reads a texel of non-zero alpha, for random planes (both signs
// of step, sub-texel offsets, clamped edges), and is empty for a texture transparent everywhere.
TEST(TransparentColumns, RowIntervalHoldsEveryPixelThatMayBeVisible) {
    const std::vector<Texture2D> textures = transparencyTextures();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const Texture2D& tex : textures) {
        const SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);
        const detail::TransparentColumns columns(AlphaSource{&tex, &sampler, 4});
        ASSERT_TRUE(columns.enabled());
        const int tw = int(tex.width()), th = int(tex.height());
        auto alphaAt = [&](int x, int y) {
            return tex.load(std::clamp(x, 0, tw - 1), std::clamp(y, 0, th - 1)).w;
        };
        uint64_t skipped = 0;
        for (int trial = 0; trial < 300; ++trial) {
            const int w = 1 + int(rng() % 60), h = 1 + int(rng() % 60);
            // u from about −0.2 to 1.2 across the box, either way round.
            // Every tenth box has one u across it (a billboard seen edge-on would), exactly or nearly.
            const float span_u = trial % 10 == 0   ? (trial % 20 == 0 ? 0.0f : 1e-9f)
                                 : float((unit(rng) * 1.4 + 0.1) * (rng() % 2 ? 1 : -1));
            const float bu = float(trial % 10 == 0 ? unit(rng) * 1.4 - 0.2
                                   : span_u > 0    ? unit(rng) * 0.4 - 0.2
                                                   : 1.0 + unit(rng) * 0.4 - 0.2);
            const float span_v = float(unit(rng) * 1.4 + 0.1);
            const float bv = float(unit(rng) * 0.4 - 0.2);
            float base[6] = {0, 0, 0, 1, bu, bv}, sx[6] = {}, sy[6] = {};
            sx[4] = span_u / float(w), sy[5] = span_v / float(h);
            const auto planes = columns.planes(base, sx, sy, w, h);
            ASSERT_TRUE(planes.usable);
            for (int j = 0; j < h; j += 2) {
                int32_t lo, hi;
                columns.rowPair(planes, j, 0, w - 1, lo, hi);
                for (int i = 0; i < w; ++i) {
                    bool visible = false;
                    for (int jj = j; jj <= j + 1; ++jj) {
                        const float u = base[4] + float(i) * sx[4], v = base[5] + float(jj) * sy[5];
                        const int ia = int(std::floor(u * float(tw) - 0.5f));
                        const int ib = int(std::floor(v * float(th) - 0.5f));
                        for (int dy = 0; dy <= 1; ++dy)
                            for (int dx = 0; dx <= 1; ++dx) visible |= alphaAt(ia + dx, ib + dy) != 0.0f;
                    }
                    if (visible)
                        ASSERT_TRUE(i >= lo && i <= hi) << "pixel " << i << " row " << j << " of " << w << "x" << h;
                    else if (i < lo || i > hi)
                        ++skipped;
                }
            }
        }
        EXPECT_GT(skipped, 1000u) << "the interval should leave transparent pixels out";
    }
    // Transparent everywhere: nothing to shade; and no skip where it cannot be proven.
    const std::vector<uint8_t> clear(8 * 8 * 4, 0);
    const Texture2D empty = Texture2D::fromRgba8(8, 8, clear, false);
    const SamplerState clamp = SamplerState::bilinear(AddressMode::Clamp);
    const detail::TransparentColumns none(AlphaSource{&empty, &clamp, 4});
    const float base[6] = {0, 0, 0, 1, 0.1f, 0.1f};
    const float sx[6] = {0, 0, 0, 0, 0.05f, 0}, sy[6] = {0, 0, 0, 0, 0, 0.05f};
    int32_t lo, hi;
    none.rowPair(none.planes(base, sx, sy, 16, 16), 4, 0, 15, lo, hi);
    EXPECT_GT(lo, hi);
    const float tilted_sy[6] = {0, 0, 0, 0, 0.01f, 0.05f};  // u varies along y too
    EXPECT_FALSE(none.planes(base, sx, tilted_sy, 16, 16).usable);
    const float far_base[6] = {0, 0, 0, 1, 100.0f, 0.1f};
    EXPECT_FALSE(none.planes(far_base, sx, sy, 16, 16).usable);
    const float nan_base[6] = {0, 0, 0, 1, std::nanf(""), 0.1f};
    EXPECT_FALSE(none.planes(nan_base, sx, sy, 16, 16).usable);
    const SamplerState wrap = SamplerState::bilinear(AddressMode::Wrap);
    EXPECT_FALSE(detail::TransparentColumns(AlphaSource{&empty, &wrap, 4}).enabled());
    const Texture2D mipmapped = Texture2D::fromRgba8(8, 8, clear, true);
    EXPECT_FALSE(detail::TransparentColumns(AlphaSource{&mipmapped, &clamp, 4}).enabled());
}

// The four-at-a-time intervals (rowPairs) are rowPair's, value for value: random planes of both
// signs, boxes cut to parts of themselves, any count of row pairs (a partial last group of four),
// row pairs starting above the box, planes with one u across the box, and unusable ones.
TEST(TransparentColumns, RowPairsGiveRowPairsIntervals) {
    const std::vector<Texture2D> textures = transparencyTextures();
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    uint64_t compared = 0, empty = 0, cut = 0;
    for (const Texture2D& tex : textures) {
        const SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);
        const detail::TransparentColumns columns(AlphaSource{&tex, &sampler, 4});
        for (int trial = 0; trial < 400; ++trial) {
            const int w = 1 + int(rng() % 70), h = 1 + int(rng() % 70);
            const float span_u = trial % 13 == 0 ? 0.0f : float((unit(rng) * 3.0 - 1.5));
            const float span_v = float(unit(rng) * 3.0 - 1.5);
            float base[6] = {0, 0, 0, 1, float(unit(rng) * 2.0 - 0.5), float(unit(rng) * 2.0 - 0.5)};
            float sx[6] = {}, sy[6] = {};
            sx[4] = span_u / float(w), sy[5] = span_v / float(h);
            if (trial % 17 == 0) base[4] = 50.0f;  // not usable: every pixel may be visible
            const auto planes = columns.planes(base, sx, sy, w, h);
            const int32_t i_min = int32_t(rng() % uint32_t(w)), i_max = i_min + int32_t(rng() % uint32_t(w - i_min));
            const int32_t j0 = int32_t(rng() % uint32_t(h)) - 1;
            const int n = 1 + int(rng() % 33);
            // Room for the padding rowPairs may write, and one sentinel past it that must stay.
            const size_t room = size_t(n + detail::TransparentColumns::kRowPairsPadding);
            std::vector<int32_t> lo(room + 1, -7), hi(room + 1, -7);
            columns.rowPairs(planes, j0, n, i_min, i_max, lo.data(), hi.data());
            ASSERT_EQ(lo[room], -7);
            ASSERT_EQ(hi[room], -7);
            for (int q = 0; q < n; ++q) {
                int32_t l, r;
                columns.rowPair(planes, j0 + 2 * q, i_min, i_max, l, r);
                ASSERT_EQ(lo[size_t(q)], l) << "row pair " << j0 + 2 * q << " trial " << trial;
                ASSERT_EQ(hi[size_t(q)], r) << "row pair " << j0 + 2 * q << " trial " << trial;
                ++compared;
                empty += l > r;
                cut += l <= r && (l > i_min || r < i_max);
            }
        }
    }
    // The cases that matter occurred: row pairs with nothing to shade and row pairs cut at either end.
    EXPECT_GT(compared, 10000u);
    EXPECT_GT(empty, 500u);
    EXPECT_GT(cut, 1000u);
}

// A read-only depth draw skips the per-block test where a rectangle lies in front of the tile's
// nearest stored depth. Stored NaN (fails every test) and nearer depths must still refuse their
// fragments: the image equals the scalar path's, which tests every pixel.
TEST(Rectangles, InFrontOfTheTileSkipsTheTestButNotItsRefusals) {
    const Texture2D fire = makeFireTexture();
    shaders::PsFire wide;
    wide.billboardTexture = &fire;
    // Pixels every particle covers at 320×180 (the image's busiest area), one per kind.
    const uint32_t nan_x = 150, nan_y = 95, near_x = 170, near_y = 85, wall_y = 120;
    auto prepare = [&](DepthTarget& d) {
        d.store(nan_x, nan_y, std::nanf(""));
        d.store(near_x, near_y, 0.0f);
        for (uint32_t x = 0; x < 320; ++x) d.store(x, wall_y, 0.0f);  // a whole row in front of all
    };
    PipelineStatistics wide_stats, scalar_stats;
    const RenderTarget a = renderParticles(wide, &wide_stats, false, prepare);
    const RenderTarget b = renderParticles(PsFireScalarOnly{wide}, &scalar_stats, false, prepare);
    EXPECT_TRUE(a == b);
    EXPECT_EQ(wide_stats.fragmentsEarlyDepthKilled, scalar_stats.fragmentsEarlyDepthKilled);
    const RenderTarget open = renderParticles(wide, nullptr);
    const glm::vec4 cleared(0, 0, 0, 1);
    for (auto [x, y] : {std::pair{nan_x, nan_y}, std::pair{near_x, near_y}, std::pair{160u, wall_y}}) {
        EXPECT_EQ(a.load(x, y), cleared) << x << "," << y;
    }
    // Without the refusing depths those pixels are drawn (so the test above means something).
    EXPECT_NE(open.load(nan_x, nan_y), cleared);
    EXPECT_NE(open.load(near_x, near_y), cleared);
    EXPECT_NE(open.load(160, wall_y), cleared);
}

}  // namespace
}  // namespace raster

namespace raster {
namespace {

// Distance in units in the last place between two finite floats of the same sign.
int64_t ulps(float a, float b) {
    const int32_t ia = __builtin_bit_cast(int32_t, a), ib = __builtin_bit_cast(int32_t, b);
    return std::abs(int64_t(ia) - int64_t(ib));
}

TEST(FastMath, ExpAndExpm1WithinTwoUlpOfTheCLibrary) {
    int64_t worst_exp = 0, worst_expm1 = 0;
    for (float x = -87.0f; x <= 88.0f; x += 0.0007f) {
        worst_exp = std::max(worst_exp, ulps(fastExp(x), std::exp(x)));
        worst_expm1 = std::max(worst_expm1, ulps(fastExpm1(x), std::expm1(x)));
    }
    for (float x = -1e-3f; x <= 1e-3f; x += 1.3e-7f) worst_expm1 = std::max(worst_expm1, ulps(fastExpm1(x), std::expm1(x)));
    EXPECT_LE(worst_exp, 2);
    EXPECT_LE(worst_expm1, 2);
    std::printf("fastExp max %lld ulp, fastExpm1 max %lld ulp\n", (long long)worst_exp, (long long)worst_expm1);
}

TEST(FastMath, LimitsAndSpecialValues) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(fastExp(0.0f), 1.0f);
    EXPECT_EQ(fastExpm1(0.0f), 0.0f);
    EXPECT_EQ(fastExp(-inf), 0.0f);
    EXPECT_EQ(fastExpm1(-inf), -1.0f);
    EXPECT_EQ(fastExp(inf), inf);
    EXPECT_EQ(fastExpm1(inf), inf);
    EXPECT_TRUE(std::isnan(fastExp(std::nanf(""))));
    EXPECT_EQ(fastExp(-100.0f), 0.0f);
    EXPECT_EQ(fastExpm1(1e-30f), 1e-30f);
    // expm1 clamps its argument at −20 (where it is −1 to float precision) and lets NaN through.
    EXPECT_TRUE(std::isnan(fastExpm1(std::nanf(""))));
    EXPECT_TRUE(std::isnan(fastExpm1(Float8(std::nanf("")))[5]));
    EXPECT_EQ(fastExpm1(100.0f), inf);
    EXPECT_EQ(fastExpm1(88.8f), inf);
    for (float x : {-20.0f, -20.01f, -25.0f, -87.5f, -1e30f}) {
        EXPECT_EQ(fastExpm1(x), -1.0f) << x;
        EXPECT_EQ(fastExpm1(Float8(x))[3], -1.0f) << x;
    }
    for (float x : {-17.0f, -19.99f}) EXPECT_LE(ulps(fastExpm1(x), std::expm1(x)), 2) << x;
}

// fastExpm1 passes NaN to the float-to-int rounding; there, as in CVTPS2DQ, NaN and values outside
// int32 give INT32_MIN (a C++ cast of them would be undefined behaviour), scalar and eight-wide alike.
TEST(FastMath, RoundingToIntIsDefinedForNaNAndOutOfRange) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(detail::toIntRound(2.5f), 2);
    EXPECT_EQ(detail::toIntRound(-3.5f), -4);
    EXPECT_EQ(detail::toIntRound(-2147483648.0f), INT32_MIN);
    EXPECT_EQ(detail::toIntRound(2147483520.0f), 2147483520);
    for (const float x : {std::nanf(""), inf, -inf, 2147483648.0f, -3e9f, 3e38f}) {
        EXPECT_EQ(detail::toIntRound(x), INT32_MIN) << x;
        EXPECT_EQ(detail::toIntRound(Float8(x))[2], INT32_MIN) << x;
    }
}

TEST(Float8, BroadcastKeepsTheSignOfZero) {
    EXPECT_TRUE(std::signbit(Float8(-0.0f)[0]));
    EXPECT_TRUE(std::signbit(Float8(-0.0f)[7]));
    EXPECT_EQ(toFloat8(simd::F64x4{1.0, -0.0, 0.1, 1e300}, simd::F64x4{-2.5, 3.0, 1e-300, -1e300})[2], 0.1f);
}

TEST(Float8, MinMaxReturnTheSecondOperandForNaN) {
    const float nan = std::nanf("");
    EXPECT_EQ(max(Float8(nan), Float8(0.0f))[0], 0.0f);
    EXPECT_TRUE(std::isnan(max(Float8(0.0f), Float8(nan))[0]));
    EXPECT_EQ(min(Float8(nan), Float8(1.0f))[0], 1.0f);
    EXPECT_TRUE(std::isnan(min(Float8(1.0f), Float8(nan))[0]));
    EXPECT_EQ(floor(Float8(-1.5f))[1], -2.0f);
    EXPECT_EQ(floor(Float8(2.0f))[1], 2.0f);
}

TEST(Float8, FmaRoundsOnceLikeStdFma) {
    // (1 + 2^-12)² − (1 + 2^-11) = 2^-24 exactly; the product alone rounds to 1 + 2^-11 (floats
    // above 1 are 2^-23 apart), so an unfused multiply-add gives 0.
    const float a = 1.0f + 0x1p-12f, c = -(1.0f + 0x1p-11f);
    EXPECT_EQ(fma(a, a, c), 0x1p-24f);
    EXPECT_EQ(fma(Float8(a), Float8(a), Float8(c))[6], 0x1p-24f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> d(-3.0f, 3.0f);
    for (int round = 0; round < 1000; ++round) {
        Float8 x, y, z;
        for (int i = 0; i < 8; ++i) x.set(i, d(rng)), y.set(i, d(rng)), z.set(i, d(rng));
        const Float8 r = fma(x, y, z);
        for (int i = 0; i < 8; ++i)
            ASSERT_EQ(__builtin_bit_cast(int32_t, r[i]), __builtin_bit_cast(int32_t, std::fma(x[i], y[i], z[i])));
    }
}

// Float8x2 is two Float8 side by side: every operation must give, in each half, the bits of the
// Float8 operation on that half (the pipeline relies on it for billboard block pairs).
TEST(Float8x2, EveryOperationIsTheFloat8OperationOnEachHalf) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> d(-100.0f, 100.0f);
    const float specials[] = {0.0f, -0.0f, std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(), std::nanf(""), 1e-40f, 3e38f, -1.5f};
    auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
    auto same = [&](Float8x2 pair, Float8 lo, Float8 hi, const char* what) {
        for (int i = 0; i < 8; ++i) {
            ASSERT_EQ(bits(pair[i]), bits(lo[i])) << what << " lane " << i;
            ASSERT_EQ(bits(pair[8 + i]), bits(hi[i])) << what << " lane " << 8 + i;
        }
    };
    auto sameInt = [&](Int8x2 pair, Int8 lo, Int8 hi, const char* what) {
        for (int i = 0; i < 8; ++i) {
            ASSERT_EQ(pair[i], lo[i]) << what << " lane " << i;
            ASSERT_EQ(pair[8 + i], hi[i]) << what << " lane " << 8 + i;
        }
    };
    const int32_t table[16] = {3, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5, 8, 9, 7, 9, 3};
    const float ftable[16] = {0.5f, -1, 2, 8, 16, 1e9f, -0.0f, 7, 6, 5, 4, 3, 2, 1, 0, -3};
    for (int round = 0; round < 200; ++round) {
        Float8 a[2], b[2], c[2];
        Int8 k[2], m[2];
        for (int h = 0; h < 2; ++h)
            for (int i = 0; i < 8; ++i) {
                const bool special = round % 4 == 0;
                a[h].set(i, special ? specials[(i + h) % 8] : d(rng));
                b[h].set(i, special ? specials[(3 * i + round) % 8] : d(rng));
                c[h].set(i, d(rng));
                k[h].v[i] = int32_t(rng() % 16), m[h].v[i] = int32_t(rng());
            }
        const Float8x2 A(a[0], a[1]), B(b[0], b[1]), C(c[0], c[1]);
        const Int8x2 K(k[0], k[1]), M(m[0], m[1]);
        same(A + B, a[0] + b[0], a[1] + b[1], "+");
        same(A - B, a[0] - b[0], a[1] - b[1], "-");
        same(A * B, a[0] * b[0], a[1] * b[1], "*");
        same(A / B, a[0] / b[0], a[1] / b[1], "/");
        same(-A, -a[0], -a[1], "negate");
        Float8x2 acc = A;
        acc += B, acc *= C, acc -= A, acc /= B;
        same(acc, (((a[0] + b[0]) * c[0]) - a[0]) / b[0], (((a[1] + b[1]) * c[1]) - a[1]) / b[1], "compound");
        same(min(A, B), min(a[0], b[0]), min(a[1], b[1]), "min");
        same(max(A, B), max(a[0], b[0]), max(a[1], b[1]), "max");
        same(floor(A), floor(a[0]), floor(a[1]), "floor");
        same(sqrt(A), sqrt(a[0]), sqrt(a[1]), "sqrt");
        same(abs(A), abs(a[0]), abs(a[1]), "abs");
        same(fma(A, B, C), fma(a[0], b[0], c[0]), fma(a[1], b[1], c[1]), "fma");
        same(exp(C * Float8x2(0.5f)), exp(c[0] * Float8(0.5f)), exp(c[1] * Float8(0.5f)), "exp");
        same(expm1(A), expm1(a[0]), expm1(a[1]), "expm1");
        same(select(A < B, A, C), select(a[0] < b[0], a[0], c[0]), select(a[1] < b[1], a[1], c[1]), "select");
        same(toFloat(K), toFloat(k[0]), toFloat(k[1]), "toFloat");
        same(gather(ftable, K), gather(ftable, k[0]), gather(ftable, k[1]), "gather");
        sameInt(toInt(C), toInt(c[0]), toInt(c[1]), "toInt");
        sameInt(K + M, k[0] + m[0], k[1] + m[1], "int +");
        sameInt(K - M, k[0] - m[0], k[1] - m[1], "int -");
        sameInt(K * M, k[0] * m[0], k[1] * m[1], "int *");
        sameInt(K & M, k[0] & m[0], k[1] & m[1], "int &");
        sameInt(K | M, k[0] | m[0], k[1] | m[1], "int |");
        sameInt(M << 3, m[0] << 3, m[1] << 3, "<<");
        sameInt(M >> 5, m[0] >> 5, m[1] >> 5, ">>");
        sameInt(min(K, M), min(k[0], m[0]), min(k[1], m[1]), "int min");
        sameInt(max(K, M), max(k[0], m[0]), max(k[1], m[1]), "int max");
        sameInt(select(K < M, K, M), select(k[0] < m[0], k[0], m[0]), select(k[1] < m[1], k[1], m[1]), "int select");
        sameInt(gather(table, K), gather(table, k[0]), gather(table, k[1]), "int gather");
        auto maskBits = [](Mask8 lo, Mask8 hi) { return lo.bits() | (hi.bits() << 8); };
        EXPECT_EQ((A < B).bits(), maskBits(a[0] < b[0], a[1] < b[1]));
        EXPECT_EQ((A <= B).bits(), maskBits(a[0] <= b[0], a[1] <= b[1]));
        EXPECT_EQ((A > B).bits(), maskBits(a[0] > b[0], a[1] > b[1]));
        EXPECT_EQ((A >= B).bits(), maskBits(a[0] >= b[0], a[1] >= b[1]));
        EXPECT_EQ((A == B).bits(), maskBits(a[0] == b[0], a[1] == b[1]));
        EXPECT_EQ((A != B).bits(), maskBits(a[0] != b[0], a[1] != b[1]));
        EXPECT_EQ((K > M).bits(), maskBits(k[0] > m[0], k[1] > m[1]));
        EXPECT_EQ(((A < B) & (B < C)).bits(), maskBits((a[0] < b[0]) & (b[0] < c[0]), (a[1] < b[1]) & (b[1] < c[1])));
        EXPECT_EQ(((A < B) | (B < C)).bits(), maskBits((a[0] < b[0]) | (b[0] < c[0]), (a[1] < b[1]) | (b[1] < c[1])));
        EXPECT_EQ((!(A < B)).bits(), maskBits(!(a[0] < b[0]), !(a[1] < b[1])));
    }
    EXPECT_EQ(Mask8x2::fromBits(0xA55Au).bits(), 0xA55Au);
    // Lane order, broadcasts and memory: lanes 0–7 are the first block.
    float in[16], out[16];
    for (int i = 0; i < 16; ++i) in[i] = float(i) - 7.5f;
    const Float8x2 loaded = Float8x2::load(in);
    loaded.store(out);
    for (int i = 0; i < 16; ++i) {
        EXPECT_EQ(loaded[i], in[i]);
        EXPECT_EQ(out[i], in[i]);
    }
    EXPECT_TRUE(std::signbit(Float8x2(-0.0f)[15]));
    EXPECT_EQ(Int8x2(-3)[9], -3);
}

TEST(FastMath, EightWideEqualsScalar) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> d(-90.0f, 90.0f);
    for (int round = 0; round < 1000; ++round) {
        Float8 x;
        for (int i = 0; i < 8; ++i) x.set(i, round % 2 ? d(rng) : d(rng) * 1e-3f);
        const Float8 e = fastExp(x), m = fastExpm1(x);
        for (int i = 0; i < 8; ++i) {
            ASSERT_EQ(__builtin_bit_cast(int32_t, e[i]), __builtin_bit_cast(int32_t, fastExp(x[i]))) << x[i];
            ASSERT_EQ(__builtin_bit_cast(int32_t, m[i]), __builtin_bit_cast(int32_t, fastExpm1(x[i]))) << x[i];
        }
    }
}

}  // namespace
}  // namespace raster
