// Rasterisation through the whole pipeline: triangle coverage against an independent brute-force
// reference, watertight fans and grids, the top-left rule, culling, points, lines, depth
// interpolation, determinism across thread counts, and the fast pipeline against the reference one.
#include "raster/stages/7_rasterizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"

namespace raster {
namespace {

// ---- Shaders: clip-space positions straight through, a constant 1 out ----------------------------

struct ClipIn {
    glm::vec4 position;
    RASTER_INPUT_SIGNATURE(ClipIn, RASTER_INPUT(position, "POSITION", 0))
};
struct ClipVertex {
    glm::vec4 position;
};
struct VsPass {
    ClipVertex operator()(const ClipIn& in) const { return {in.position}; }
};
struct PsOne {
    glm::vec4 operator()(const ClipVertex&) const { return glm::vec4(1.0f); }
};

// The same, as a vertex template with an eight-wide pixel shader: with an RGBA8 target and the
// replace or additive blend the pipeline shades these in 4×2 blocks (rasterizeTriangleBlocks).
// Each fragment adds 1/255, one UNORM step, so the red byte counts fragments.
template <class T>
struct BlockVertex {
    glm::vec<4, T> position;
};
struct VsBlock {
    BlockVertex<float> operator()(const ClipIn& in) const { return {in.position}; }
};
struct PsBlockCount {
    using Input = BlockVertex<float>;
    glm::vec4 operator()(const Input&) const { return glm::vec4(glm::vec3(1.0f / 255), 1.0f); }
    glm::vec<4, Float8> operator()(const Wide<Input>&) const {
        return {Float8(1.0f / 255), Float8(1.0f / 255), Float8(1.0f / 255), Float8(1.0f)};
    }
};
static_assert(WidePixelShader<PsBlockCount>);
static_assert(!WidePixelShader<PsOne>);

struct ColorIn {
    glm::vec4 position;
    glm::vec4 color;
    RASTER_INPUT_SIGNATURE(ColorIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0))
};
struct ColorVertex {
    glm::vec4 position;
    glm::vec4 color;
};
struct VsColor {
    ColorVertex operator()(const ColorIn& in) const { return {in.position, in.color}; }
};
// rgb from the vertex colour, alpha 1 so that an additive One/One blend counts fragments in alpha.
struct PsColorCount {
    glm::vec4 operator()(const ColorVertex& v) const { return glm::vec4(glm::vec3(v.color), 1.0f); }
};
struct PsColor {
    glm::vec4 operator()(const ColorVertex& v) const { return v.color; }
};
// The same colour pass with an eight-wide pixel shader (4×2 blocks on RGBA8 targets).
template <class T>
struct ColorVertexT {
    glm::vec<4, T> position;
    glm::vec<4, T> color;
};
struct VsColorT {
    ColorVertexT<float> operator()(const ColorIn& in) const { return {in.position, in.color}; }
};
struct PsColorWide {
    using Input = ColorVertexT<float>;
    glm::vec4 operator()(const Input& v) const { return v.color; }
    glm::vec<4, Float8> operator()(const Wide<Input>& v) const { return v.color; }
};

const InputElementDesc kPositionLayout[] = {
    {"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0, InputClassification::PerVertexData, 0}};
const InputElementDesc kColorLayout[] = {
    {"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0, InputClassification::PerVertexData, 0},
    {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, 16, InputClassification::PerVertexData, 0}};

BlendState countingBlend() {
    BlendState b;
    RenderTargetBlendDesc& d = b.renderTarget[0];
    d.blendEnable = true;
    d.srcBlend = d.destBlend = d.srcBlendAlpha = d.destBlendAlpha = Blend::One;
    d.blendOp = d.blendOpAlpha = BlendOp::Add;
    return b;
}

RasterizerState noCull() {
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    return rs;
}

// ---- Screen positions <-> clip space (w = 1) -----------------------------------------------------

struct Screen {
    double x, y;
};

// The clip-space position (w = 1) that lands on screen position p under viewport v.
glm::vec4 toClip(const Screen& p, const Viewport& v, float z = 0.5f) {
    return {float(2.0 * (p.x - v.topLeftX) / v.width - 1.0), float(1.0 - 2.0 * (p.y - v.topLeftY) / v.height),
            z, 1.0f};
}

// Screen position in 1/256 pixel, from the float clip position actually fed to the pipeline, by
// D3D11's viewport formula and a round-half-even snap.
struct Fixed {
    int64_t x, y;
};
Fixed toFixed(const glm::vec4& clip, const Viewport& v) {
    const double sx = (double(clip.x) / double(clip.w) + 1.0) * 0.5 * double(v.width) + double(v.topLeftX);
    const double sy = (1.0 - double(clip.y) / double(clip.w)) * 0.5 * double(v.height) + double(v.topLeftY);
    return {int64_t(std::nearbyint(sx * 256.0)), int64_t(std::nearbyint(sy * 256.0))};
}

// Centre of pixel (i, j) in 1/256 pixel.
int64_t centre(int64_t i) {
    return i * 256 + 128;
}

int sign(int64_t a) {
    return (a > 0) - (a < 0);
}

// The brute-force reference: is the centre (cx, cy) (1/256 pixel) inside the triangle, by the
// D3D11 top-left rule taken from its definition.
bool referenceCovers(const Fixed (&v)[3], int64_t cx, int64_t cy) {
    const int64_t area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
    if (area == 0) return false;
    for (int k = 0; k < 3; ++k) {
        const Fixed& a = v[k];
        const Fixed& b = v[(k + 1) % 3];
        const Fixed& c = v[(k + 2) % 3];
        const int64_t dx = b.x - a.x, dy = b.y - a.y;
        const int64_t e = dx * (cy - a.y) - dy * (cx - a.x);     // side of the centre
        const int64_t ec = dx * (c.y - a.y) - dy * (c.x - a.x);  // side of the third vertex (interior)
        if (e != 0) {
            if (sign(e) != sign(ec)) return false;
            continue;
        }
        // Exactly on the edge's line: only top and left edges keep it.
        // Top: exactly horizontal, the third vertex below (larger y; row 0 is on top).
        const bool top = dy == 0 && c.y > a.y;
        // Left: not horizontal, the interior to its right: the third vertex lies at larger x than
        // the edge's line at the third vertex's height. c.x - x_edge(c.y) has the sign of
        // dy · ((c.x - a.x)·dy - dx·(c.y - a.y)).
        const int64_t d = (c.x - a.x) * dy - dx * (c.y - a.y);
        const bool left = dy != 0 && sign(dy) * sign(d) > 0;
        if (!top && !left) return false;
    }
    return true;
}

// Pixels whose centres lie in [topLeft, topLeft + size) and in the target.
struct PixelBox {
    int x0, y0, x1, y1;  // inclusive
};
PixelBox viewportPixels(const Viewport& v, uint32_t width, uint32_t height) {
    PixelBox b{int(width), int(height), -1, -1};
    for (int i = 0; i < int(width); ++i)
        if (i + 0.5 >= v.topLeftX && i + 0.5 < double(v.topLeftX) + v.width)
            b.x0 = std::min(b.x0, i), b.x1 = std::max(b.x1, i);
    for (int j = 0; j < int(height); ++j)
        if (j + 0.5 >= v.topLeftY && j + 0.5 < double(v.topLeftY) + v.height)
            b.y0 = std::min(b.y0, j), b.y1 = std::max(b.y1, j);
    return b;
}

// ---- A context with one float target and a vertex buffer of clip positions ------------------------

// How triangles reach the pixel shader: 2×2 quads (scalar shader, float target, generic blend)
// or 4×2 blocks (eight-wide shader, RGBA8 target, the fast additive blend).
enum class Path { Quads, Blocks };
const char* pathName(Path p) {
    return p == Path::Quads ? "quads" : "blocks";
}
constexpr Path kPaths[] = {Path::Quads, Path::Blocks};

class Rig {
  public:
    Rig(uint32_t width, uint32_t height, Path path = Path::Quads, ContextOptions options = {.threads = 2})
        : path_(path),
          ctx_(options),
          layout_(kPositionLayout),
          color_(width, height, path == Path::Quads ? Format::R32G32B32A32_FLOAT : Format::R8G8B8A8_UNORM) {
        ctx_.setInputLayout(&layout_);
        ctx_.setRenderTargets(&color_, nullptr);
        setViewport({0, 0, float(width), float(height), 0, 1});
        ctx_.setRasterizerState(noCull());
        ctx_.setBlendState(path == Path::Quads ? countingBlend() : BlendState::additive());
        color_.clear(glm::vec4(0.0f));
        const glm::vec4 dummy[1] = {};
        vb_ = VertexBuffer::create(std::span<const glm::vec4>(dummy));
        ctx_.setVertexBuffer(0, &vb_);
    }

    Context& ctx() { return ctx_; }
    RenderTarget& color() { return color_; }
    const Viewport& viewport() const { return viewport_; }
    void setViewport(const Viewport& v) {
        viewport_ = v;
        ctx_.setViewport(v);
    }
    void clear() { color_.clear(glm::vec4(0.0f)); }

    void drawClip(std::span<const glm::vec4> clip, Topology topology) {
        vb_.update(clip);
        ctx_.setPrimitiveTopology(topology);
        if (path_ == Path::Quads)
            ctx_.draw(VsPass{}, PsOne{}, uint32_t(clip.size()));
        else
            ctx_.draw(VsBlock{}, PsBlockCount{}, uint32_t(clip.size()));
    }
    void drawScreen(const std::vector<Screen>& points, Topology topology, float z = 0.5f) {
        std::vector<glm::vec4> clip;
        for (const Screen& p : points) clip.push_back(toClip(p, viewport_, z));
        drawClip(clip, topology);
    }

    // The red channel: fragments counted at the pixel.
    float count(int x, int y) const {
        const size_t i = 4 * (size_t(y) * color_.width() + size_t(x));
        return path_ == Path::Quads ? color_.rgba32f()[i] : float(color_.rgba8()[i]);
    }
    uint32_t width() const { return color_.width(); }
    uint32_t height() const { return color_.height(); }
    int total() const {
        double sum = 0;
        for (uint32_t y = 0; y < height(); ++y)
            for (uint32_t x = 0; x < width(); ++x) sum += count(int(x), int(y));
        return int(sum);
    }
    const PipelineStatistics& stats() const { return ctx_.drawStatistics(); }

  private:
    Path path_;
    Context ctx_;
    InputLayout layout_;
    RenderTarget color_;
    VertexBuffer vb_;
    Viewport viewport_;
};

std::string describe(const glm::vec4 (&clip)[3], const Fixed (&f)[3], const Viewport& v) {
    std::ostringstream os;
    os.precision(9);
    os << "viewport {" << v.topLeftX << ", " << v.topLeftY << ", " << v.width << ", " << v.height << "}\n";
    for (int k = 0; k < 3; ++k) {
        char hex[128];
        std::snprintf(hex, sizeof hex, "clip (%a, %a, %a, 1)", clip[k].x, clip[k].y, clip[k].z);
        os << "  v" << k << " screen (" << f[k].x / 256.0 << ", " << f[k].y / 256.0 << ") = 16.8 (" << f[k].x
           << ", " << f[k].y << ")  " << hex << "\n";
    }
    return os.str();
}

// ---- 1. Random triangles against the brute-force reference ----------------------------------------

// A random screen position (viewport-relative) of one of several kinds.
struct TriangleMaker {
    std::mt19937 rng;
    double w, h;

    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    int uniInt(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }

    Screen anywhere(double margin) { return {uni(-margin, w + margin), uni(-margin, h + margin)}; }
    Screen onCentre() { return {uniInt(-2, int(w) + 2) + 0.5, uniInt(-2, int(h) + 2) + 0.5}; }
    Screen onCorner() { return {double(uniInt(-2, int(w) + 2)), double(uniInt(-2, int(h) + 2))}; }
    Screen onSubpixel() {
        return {uniInt(-512, int(w) * 256 + 512) / 256.0, uniInt(-512, int(h) * 256 + 512) / 256.0};
    }
    // Exactly half-way between two 16.8 positions: the snap must round half to even.
    Screen onHalfSubpixel() {
        return {(uniInt(-512, int(w) * 256 + 512) + 0.5) / 256.0,
                (uniInt(-512, int(h) * 256 + 512) + 0.5) / 256.0};
    }
    Screen mixed() {
        switch (uniInt(0, 4)) {
            case 0:
                return onCentre();
            case 1:
                return onCorner();
            case 2:
                return onSubpixel();
            case 3:
                return onHalfSubpixel();
            default:
                return anywhere(4);
        }
    }

    std::array<Screen, 3> make(int kind) {
        std::array<Screen, 3> p;
        switch (kind) {
            case 0:
            case 1:
                for (auto& q : p) q = anywhere(8);
                break;
            case 2: {  // tiny: under a pixel across
                const Screen c = anywhere(1);
                for (auto& q : p) q = {c.x + uni(-0.6, 0.6), c.y + uni(-0.6, 0.6)};
                break;
            }
            case 3:  // huge: far past the screen, inside the guard band
                for (auto& q : p) q = {uni(-12000, 12000), uni(-12000, 12000)};
                break;
            case 4: {  // sliver: the third vertex within a third of a pixel of the line through the others
                p[0] = anywhere(16), p[1] = anywhere(16);
                const double t = uni(-0.2, 1.2), dx = p[1].x - p[0].x, dy = p[1].y - p[0].y;
                const double len = std::max(1e-9, std::hypot(dx, dy)), off = uni(-0.3, 0.3);
                p[2] = {p[0].x + t * dx - off * dy / len, p[0].y + t * dy + off * dx / len};
                break;
            }
            case 5: {  // partly or wholly off-screen
                for (auto& q : p) q = anywhere(200);
                if (uniInt(0, 1)) {
                    const double shift[4][2] = {{-w - 210, 0}, {w + 210, 0}, {0, -h - 210}, {0, h + 210}};
                    const int s = uniInt(0, 3);
                    for (auto& q : p) q.x += shift[s][0] * 0.5, q.y += shift[s][1] * 0.5;
                }
                break;
            }
            case 6:
                for (auto& q : p) q = onCentre();
                break;
            case 7:
                for (auto& q : p) q = onCorner();
                break;
            case 8: {  // axis-aligned right triangle on centres, corners or the 1/256 grid
                const Screen a = mixed(), b = mixed();
                p[0] = a, p[1] = {b.x, a.y}, p[2] = {a.x, b.y};
                break;
            }
            default:
                for (auto& q : p) q = mixed();
                break;
        }
        if (uniInt(0, 1)) std::swap(p[1], p[2]);  // both windings
        return p;
    }
};

void expectCoverageMatchesBruteForce(Path path, uint32_t seed) {
    constexpr int kTriangles = 12000;
    struct Config {
        uint32_t width, height;
        Viewport viewport;
    };
    const Config configs[] = {
        {64, 64, {0, 0, 64, 64, 0, 1}},
        {96, 72, {13, 7, 64, 48, 0, 1}},          // offset viewport, two tiles across
        {96, 72, {10.25f, 6.75f, 70, 50, 0, 1}},  // fractional offset and size
    };
    std::vector<std::unique_ptr<Rig>> rigs;
    std::vector<PixelBox> boxes;
    for (const Config& c : configs) {
        rigs.push_back(std::make_unique<Rig>(c.width, c.height, path));
        rigs.back()->setViewport(c.viewport);
        rigs.back()->ctx().setBlendState(BlendState::opaque());
        boxes.push_back(viewportPixels(c.viewport, c.width, c.height));
    }

    std::mt19937 seeds(seed);
    int failures = 0, covered_triangles = 0, tie_pixels = 0;
    uint64_t covered_pixels = 0;
    for (int n = 0; n < kTriangles && failures < 5; ++n) {
        const int ci = n % 8 == 7 ? 1 + (n / 8) % 2 : 0;
        Rig& rig = *rigs[ci];
        const Viewport& v = configs[ci].viewport;
        const PixelBox& box = boxes[ci];
        TriangleMaker maker{std::mt19937(seeds()), v.width, v.height};
        const auto pts = maker.make(n % 10);
        glm::vec4 clip[3];
        Fixed f[3];
        for (int k = 0; k < 3; ++k) {
            clip[k] = toClip({pts[k].x + v.topLeftX, pts[k].y + v.topLeftY}, v, float(maker.uni(0, 1)));
            f[k] = toFixed(clip[k], v);
        }
        rig.clear();
        rig.drawClip(clip, Topology::TriangleList);
        ASSERT_EQ(rig.stats().primitivesClipped, 0u) << "triangle " << n << " left the guard band";

        int mismatches = 0, expected_count = 0;
        int first_x = -1, first_y = -1;
        bool first_expected = false;
        for (int y = 0; y < int(rig.height()); ++y) {
            for (int x = 0; x < int(rig.width()); ++x) {
                const bool in_box = x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1;
                const bool expected = in_box && referenceCovers(f, centre(x), centre(y));
                const bool actual = rig.count(x, y) != 0.0f;
                expected_count += expected;
                if (expected != actual) {
                    if (mismatches++ == 0) first_x = x, first_y = y, first_expected = expected;
                }
            }
        }
        // Ties: centres exactly on an edge's line, inside the other two.
        for (int y = box.y0; y <= box.y1; ++y)
            for (int x = box.x0; x <= box.x1; ++x)
                for (int k = 0; k < 3; ++k) {
                    const Fixed &a = f[k], &b = f[(k + 1) % 3];
                    if ((b.x - a.x) * (centre(y) - a.y) == (b.y - a.y) * (centre(x) - a.x) &&
                        rig.count(x, y) != 0)
                        ++tie_pixels;
                }
        if (mismatches) {
            ++failures;
            ADD_FAILURE() << pathName(path) << " triangle " << n << " (kind " << n % 10 << "): " << mismatches
                          << " pixels differ from the reference; first at (" << first_x << ", " << first_y
                          << ") expected " << (first_expected ? "covered" : "empty") << "\n"
                          << describe(clip, f, v);
        }
        EXPECT_EQ(rig.stats().psInvocations, uint64_t(expected_count)) << "triangle " << n << "\n"
                                                                       << describe(clip, f, v);
        covered_triangles += expected_count > 0;
        covered_pixels += uint64_t(expected_count);
    }
    // The mix must actually draw things and hit the tie rule.
    EXPECT_GT(covered_triangles, kTriangles / 2);
    EXPECT_GT(covered_pixels, 1000000u);
    EXPECT_GT(tie_pixels, 1000);
}

TEST(TriangleCoverage, RandomTrianglesMatchBruteForce) {
    expectCoverageMatchesBruteForce(Path::Quads, 20240611);
}

TEST(TriangleCoverage, RandomTrianglesMatchBruteForceEightWide) {
    expectCoverageMatchesBruteForce(Path::Blocks, 20240612);
}

// ---- 2. Watertight fans and grids -----------------------------------------------------------------

// Where a pixel centre lies with respect to a simple polygon (1/256 pixel units), exactly.
enum class Where { Inside, Outside, Boundary };
Where classify(const std::vector<Fixed>& poly, int64_t px, int64_t py) {
    bool inside = false;
    for (size_t i = 0; i < poly.size(); ++i) {
        const Fixed& a = poly[i];
        const Fixed& b = poly[(i + 1) % poly.size()];
        const int64_t cross = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
        if (cross == 0 && px >= std::min(a.x, b.x) && px <= std::max(a.x, b.x) && py >= std::min(a.y, b.y) &&
            py <= std::max(a.y, b.y))
            return Where::Boundary;
        if ((a.y > py) != (b.y > py)) {
            const int64_t lhs = (px - a.x) * (b.y - a.y), rhs = (py - a.y) * (b.x - a.x);
            if (b.y > a.y ? lhs < rhs : lhs > rhs) inside = !inside;
        }
    }
    return inside ? Where::Inside : Where::Outside;
}

// Every pixel strictly inside the polygon counted exactly once, strictly outside never, on its
// boundary at most once. Returns the number of pixels counted once.
int expectExactlyOnce(const Rig& rig, const std::vector<Fixed>& poly, const std::string& what) {
    int once = 0, bad = 0;
    for (int y = 0; y < int(rig.height()); ++y) {
        for (int x = 0; x < int(rig.width()); ++x) {
            const float c = rig.count(x, y);
            once += c == 1.0f;
            const Where w = classify(poly, centre(x), centre(y));
            const bool ok = w == Where::Inside    ? c == 1.0f
                            : w == Where::Outside ? c == 0.0f
                                                  : (c == 0.0f || c == 1.0f);
            if (!ok && bad++ < 5)
                ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") counted " << c
                              << " times, centre "
                              << (w == Where::Inside    ? "inside"
                                  : w == Where::Outside ? "outside"
                                                        : "on the boundary");
        }
    }
    EXPECT_EQ(bad, 0) << what;
    return once;
}

void drawFan(Rig& rig, Screen centrePoint, const std::vector<Screen>& rim, std::mt19937& rng,
             const std::string& what) {
    std::vector<Screen> tris;
    for (size_t k = 0; k < rim.size(); ++k) {
        Screen a = rim[k], b = rim[(k + 1) % rim.size()];
        if (rng() & 1) std::swap(a, b);
        tris.insert(tris.end(), {centrePoint, a, b});
    }
    rig.clear();
    rig.drawScreen(tris, Topology::TriangleList);
    EXPECT_EQ(rig.stats().cPrimitives, rim.size()) << what;
    EXPECT_EQ(rig.stats().primitivesDegenerate, 0u) << what;
    std::vector<Fixed> poly;
    for (const Screen& s : rim) poly.push_back(toFixed(toClip(s, rig.viewport()), rig.viewport()));
    const int once = expectExactlyOnce(rig, poly, what);
    EXPECT_GT(once, 400) << what;
}

TEST(Watertight, FanAroundInteriorPointCoversEachPixelOnce) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        Rig rig(96, 80, path);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> jitter(-0.3, 0.3), radius(12.0, 34.0);
        const Screen c{47.3719, 39.6087};
        std::vector<Screen> rim;
        for (int k = 0; k < 32; ++k) {
            const double a = 2 * std::numbers::pi * (k + jitter(rng)) / 32, r = radius(rng);
            rim.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
        }
        drawFan(rig, c, rim, rng, "awkward fan");
    }
}

TEST(Watertight, FanOnPixelCentresAndCornersCoversEachPixelOnce) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        // Centre on a pixel centre, rim on the half-pixel lattice: spokes through many centres.
        Rig rig(96, 80, path);
        std::mt19937 rng(11);
        const Screen c{48.5, 40.5};
        std::vector<Screen> rim;
        for (int k = 0; k < 32; ++k) {
            const double a = 2 * std::numbers::pi * k / 32, r = k % 2 ? 30.0 : 21.0;
            rim.push_back(
                {std::round(2 * (c.x + r * std::cos(a))) / 2, std::round(2 * (c.y + r * std::sin(a))) / 2});
        }
        drawFan(rig, c, rim, rng, "lattice fan");
    }
}

// An (n+1)×(m+1) lattice of vertices split into 2·n·m triangles, random diagonals and windings.
void drawGrid(Rig& rig, const std::vector<std::vector<Screen>>& vtx, std::mt19937& rng) {
    const size_t rows = vtx.size() - 1, cols = vtx[0].size() - 1;
    std::vector<Screen> tris;
    auto add = [&](Screen a, Screen b, Screen c) {
        if (rng() & 1) std::swap(b, c);
        tris.insert(tris.end(), {a, b, c});
    };
    for (size_t j = 0; j < rows; ++j)
        for (size_t i = 0; i < cols; ++i) {
            const Screen &p00 = vtx[j][i], &p10 = vtx[j][i + 1], &p01 = vtx[j + 1][i],
                         &p11 = vtx[j + 1][i + 1];
            if (rng() & 1) {
                add(p00, p10, p11), add(p00, p11, p01);
            } else {
                add(p00, p10, p01), add(p10, p11, p01);
            }
        }
    rig.clear();
    rig.drawScreen(tris, Topology::TriangleList);
}

std::vector<Fixed> gridOutline(const Rig& rig, const std::vector<std::vector<Screen>>& vtx) {
    const size_t rows = vtx.size() - 1, cols = vtx[0].size() - 1;
    std::vector<Screen> ring;
    for (size_t i = 0; i < cols; ++i) ring.push_back(vtx[0][i]);
    for (size_t j = 0; j < rows; ++j) ring.push_back(vtx[j][cols]);
    for (size_t i = cols; i > 0; --i) ring.push_back(vtx[rows][i]);
    for (size_t j = rows; j > 0; --j) ring.push_back(vtx[j][0]);
    std::vector<Fixed> poly;
    for (const Screen& s : ring) poly.push_back(toFixed(toClip(s, rig.viewport()), rig.viewport()));
    return poly;
}

TEST(Watertight, JitteredGridCoversEachPixelOnce) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        Rig rig(160, 136, path);  // several tiles
        std::mt19937 rng(3);
        constexpr int kCols = 19, kRows = 17;
        const double cw = 7.31, ch = 6.77;
        std::uniform_real_distribution<double> jitter(-0.2, 0.2);
        std::vector<std::vector<Screen>> vtx(kRows + 1, std::vector<Screen>(kCols + 1));
        for (int j = 0; j <= kRows; ++j)
            for (int i = 0; i <= kCols; ++i)
                vtx[j][i] = {5.137 + (i + jitter(rng)) * cw, 3.911 + (j + jitter(rng)) * ch};
        drawGrid(rig, vtx, rng);
        EXPECT_EQ(rig.stats().cPrimitives, 2u * kCols * kRows);
        const int once = expectExactlyOnce(rig, gridOutline(rig, vtx), "jittered grid");
        EXPECT_GT(once, 15000);
    }
}

TEST(Watertight, GridOnPixelCentresCoversHalfOpenRectangleOnce) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        // Shared vertices exactly on pixel centres: every internal edge and the outline pass through
        // rows and columns of centres. The top-left rule gives the half-open rectangle
        // [x0, x1) × [y0, y1) of centres, each once.
        Rig rig(160, 136, path);
        std::mt19937 rng(5);
        constexpr int kCols = 12, kRows = 10;
        const double x0 = 6.5, y0 = 9.5, cw = 11, ch = 12;
        std::vector<std::vector<Screen>> vtx(kRows + 1, std::vector<Screen>(kCols + 1));
        for (int j = 0; j <= kRows; ++j)
            for (int i = 0; i <= kCols; ++i) vtx[j][i] = {x0 + i * cw, y0 + j * ch};
        drawGrid(rig, vtx, rng);
        int bad = 0;
        for (int y = 0; y < int(rig.height()); ++y)
            for (int x = 0; x < int(rig.width()); ++x) {
                const bool in =
                    x + 0.5 >= x0 && x + 0.5 < x0 + kCols * cw && y + 0.5 >= y0 && y + 0.5 < y0 + kRows * ch;
                if (rig.count(x, y) != (in ? 1.0f : 0.0f) && bad++ < 5)
                    ADD_FAILURE() << "pixel (" << x << ", " << y << ") counted " << rig.count(x, y)
                                  << ", expected " << in;
            }
        EXPECT_EQ(bad, 0);
        EXPECT_EQ(rig.total(), kCols * int(cw) * kRows * int(ch));
    }
}

TEST(Watertight, GridBeyondTheTargetCoversEveryPixelOnce) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        // A jittered grid reaching past all four sides of the target (and of several tiles).
        Rig rig(150, 100, path);
        std::mt19937 rng(9);
        constexpr int kCols = 9, kRows = 7;
        std::uniform_real_distribution<double> jitter(-0.2, 0.2);
        std::vector<std::vector<Screen>> vtx(kRows + 1, std::vector<Screen>(kCols + 1));
        for (int j = 0; j <= kRows; ++j)
            for (int i = 0; i <= kCols; ++i)
                vtx[j][i] = {-31.7 + (i + (i % kCols ? jitter(rng) : 0)) * 23.9,
                             -27.3 + (j + (j % kRows ? jitter(rng) : 0)) * 21.3};
        drawGrid(rig, vtx, rng);
        for (int y = 0; y < int(rig.height()); ++y)
            for (int x = 0; x < int(rig.width()); ++x) ASSERT_EQ(rig.count(x, y), 1.0f) << x << ", " << y;
    }
}

// ---- 3. The top-left rule by hand -----------------------------------------------------------------

// Draws one triangle (both windings) into a 16×16 target and checks the covered set against
// `expected(i, j)`.
template <class Expected>
void expectTriangle(Screen a, Screen b, Screen c, Expected expected, const std::string& what) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        for (int winding = 0; winding < 2; ++winding) {
            Rig rig(16, 16, path);
            rig.drawScreen({a, winding ? c : b, winding ? b : c}, Topology::TriangleList);
            for (int j = 0; j < 16; ++j)
                for (int i = 0; i < 16; ++i)
                    EXPECT_EQ(rig.count(i, j), expected(i, j) ? 1.0f : 0.0f)
                        << what << (winding ? " (reversed)" : "") << ": pixel (" << i << ", " << j << ")";
        }
    }
}

TEST(TopLeftRule, TopEdgeOnCentresIsCoveredBottomEdgeIsNot) {
    // Top edge y = 3.5 through row 3's centres, left edge x = 2.5 through column 2's; the
    // hypotenuse x + y = 14 (a right edge) through centres (10.5, 3.5), (9.5, 4.5)...
    expectTriangle(
        {2.5, 3.5}, {10.5, 3.5}, {2.5, 11.5}, [](int i, int j) { return i >= 2 && j >= 3 && i + j + 1 < 14; },
        "top-left corner triangle");
    // Bottom edge y = 11.5 through row 11's centres: not a top edge, row 11 is empty.
    // Hypotenuse x = y - 1 with the interior to its left (a right edge) through (2.5, 3.5)...
    expectTriangle(
        {2.5, 3.5}, {10.5, 11.5}, {2.5, 11.5},
        [](int i, int j) { return i >= 2 && j <= 10 && i + 0.5 < j + 0.5 - 1; }, "bottom edge triangle");
    {
        Rig rig(16, 16);
        rig.drawScreen({{2.5, 3.5}, {10.5, 3.5}, {2.5, 11.5}}, Topology::TriangleList);
        for (int i = 0; i < 16; ++i)
            EXPECT_EQ(rig.count(i, 3), i >= 2 && i <= 9 ? 1.0f : 0.0f) << "row 3, x " << i;
    }
}

TEST(TopLeftRule, LeftEdgeOnCentresIsCoveredRightEdgeIsNot) {
    // Right vertical edge x = 13.5 through column 13's centres: column 13 stays empty.
    // Top edge y = 3.5 covered; the hypotenuse x + y = 17 (a left edge) covered.
    expectTriangle(
        {5.5, 3.5}, {13.5, 3.5}, {13.5, 11.5},
        [](int i, int j) { return i <= 12 && j >= 3 && (i + 0.5) >= (j + 0.5) + 2; }, "right edge triangle");
    // A tall thin triangle: left edge x = 4.5 (column 4 covered), top edge y = 2.5 (row 2
    // covered), hypotenuse 5(x - 4.5) + (y - 2.5) = 10 a right edge through (6.5, 2.5), (5.5, 7.5).
    expectTriangle(
        {4.5, 2.5}, {6.5, 2.5}, {4.5, 12.5},
        [](int i, int j) {
            const double x = i + 0.5, y = j + 0.5;
            return x >= 4.5 && y >= 2.5 && 5 * (x - 4.5) + (y - 2.5) < 10;  // hypotenuse: a right edge
        },
        "thin triangle");
    {
        Rig rig(16, 16);
        rig.drawScreen({{13.5, 3.5}, {13.5, 11.5}, {5.5, 3.5}}, Topology::TriangleList);
        for (int j = 0; j < 16; ++j) EXPECT_EQ(rig.count(13, j), 0.0f) << "column 13, y " << j;
        EXPECT_EQ(rig.count(12, 3), 1.0f);
    }
}

TEST(TopLeftRule, SharedVertexOnACentreIsCoveredOnce) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        // Four triangles around (8.5, 8.5), a pixel centre: exactly one takes it.
        Rig rig(16, 16, path);
        const Screen c{8.5, 8.5};
        rig.drawScreen({c,
                        {2.5, 2.5},
                        {14.5, 2.5},
                        c,
                        {14.5, 2.5},
                        {14.5, 14.5},
                        c,
                        {14.5, 14.5},
                        {2.5, 14.5},
                        c,
                        {2.5, 14.5},
                        {2.5, 2.5}},
                       Topology::TriangleList);
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                const bool in = i >= 2 && i < 14 && j >= 2 && j < 14;
                EXPECT_EQ(rig.count(i, j), in ? 1.0f : 0.0f) << i << ", " << j;
            }
    }
}

// ---- 4. Culling -----------------------------------------------------------------------------------

TEST(Culling, CullModeAgainstWindingAndFrontCounterClockwise) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        // On screen, y down: (2,2) -> (12,2) -> (2,12) turns clockwise.
        const std::vector<Screen> cw = {{2, 2}, {12, 2}, {2, 12}};
        const std::vector<Screen> ccw = {{2, 2}, {2, 12}, {12, 2}};
        for (int winding = 0; winding < 2; ++winding)
            for (bool frontCcw : {false, true})
                for (CullMode cull : {CullMode::None, CullMode::Front, CullMode::Back}) {
                    Rig rig(16, 16, path);
                    RasterizerState rs;
                    rs.cullMode = cull;
                    rs.frontCounterClockwise = frontCcw;
                    rig.ctx().setRasterizerState(rs);
                    rig.drawScreen(winding == 0 ? cw : ccw, Topology::TriangleList);
                    const bool clockwise = winding == 0;
                    const bool front = frontCcw ? !clockwise : clockwise;
                    const bool drawn = cull == CullMode::None || (cull == CullMode::Back && front) ||
                                       (cull == CullMode::Front && !front);
                    const std::string what = std::string(clockwise ? "cw" : "ccw") +
                                             " frontCCW=" + (frontCcw ? "1" : "0") +
                                             " cull=" + std::string(name(cull));
                    EXPECT_EQ(rig.stats().primitivesCulled, drawn ? 0u : 1u) << what;
                    // Centres (i + .5, j + .5) with i, j >= 2 and i + j < 13 (the hypotenuse x + y = 14
                    // is a right edge): 45.
                    EXPECT_EQ(rig.total(), drawn ? 45 : 0) << what;
                    EXPECT_EQ(rig.stats().psInvocations, drawn ? 45u : 0u) << what;
                }
    }
}

// ---- 5. Points and lines --------------------------------------------------------------------------

TEST(Points, CoverThePixelWhoseCentreIsInHalfOpenSquare) {
    struct Case {
        double x, y;
        int px, py;
    };
    const Case cases[] = {
        {3.5, 4.5, 3, 4},               // on a centre
        {3.0, 4.0, 2, 3},               // on a corner: [2.5, 3.5) holds centre 2.5
        {3.25, 4.75, 3, 4},             // fractional
        {3.75, 4.25, 3, 4},             //
        {3.0 + 1 / 256.0, 4.0, 3, 3},   // one subpixel past the corner
        {3.0 + 1 / 1024.0, 5.0, 2, 4},  // snaps back onto the corner
        {0.0, 0.0, -1, -1},             // off the target: nothing
        {15.99, 15.99, 15, 15},         // last pixel
        {16.0, 8.5, 15, 8},             // right edge of the target: centre 15.5 in [15.5, 16.5)
    };
    for (const Case& c : cases) {
        Rig rig(16, 16);
        rig.drawScreen({{c.x, c.y}}, Topology::PointList);
        const bool visible = c.px >= 0 && c.py >= 0;
        EXPECT_EQ(rig.total(), visible ? 1 : 0) << c.x << ", " << c.y;
        if (visible) {
            EXPECT_EQ(rig.count(c.px, c.py), 1.0f) << c.x << ", " << c.y;
        }
    }
    // All 16 sub-positions of a pixel's quarter grid in one draw.
    Rig rig(16, 16);
    std::vector<Screen> pts;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) pts.push_back({6.0 + a * 0.25, 9.0 + b * 0.25});
    rig.drawScreen(pts, Topology::PointList);
    EXPECT_EQ(rig.count(5, 8), 1.0f);  // x = 6.0, y = 9.0
    EXPECT_EQ(rig.count(6, 8), 3.0f);  // x in (6, 7), y = 9.0
    EXPECT_EQ(rig.count(5, 9), 3.0f);
    EXPECT_EQ(rig.count(6, 9), 9.0f);
    EXPECT_EQ(rig.total(), 16);
}

std::vector<int> rowPixels(const Rig& rig, int y) {
    std::vector<int> xs;
    for (int x = 0; x < int(rig.width()); ++x)
        if (rig.count(x, y) != 0) xs.push_back(x);
    return xs;
}

TEST(Lines, HorizontalAndVerticalAreHalfOpen) {
    {
        Rig rig(16, 16);
        rig.drawScreen({{2.5, 3.5}, {10.5, 3.5}}, Topology::LineList);
        EXPECT_EQ(rowPixels(rig, 3), (std::vector<int>{2, 3, 4, 5, 6, 7, 8, 9}));
        EXPECT_EQ(rig.total(), 8);
    }
    {  // reversed: the end left open is now x = 2.5
        Rig rig(16, 16);
        rig.drawScreen({{10.5, 3.5}, {2.5, 3.5}}, Topology::LineList);
        EXPECT_EQ(rowPixels(rig, 3), (std::vector<int>{3, 4, 5, 6, 7, 8, 9, 10}));
        EXPECT_EQ(rig.total(), 8);
    }
    {  // between two rows of centres: the tie goes to the larger row
        Rig rig(16, 16);
        rig.drawScreen({{2.5, 4.0}, {6.5, 4.0}}, Topology::LineList);
        EXPECT_EQ(rowPixels(rig, 4), (std::vector<int>{2, 3, 4, 5}));
        EXPECT_EQ(rig.total(), 4);
    }
    {
        Rig rig(16, 16);
        rig.drawScreen({{5.5, 1.5}, {5.5, 9.5}}, Topology::LineList);
        for (int y = 0; y < 16; ++y) EXPECT_EQ(rig.count(5, y), y >= 1 && y <= 8 ? 1.0f : 0.0f) << y;
        EXPECT_EQ(rig.total(), 8);
    }
}

TEST(Lines, DiagonalHasOnePixelPerColumn) {
    Rig rig(16, 16);
    rig.drawScreen({{2.5, 2.5}, {12.5, 12.5}}, Topology::LineList);
    for (int i = 2; i < 12; ++i) EXPECT_EQ(rig.count(i, i), 1.0f) << i;
    EXPECT_EQ(rig.total(), 10);
}

TEST(Lines, RandomLinesTakeTheNearestCentrePerMajorStep) {
    // 150×100: lines cross tile borders. Per the rule in stages/5_setup.hpp: along the major axis the
    // centres in [start, end) in the direction of travel, on the minor axis the pixel whose centre
    // is nearest the line (floor of the line's minor coordinate there: ties go up).
    constexpr int W = 150, H = 100;
    Rig rig(W, H);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> ux(-20.0, W + 20.0), uy(-20.0, H + 20.0);
    int drawn = 0;
    for (int n = 0; n < 300; ++n) {
        Screen a{ux(rng), uy(rng)}, b{ux(rng), uy(rng)};
        if (n % 3 == 0)
            a = {std::round(a.x) + 0.5, std::round(a.y) + 0.5}, b = {std::round(b.x), std::round(b.y) + 0.5};
        const Fixed fa = toFixed(toClip(a, rig.viewport()), rig.viewport());
        const Fixed fb = toFixed(toClip(b, rig.viewport()), rig.viewport());
        if (fa.x == fb.x && fa.y == fb.y) continue;
        rig.clear();
        rig.drawScreen({a, b}, Topology::LineList);
        const bool x_major = std::abs(fb.x - fa.x) >= std::abs(fb.y - fa.y);
        const int64_t a0 = x_major ? fa.x : fa.y, a1 = x_major ? fb.x : fb.y;
        const int64_t b0 = x_major ? fa.y : fa.x, b1 = x_major ? fb.y : fb.x;
        const int majors = x_major ? W : H, minors = x_major ? H : W;
        auto at = [&](int major, int minor) {
            return x_major ? rig.count(major, minor) : rig.count(minor, major);
        };
        int expected_total = 0;
        for (int i = 0; i < majors; ++i) {
            const int64_t c = centre(i);
            const bool in = a1 > a0 ? (c >= a0 && c < a1) : (c <= a0 && c > a1);
            int hits = 0, where = -1;
            for (int j = 0; j < minors; ++j)
                if (at(i, j) != 0) ++hits, where = j;
            const double m = (double(b0) + double(c - a0) / double(a1 - a0) * double(b1 - b0)) / 256.0;
            const int expected = int(std::floor(m));
            if (!in || expected < 0 || expected >= minors) {
                EXPECT_EQ(hits, 0) << "line " << n << " step " << i;
                continue;
            }
            ++expected_total;
            EXPECT_EQ(hits, 1) << "line " << n << " step " << i;
            EXPECT_EQ(where, expected) << "line " << n << " step " << i << " minor " << m;
            EXPECT_LE(std::abs(where + 0.5 - m), 0.5) << "line " << n << " step " << i;
        }
        EXPECT_EQ(rig.total(), expected_total) << "line " << n;
        drawn += expected_total > 0;
    }
    EXPECT_GT(drawn, 200);
}

TEST(Lines, StripSegmentsShareNoPixel) {
    Rig rig(16, 16);
    rig.drawScreen({{2.5, 3.5}, {10.5, 3.5}, {10.5, 9.5}, {4.5, 9.5}}, Topology::LineStrip);
    EXPECT_EQ(rowPixels(rig, 3), (std::vector<int>{2, 3, 4, 5, 6, 7, 8, 9, 10}));
    for (int y = 3; y < 9; ++y) EXPECT_EQ(rig.count(10, y), 1.0f) << y;
    EXPECT_EQ(rowPixels(rig, 9), (std::vector<int>{5, 6, 7, 8, 9, 10}));
    EXPECT_EQ(rig.total(), 8 + 6 + 6);
}

// ---- 6. Depth -------------------------------------------------------------------------------------

TEST(Depth, InterpolatedLinearlyInScreenSpace) {
    for (const Path path : kPaths) {
        SCOPED_TRACE(pathName(path));
        struct Case {
            Screen p[3];
            float z[3];
            float minDepth, maxDepth;
        };
        const Case cases[] = {
            {{{3.25, 2.75}, {60.5, 10.125}, {17.0, 58.375}}, {0.1f, 0.9f, 0.45f}, 0.0f, 1.0f},
            {{{62.0, 1.0}, {2.0, 30.5}, {40.75, 63.0}}, {0.75f, 0.0f, 1.0f}, 0.25f, 0.75f},
            {{{-40.0, -20.0}, {120.0, 8.0}, {10.0, 130.0}}, {0.3f, 0.6f, 0.05f}, 0.0f, 1.0f},
        };
        for (const Case& c : cases) {
            Rig rig(64, 64, path);
            DepthTarget depth(64, 64);
            depth.clear(1.0f);
            rig.ctx().setRenderTargets(&rig.color(), &depth);
            rig.setViewport({0, 0, 64, 64, c.minDepth, c.maxDepth});
            std::vector<glm::vec4> clip;
            double X[3], Y[3], Z[3];
            for (int k = 0; k < 3; ++k) {
                clip.push_back(toClip(c.p[k], rig.viewport(), c.z[k]));
                const Fixed f = toFixed(clip.back(), rig.viewport());
                X[k] = f.x / 256.0, Y[k] = f.y / 256.0;
                Z[k] = c.minDepth + double(c.z[k]) * (double(c.maxDepth) - c.minDepth);
            }
            rig.drawClip(clip, Topology::TriangleList);
            // The plane through the three snapped vertices: z = Z0 + a (x - X0) + b (y - Y0).
            const double det = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
            const double a = ((Z[1] - Z[0]) * (Y[2] - Y[0]) - (Z[2] - Z[0]) * (Y[1] - Y[0])) / det;
            const double b = ((X[1] - X[0]) * (Z[2] - Z[0]) - (X[2] - X[0]) * (Z[1] - Z[0])) / det;
            int checked = 0;
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 64; ++x) {
                    if (rig.count(x, y) == 0) {
                        EXPECT_EQ(depth.load(x, y), 1.0f);
                        continue;
                    }
                    const double expected = Z[0] + a * (x + 0.5 - X[0]) + b * (y + 0.5 - Y[0]);
                    EXPECT_NEAR(depth.load(x, y), expected, 1e-6) << x << ", " << y;
                    EXPECT_GE(depth.load(x, y), c.minDepth);
                    EXPECT_LE(depth.load(x, y), c.maxDepth);
                    ++checked;
                }
            EXPECT_GT(checked, 500);
        }
    }
}

// ---- 7, 8. Determinism and the reference pipeline -------------------------------------------------

std::vector<ColorIn> randomScene(uint32_t seed, int triangles, double width, double height, double size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<ColorIn> v;
    for (int t = 0; t < triangles; ++t) {
        const double cx = -0.1 * width + 1.2 * width * u(rng), cy = -0.1 * height + 1.2 * height * u(rng);
        const float z = float(u(rng));
        const glm::vec4 color(float(u(rng) * 0.1), float(u(rng) * 0.1), float(u(rng) * 0.1),
                              float(0.2 + 0.6 * u(rng)));
        for (int k = 0; k < 3; ++k) {
            const double x = cx + size * (u(rng) - 0.5), y = cy + size * (u(rng) - 0.5);
            const float w = float(0.5 + 1.5 * u(rng));
            const glm::vec4 ndc(float(2 * x / width - 1), float(1 - 2 * y / height),
                                float(std::clamp(z + 0.2 * (u(rng) - 0.5), 0.0, 1.0)), 1.0f);
            glm::vec4 c = color;
            c[k] += 0.05f;
            v.push_back({ndc * w, c});
        }
    }
    return v;
}

struct SceneImage {
    RenderTarget color;
    DepthTarget depth;
    PipelineStatistics stats;
};

SceneImage renderScene(const std::vector<ColorIn>& scene, ContextOptions options, Format format,
                       const BlendState& blend, uint32_t width, uint32_t height, Path path = Path::Quads) {
    SceneImage img{RenderTarget(width, height, format), DepthTarget(width, height), {}};
    img.color.clear(glm::vec4(0.0f));
    img.depth.clear(1.0f);
    Context ctx(options);
    const InputLayout layout(kColorLayout);
    const VertexBuffer vb = VertexBuffer::create(scene);
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::TriangleList);
    ctx.setRenderTargets(&img.color, &img.depth);
    ctx.setViewport({0, 0, float(width), float(height), 0, 1});
    ctx.setRasterizerState(noCull());
    ctx.setBlendState(blend);
    DepthStencilState ds;
    ds.depthFunc = ComparisonFunc::LessEqual;
    ctx.setDepthStencilState(ds);
    if (format == Format::R32G32B32A32_FLOAT)
        ctx.draw(VsColor{}, PsColorCount{}, uint32_t(scene.size()));
    else if (path == Path::Blocks)
        ctx.draw(VsColorT{}, PsColorWide{}, uint32_t(scene.size()));
    else
        ctx.draw(VsColor{}, PsColor{}, uint32_t(scene.size()));
    img.stats = ctx.drawStatistics();
    return img;
}

TEST(Determinism, SameImageForAnyThreadCount) {
    struct Scene {
        int triangles;
        double size;
    };
    // 2 000 large overlapping triangles; 20 000 small ones, enough for the geometry to be split
    // into a different number of chunks for each thread count.
    for (const Scene& s : {Scene{2000, 60.0}, Scene{20000, 12.0}}) {
        const auto scene = randomScene(42, s.triangles, 200, 150, s.size);
        const SceneImage one =
            renderScene(scene, {.threads = 1}, Format::R32G32B32A32_FLOAT, countingBlend(), 200, 150);
        EXPECT_GT(one.stats.psInvocations, 20000u);
        for (unsigned threads : {2u, 8u}) {
            const SceneImage many = renderScene(scene, {.threads = threads}, Format::R32G32B32A32_FLOAT,
                                                countingBlend(), 200, 150);
            EXPECT_TRUE(many.color == one.color) << s.triangles << " triangles, " << threads << " threads";
            EXPECT_TRUE(many.depth == one.depth) << s.triangles << " triangles, " << threads << " threads";
            EXPECT_EQ(many.stats.psInvocations, one.stats.psInvocations) << threads << " threads";
            EXPECT_EQ(many.stats.cPrimitives, one.stats.cPrimitives) << threads << " threads";
            EXPECT_EQ(many.stats.fragmentsEarlyDepthKilled, one.stats.fragmentsEarlyDepthKilled) << threads;
        }
        // RGBA8, the lecture's additive blend, eight-wide shading.
        const SceneImage one8 = renderScene(scene, {.threads = 1}, Format::R8G8B8A8_UNORM,
                                            BlendState::additive(), 200, 150, Path::Blocks);
        for (unsigned threads : {2u, 8u}) {
            const SceneImage many8 = renderScene(scene, {.threads = threads}, Format::R8G8B8A8_UNORM,
                                                 BlendState::additive(), 200, 150, Path::Blocks);
            EXPECT_TRUE(many8.color == one8.color)
                << s.triangles << " triangles, RGBA8, " << threads << " threads";
            EXPECT_TRUE(many8.depth == one8.depth)
                << s.triangles << " triangles, RGBA8, " << threads << " threads";
            EXPECT_EQ(many8.stats.psInvocations, one8.stats.psInvocations) << threads << " threads";
        }
    }
}

TEST(ReferencePipeline, SameCoverageAndColoursWithin1Over255) {
    const auto scene = randomScene(99, 2000, 200, 150, 60.0);
    // Float target, One + One: alpha counts the fragments that passed the depth test.
    const SceneImage fast =
        renderScene(scene, {.threads = 2}, Format::R32G32B32A32_FLOAT, countingBlend(), 200, 150);
    const SceneImage ref = renderScene(scene, {.threads = 2, .reference = true}, Format::R32G32B32A32_FLOAT,
                                       countingBlend(), 200, 150);
    int bad = 0, covered = 0;
    for (uint32_t y = 0; y < 150; ++y)
        for (uint32_t x = 0; x < 200; ++x) {
            const glm::vec4 f = fast.color.load(x, y), r = ref.color.load(x, y);
            covered += f.a > 0;
            if (f.a != r.a && bad++ < 5)
                ADD_FAILURE() << "count at (" << x << ", " << y << "): " << f.a << " vs " << r.a;
            for (int c = 0; c < 3; ++c)
                if (!(std::abs(f[c] - r[c]) <= 1.0f / 255) && bad++ < 5)
                    ADD_FAILURE() << "channel " << c << " at (" << x << ", " << y << "): " << f[c] << " vs "
                                  << r[c];
            if (fast.depth.load(x, y) != ref.depth.load(x, y) && bad++ < 5)
                ADD_FAILURE() << "depth at (" << x << ", " << y << "): " << fast.depth.load(x, y) << " vs "
                              << ref.depth.load(x, y);
        }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(covered, 20000);
    // The fast pipeline tests depth before shading, the reference after.
    EXPECT_EQ(fast.stats.psInvocations, ref.stats.psInvocations - ref.stats.fragmentsLateDepthKilled);

    // RGBA8 with the lecture's additive blend: the fast RGBA8 blender, quad by quad and eight wide,
    // against double.
    const SceneImage ref8 = renderScene(scene, {.threads = 2, .reference = true}, Format::R8G8B8A8_UNORM,
                                        BlendState::additive(), 200, 150);
    for (const Path path : kPaths) {
        const SceneImage fast8 = renderScene(scene, {.threads = 2}, Format::R8G8B8A8_UNORM,
                                             BlendState::additive(), 200, 150, path);
        int bad8 = 0;
        for (uint32_t y = 0; y < 150; ++y)
            for (uint32_t x = 0; x < 200; ++x) {
                const glm::vec4 f = fast8.color.load(x, y), r = ref8.color.load(x, y);
                for (int c = 0; c < 4; ++c)
                    if (!(std::abs(f[c] - r[c]) <= 1.0f / 255 + 1e-6f) && bad8++ < 5)
                        ADD_FAILURE() << pathName(path) << " RGBA8 channel " << c << " at (" << x << ", " << y
                                      << "): " << f[c] * 255 << " vs " << r[c] * 255;
                if (fast8.depth.load(x, y) != ref8.depth.load(x, y) && bad8++ < 5)
                    ADD_FAILURE() << pathName(path) << " RGBA8 depth at (" << x << ", " << y << ")";
            }
        EXPECT_EQ(bad8, 0) << pathName(path);
        EXPECT_EQ(fast8.stats.psInvocations, ref8.stats.psInvocations - ref8.stats.fragmentsLateDepthKilled)
            << pathName(path);
    }
}

}  // namespace
}  // namespace raster
