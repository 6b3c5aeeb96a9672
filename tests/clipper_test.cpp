// Clipping: the clipper unit on hand-made vertices, and through the pipeline the near and far
// planes, the guard band, trivial rejection, non-finite positions and watertightness after clipping.
#include "raster/stages/4_clipper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"

namespace raster {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- The clipper unit -----------------------------------------------------------------------------

struct V {
    glm::vec4 position;
    float a;
};

// An attribute linear in clip space: every vertex the clipper makes must keep it.
float linearAttribute(const glm::vec4& p) {
    return 3 * p.x + 5 * p.y + 7 * p.z + 11 * p.w;
}
V linearVertex(const glm::vec4& p) {
    return {p, linearAttribute(p)};
}

std::vector<std::array<V, 3>> clipTriangle(const V& v0, const V& v1, const V& v2, uint32_t cut,
                                           const ClipPlanes& planes = {}, int* returned = nullptr) {
    const V* const in[3] = {&v0, &v1, &v2};
    std::vector<std::array<V, 3>> out;
    const int n = clipPrimitive<3>(in, cut, planes, [&](const V* const* t) {
        out.push_back({*t[0], *t[1], *t[2]});
    });
    if (returned) *returned = n;
    EXPECT_EQ(size_t(n), out.size());
    return out;
}

// Twice the signed area in NDC (x/w, y/w).
double signedArea(const std::array<V, 3>& t) {
    auto ndc = [](const V& v) {
        return glm::dvec2(v.position.x / v.position.w, v.position.y / v.position.w);
    };
    const glm::dvec2 a = ndc(t[0]), b = ndc(t[1]), c = ndc(t[2]);
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool sameBits(const V& a, const V& b) {
    return std::memcmp(&a, &b, sizeof(V)) == 0;
}

std::vector<V> distinctVertices(const std::vector<std::array<V, 3>>& tris) {
    std::vector<V> out;
    for (const auto& t : tris)
        for (const V& v : t)
            if (std::none_of(out.begin(), out.end(), [&](const V& o) { return sameBits(o, v); }))
                out.push_back(v);
    return out;
}

void expectVertex(const V& v, const glm::vec4& p, float a, const std::string& what) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(v.position[c], p[c], 1e-6f) << what << " component " << c;
    EXPECT_NEAR(v.a, a, 1e-5f) << what << " attribute";
}

const V* findNear(const std::vector<V>& vs, const glm::vec4& p) {
    for (const V& v : vs)
        if (glm::all(glm::lessThan(glm::abs(v.position - p), glm::vec4(1e-5f)))) return &v;
    return nullptr;
}

TEST(ClipPrimitive, OneVertexBehindNearBecomesAQuadOfTwoTriangles) {
    // v0 has z < 0. The cuts, from the inside end: on v1 -> v0, t = 3 / (3 + 1) = 0.75:
    // (0.5, 0, 0, 1.75), a = 10 - 0.75·10 = 2.5; on v2 -> v0, t = 1 / 2: (0, 1, 0, 1.5), a = 10.
    const V v0{{0, 0, -1, 1}, 0}, v1{{2, 0, 3, 4}, 10}, v2{{0, 2, 1, 2}, 20};
    int returned = 0;
    const auto tris = clipTriangle(v0, v1, v2, kClipNear, {}, &returned);
    ASSERT_EQ(returned, 2);
    const auto verts = distinctVertices(tris);
    ASSERT_EQ(verts.size(), 4u);
    const V* c01 = findNear(verts, {0.5f, 0, 0, 1.75f});
    const V* c20 = findNear(verts, {0, 1, 0, 1.5f});
    ASSERT_NE(c01, nullptr);
    ASSERT_NE(c20, nullptr);
    EXPECT_NEAR(c01->a, 2.5f, 1e-6f);
    EXPECT_NEAR(c20->a, 10.0f, 1e-6f);
    EXPECT_NE(findNear(verts, v1.position), nullptr);
    EXPECT_NE(findNear(verts, v2.position), nullptr);
    // A fan: both triangles start at the same vertex; the winding is kept.
    EXPECT_TRUE(sameBits(tris[0][0], tris[1][0]));
    const double area = signedArea({v0, v1, v2});
    for (const auto& t : tris) {
        EXPECT_GT(signedArea(t) * area, 0.0);
        for (const V& v : t) EXPECT_GE(v.position.z, 0.0f);
    }
}

TEST(ClipPrimitive, TwoVerticesBehindNearLeaveOneTriangle) {
    // Only v2 inside: cuts on v2 -> v0 (t = 2/3) and v2 -> v1 (t = 1/2).
    const V v0{{-1, 0, -1, 1}, 1}, v1{{1, 0, -2, 1}, 2}, v2{{0, 1, 2, 3}, 4};
    const auto tris = clipTriangle(v0, v1, v2, kClipNear);
    ASSERT_EQ(tris.size(), 1u);
    const auto verts = distinctVertices(tris);
    ASSERT_EQ(verts.size(), 3u);
    // v2 + 2/3 (v0 - v2) = (-2/3, 1/3, 0, 5/3), a = 4 - 2 = 2; v2 + 1/2 (v1 - v2) = (0.5, 0.5, 0, 2), a = 3.
    const V* a = findNear(verts, {-2.0f / 3, 1.0f / 3, 0, 5.0f / 3});
    const V* b = findNear(verts, {0.5f, 0.5f, 0, 2});
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    EXPECT_NEAR(a->a, 2.0f, 1e-6f);
    EXPECT_NEAR(b->a, 3.0f, 1e-6f);
    EXPECT_NE(findNear(verts, v2.position), nullptr);
    EXPECT_GT(signedArea(tris[0]) * signedArea({v0, v1, v2}), 0.0);
}

TEST(ClipPrimitive, InsideUnchangedOutsideGone) {
    const V v0{{0, 0, 0.5f, 1}, 1}, v1{{1, 0, 0.25f, 1}, 2}, v2{{0, 1, 0.75f, 1}, 3};
    const auto tris = clipTriangle(v0, v1, v2, kClipNear | kClipFar);
    ASSERT_EQ(tris.size(), 1u);
    EXPECT_TRUE(sameBits(tris[0][0], v0));
    EXPECT_TRUE(sameBits(tris[0][1], v1));
    EXPECT_TRUE(sameBits(tris[0][2], v2));

    const V w0{{0, 0, -0.5f, 1}, 1}, w1{{1, 0, -0.25f, 1}, 2}, w2{{0, 1, -0.75f, 1}, 3};
    EXPECT_TRUE(clipTriangle(w0, w1, w2, kClipNear).empty());
    // A vertex exactly on the plane (distance 0) counts as inside.
    const V on{{0, 0, 0, 1}, 5};
    const auto touching = clipTriangle(on, w1, w2, kClipNear);
    EXPECT_TRUE(touching.empty() || std::all_of(touching.begin(), touching.end(), [](const auto& t) {
                    return std::abs(signedArea(t)) == 0.0;
                }));
}

TEST(ClipPrimitive, NearAndFarTogetherMakeAPentagon) {
    const ClipPlanes planes;  // depthClip on
    const V v0 = linearVertex({0, 0, -1, 1}), v1 = linearVertex({1, 0, 2, 1}),
            v2 = linearVertex({0, 1, 0.5f, 1});
    const auto tris = clipTriangle(v0, v1, v2, kClipNear | kClipFar, planes);
    ASSERT_EQ(tris.size(), 3u);
    const auto verts = distinctVertices(tris);
    EXPECT_EQ(verts.size(), 5u);
    int on_near = 0, on_far = 0;
    for (const V& v : verts) {
        EXPECT_GE(v.position.z, -1e-6f);
        EXPECT_LE(v.position.z, v.position.w + 1e-6f);
        on_near += std::abs(v.position.z) < 1e-6f;
        on_far += std::abs(v.position.w - v.position.z) < 1e-6f;
        EXPECT_NEAR(v.a, linearAttribute(v.position), 1e-5f) << "not linear in clip space";
    }
    EXPECT_EQ(on_near, 2);
    EXPECT_EQ(on_far, 2);
    for (const auto& t : tris) EXPECT_GT(signedArea(t) * signedArea({v0, v1, v2}), 0.0);
}

TEST(ClipPrimitive, GuardPlanesAreScaledByW) {
    ClipPlanes planes;
    planes.guardX = 2, planes.guardY = 3;
    // v1 at x = 8 with w = 2 is beyond x = 2w = 4.
    const V v0 = linearVertex({0, 0, 0.5f, 1}), v1 = linearVertex({8, 0, 0.5f, 2}),
            v2 = linearVertex({0, 1, 0.5f, 1});
    ASSERT_EQ(outcode(v1.position, planes) & kClipPlanesMask, uint32_t(kClipGuardRight));
    ASSERT_EQ(outcode(v0.position, planes) & kClipPlanesMask, 0u);
    const auto tris = clipTriangle(v0, v1, v2, kClipGuardRight, planes);
    ASSERT_EQ(tris.size(), 2u);
    int on_plane = 0;
    for (const V& v : distinctVertices(tris)) {
        EXPECT_LE(v.position.x, 2 * v.position.w + 1e-5f);
        on_plane += std::abs(v.position.x - 2 * v.position.w) < 1e-5f;
        EXPECT_NEAR(v.a, linearAttribute(v.position), 1e-5f);
    }
    EXPECT_EQ(on_plane, 2);
    // On v0 -> v1, distance 2·w - x goes 2 -> -4: t = 1/3, (8/3, 0, 0.5, 4/3).
    EXPECT_NE(findNear(distinctVertices(tris), {8.0f / 3, 0, 0.5f, 4.0f / 3}), nullptr);
}

TEST(ClipPrimitive, SharedEdgeGetsBitIdenticalCutsWhicheverWayItRuns) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f), pw(0.3f, 3.0f);
    for (int n = 0; n < 500; ++n) {
        // Edge p -> q crosses the near plane; r and s lie on either side of it.
        const V p = linearVertex({u(rng), u(rng), -std::abs(u(rng)) - 0.01f, pw(rng)});
        const V q = linearVertex({u(rng), u(rng), std::abs(u(rng)) + 0.01f, pw(rng)});
        const V r = linearVertex({u(rng), u(rng), u(rng), pw(rng)});
        const V s = linearVertex({u(rng), u(rng), u(rng), pw(rng)});
        const auto first = distinctVertices(clipTriangle(p, q, r, kClipNear));
        const auto second = distinctVertices(clipTriangle(q, p, s, kClipNear));
        // Where the edge meets z = 0, in double.
        const double t = double(q.position.z) / (double(q.position.z) - double(p.position.z));
        const glm::dvec4 expected =
            glm::dvec4(q.position) + t * (glm::dvec4(p.position) - glm::dvec4(q.position));
        auto closest = [&](const std::vector<V>& vs) {
            const V* best = nullptr;
            double best_d = 1e30;
            for (const V& v : vs) {
                const double d = glm::length(glm::dvec4(v.position) - expected);
                if (d < best_d) best_d = d, best = &v;
            }
            EXPECT_LT(best_d, 1e-5) << "case " << n;
            return best;
        };
        const V* a = closest(first);
        const V* b = closest(second);
        ASSERT_TRUE(a && b);
        EXPECT_TRUE(sameBits(*a, *b))
            << "case " << n << ": the shared edge's cut differs between its triangles";
    }
}

TEST(ClipPrimitive, LinesAreCutAtThePlane) {
    const V a = linearVertex({0, 0, -1, 1}), b = linearVertex({2, 2, 3, 2});
    const V* const in[2] = {&a, &b};
    std::vector<V> out;
    EXPECT_EQ(clipPrimitive<2>(in, kClipNear, ClipPlanes{},
                               [&](const V* const* l) {
                                   out = {*l[0], *l[1]};
                               }),
              1);
    ASSERT_EQ(out.size(), 2u);
    // From b (distance 3) towards a (distance -1): t = 3/4, (0.5, 0.5, 0, 1.25).
    expectVertex(out[0], {0.5f, 0.5f, 0, 1.25f}, linearAttribute({0.5f, 0.5f, 0, 1.25f}), "cut end");
    EXPECT_TRUE(sameBits(out[1], b));
    const V c = linearVertex({0, 0, -2, 1});
    const V* const gone[2] = {&a, &c};
    EXPECT_EQ(clipPrimitive<2>(gone, kClipNear, ClipPlanes{}, [&](const V* const*) { FAIL(); }), 0);
}

// ---- Through the pipeline -------------------------------------------------------------------------

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
const InputElementDesc kLayout[] = {
    {"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0, InputClassification::PerVertexData, 0}};

// A context drawing clip positions into a float target with additive counting and, optionally, depth.
class Rig {
  public:
    Rig(uint32_t width, uint32_t height, ContextOptions options = {.threads = 2})
        : ctx_(options),
          layout_(kLayout),
          color_(width, height, Format::R32G32B32A32_FLOAT),
          depth_(width, height) {
        ctx_.setInputLayout(&layout_);
        ctx_.setRenderTargets(&color_, &depth_);
        ctx_.setViewport({0, 0, float(width), float(height), 0, 1});
        RasterizerState rs;
        rs.cullMode = CullMode::None;
        ctx_.setRasterizerState(rs);
        BlendState b;
        RenderTargetBlendDesc& d = b.renderTarget[0];
        d.blendEnable = true;
        d.srcBlend = d.destBlend = d.srcBlendAlpha = d.destBlendAlpha = Blend::One;
        ctx_.setBlendState(b);
        ctx_.setDepthStencilState(DepthStencilState::disabled());
        color_.clear(glm::vec4(0.0f));
        depth_.clear(1.0f);
    }
    Context& ctx() { return ctx_; }
    DepthTarget& depth() { return depth_; }
    void useDepth() {
        DepthStencilState ds;
        ds.depthFunc = ComparisonFunc::Less;
        ctx_.setDepthStencilState(ds);
    }
    void draw(const std::vector<glm::vec4>& clip, Topology topology = Topology::TriangleList) {
        vb_ = VertexBuffer::create(clip);
        ctx_.setVertexBuffer(0, &vb_);
        ctx_.setPrimitiveTopology(topology);
        ctx_.draw(VsPass{}, PsOne{}, uint32_t(clip.size()));
    }
    float count(int x, int y) const { return color_.load(uint32_t(x), uint32_t(y)).r; }
    int width() const { return int(color_.width()); }
    int height() const { return int(color_.height()); }
    int total() const {
        int t = 0;
        for (int y = 0; y < height(); ++y)
            for (int x = 0; x < width(); ++x) t += int(count(x, y));
        return t;
    }
    const PipelineStatistics& stats() const { return ctx_.drawStatistics(); }

  private:
    Context ctx_;
    InputLayout layout_;
    RenderTarget color_;
    DepthTarget depth_;
    VertexBuffer vb_;
};

// Clip position (w = 1) of a screen position in a width × height viewport at the origin.
glm::vec4 screenClip(double x, double y, double z, int width, int height, float w = 1.0f) {
    return glm::vec4(float(2 * x / width - 1), float(1 - 2 * y / height), float(z), 1.0f) * w;
}

// Per pixel, whether a region holds its centre: `inside(sx, sy)` at the centre and at the four
// corners; when they disagree the pixel is on the region's edge and only "at most once" is checked.
template <class Inside>
void expectRegion(const Rig& rig, Inside inside, const std::string& what, int* inner = nullptr) {
    int bad = 0, in_count = 0;
    for (int y = 0; y < rig.height(); ++y)
        for (int x = 0; x < rig.width(); ++x) {
            const bool c = inside(x + 0.5, y + 0.5);
            bool all_same = true;
            for (int k = 0; k < 4; ++k) all_same &= inside(x + (k & 1), y + (k >> 1)) == c;
            const float n = rig.count(x, y);
            const bool ok = all_same ? n == (c ? 1.0f : 0.0f) : (n == 0.0f || n == 1.0f);
            in_count += all_same && c;
            if (!ok && bad++ < 5)
                ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") counted " << n << ", expected "
                              << (all_same ? (c ? "1" : "0") : "0 or 1");
        }
    EXPECT_EQ(bad, 0) << what;
    if (inner) *inner = in_count;
}

// A perspective camera at the origin looking down -z (view = identity).
struct Camera {
    double fovy, aspect, zNear, zFar;
    glm::mat4 proj() const {
        return glm::perspectiveRH_ZO(float(fovy), float(aspect), float(zNear), float(zFar));
    }
    // The view-space ray through screen point (sx, sy), with direction z = -1.
    glm::dvec3 ray(double sx, double sy, int width, int height) const {
        const double t = std::tan(fovy / 2);
        return {(2 * sx / width - 1) * t * aspect, (1 - 2 * sy / height) * t, -1.0};
    }
};

TEST(NearPlane, TriangleWithOneVertexBehindIsCutIntoTwo) {
    const int W = 64, H = 64;
    const Camera cam{glm::radians(60.0), 1.0, 0.5, 100.0};
    // On the ground y = -1: A behind the camera (w = -1), B and C in front.
    const glm::dvec3 A(0, -1, 1), B(-1, -1, -3), C(1, -1, -3);
    Rig rig(W, H);
    rig.useDepth();
    const glm::mat4 proj = cam.proj();
    rig.draw({proj * glm::vec4(glm::vec3(A), 1), proj * glm::vec4(glm::vec3(B), 1),
              proj * glm::vec4(glm::vec3(C), 1)});
    EXPECT_EQ(rig.stats().cInvocations, 1u);
    EXPECT_EQ(rig.stats().primitivesClipped, 1u);
    EXPECT_EQ(rig.stats().cPrimitives, 2u);
    EXPECT_EQ(rig.stats().primitivesOutside, 0u);

    // The visible part: points of ABC (on y = -1) in front of the near plane z = -zNear.
    auto hit = [&](double sx, double sy, glm::dvec3& p) {
        const glm::dvec3 d = cam.ray(sx, sy, W, H);
        if (d.y >= 0) return false;
        p = d * (-1.0 / d.y);
        return true;
    };
    auto inside = [&](double sx, double sy) {
        glm::dvec3 p;
        if (!hit(sx, sy, p) || p.z > -cam.zNear) return false;
        auto side = [&](const glm::dvec3& a, const glm::dvec3& b) {
            return (b.x - a.x) * (p.z - a.z) - (b.z - a.z) * (p.x - a.x);
        };
        const double s0 = side(A, B), s1 = side(B, C), s2 = side(C, A);
        return (s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0);
    };
    int inner = 0;
    expectRegion(rig, inside, "near-clipped triangle", &inner);
    EXPECT_GT(inner, 200);
    // Depth: that of the ground point seen, never below 0.
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (rig.count(x, y) == 0) continue;
            glm::dvec3 p;
            ASSERT_TRUE(hit(x + 0.5, y + 0.5, p));
            const glm::dvec4 clip = glm::dmat4(proj) * glm::dvec4(p, 1);
            EXPECT_GE(rig.depth().load(x, y), 0.0f);
            // Snapping moves the vertices by up to 1/512 pixel: allow for the depth's slope over that.
            auto depthAt = [&](double sx, double sy) {
                glm::dvec3 q;
                if (!hit(sx, sy, q)) return 1.0;
                const glm::dvec4 c = glm::dmat4(proj) * glm::dvec4(q, 1);
                return c.z / c.w;
            };
            const double slope = std::abs(depthAt(x + 1.5, y + 0.5) - depthAt(x - 0.5, y + 0.5)) +
                                 std::abs(depthAt(x + 0.5, y + 1.5) - depthAt(x + 0.5, y - 0.5));
            EXPECT_NEAR(rig.depth().load(x, y), clip.z / clip.w, 1e-6 + slope / 256) << x << ", " << y;
        }
}

TEST(NearPlane, GroundPlaneCrossingNearCoversEverythingBelowTheHorizon) {
    const int W = 96, H = 64;
    const Camera cam{glm::radians(60.0), double(W) / H, 0.1, 500.0};
    // Ground y = -1 from z = +10 (behind) to z = -200, |x| <= 50: both triangles cross the near plane.
    const glm::vec4 q[4] = {{-50, -1, 10, 1}, {50, -1, 10, 1}, {50, -1, -200, 1}, {-50, -1, -200, 1}};
    const glm::mat4 proj = cam.proj();
    Rig rig(W, H);
    rig.useDepth();
    rig.draw({proj * q[0], proj * q[1], proj * q[2], proj * q[0], proj * q[2], proj * q[3]});
    EXPECT_EQ(rig.stats().primitivesClipped, 2u);
    EXPECT_GE(rig.stats().cPrimitives, 2u);
    auto inside = [&](double sx, double sy) {
        const glm::dvec3 d = cam.ray(sx, sy, W, H);
        if (d.y >= 0) return false;
        const glm::dvec3 p = d * (-1.0 / d.y);
        return std::abs(p.x) <= 50 && p.z >= -200 && p.z <= -cam.zNear;
    };
    int inner = 0;
    expectRegion(rig, inside, "ground plane", &inner);
    EXPECT_GT(inner, W * H / 2 - 3 * W);
    // The rows below the horizon (y_ndc < 0 well past the far edge) are full.
    for (int y = H / 2 + 2; y < H; ++y)
        for (int x = 0; x < W; ++x) ASSERT_EQ(rig.count(x, y), 1.0f) << x << ", " << y;
    for (int y = 0; y < H / 2; ++y)
        for (int x = 0; x < W; ++x) ASSERT_EQ(rig.count(x, y), 0.0f) << x << ", " << y;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (rig.count(x, y) != 0) {
                EXPECT_GE(rig.depth().load(x, y), 0.0f) << x << ", " << y;
                EXPECT_LE(rig.depth().load(x, y), 1.0f) << x << ", " << y;
            }
}

// ---- Far plane ------------------------------------------------------------------------------------

// A(4, 4) and C(4, 60) at z = 0.2, B(60, 4) at z = 1.8: z = 1 on the line x = 32.
std::vector<glm::vec4> farTriangle() {
    return {screenClip(4, 4, 0.2, 64, 64), screenClip(60, 4, 1.8, 64, 64), screenClip(4, 60, 0.2, 64, 64)};
}
bool inFarTriangle(int i, int j) {
    return i >= 4 && j >= 4 && i + j < 63;
}  // x + y = 64 is a right edge
double farPlaneZ(int i) {
    return 0.2 + 1.6 * (i + 0.5 - 4) / 56;
}

TEST(FarPlane, CutWithDepthClip) {
    Rig rig(64, 64);
    rig.useDepth();
    rig.draw(farTriangle());
    EXPECT_EQ(rig.stats().primitivesClipped, 1u);
    EXPECT_EQ(rig.stats().cPrimitives, 2u);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            const bool in = inFarTriangle(i, j) && i + 0.5 < 32;
            ASSERT_EQ(rig.count(i, j), in ? 1.0f : 0.0f) << i << ", " << j;
            if (in) {
                EXPECT_NEAR(rig.depth().load(i, j), farPlaneZ(i), 1e-6) << i << ", " << j;
            }
        }
}

TEST(FarPlane, ClampedToMaxDepthWithoutDepthClip) {
    Rig rig(64, 64);
    rig.useDepth();
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    rs.depthClipEnable = false;
    rig.ctx().setRasterizerState(rs);
    rig.ctx().setViewport({0, 0, 64, 64, 0.0f, 0.8f});
    rig.draw(farTriangle());
    EXPECT_EQ(rig.stats().primitivesClipped, 0u);
    EXPECT_EQ(rig.stats().cPrimitives, 1u);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            const bool in = inFarTriangle(i, j);
            ASSERT_EQ(rig.count(i, j), in ? 1.0f : 0.0f) << i << ", " << j;
            if (in) {
                EXPECT_NEAR(rig.depth().load(i, j), std::min(0.8 * farPlaneZ(i), 0.8), 1e-6)
                    << i << ", " << j;
            }
        }
    EXPECT_EQ(rig.depth().load(50, 8), 0.8f);  // beyond the far plane: exactly maxDepth
}

TEST(FarPlane, WhollyBeyondIsRejectedOnlyWithDepthClip) {
    const std::vector<glm::vec4> tri = {screenClip(4, 4, 1.5, 64, 64), screenClip(60, 4, 1.2, 64, 64),
                                        screenClip(4, 60, 2.0, 64, 64)};
    Rig clipped(64, 64);
    clipped.draw(tri);
    EXPECT_EQ(clipped.stats().primitivesOutside, 1u);
    EXPECT_EQ(clipped.total(), 0);
    Rig clamped(64, 64);
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    rs.depthClipEnable = false;
    clamped.ctx().setRasterizerState(rs);
    DepthStencilState ds;
    ds.depthFunc = ComparisonFunc::LessEqual;  // the clamped depth, 1, passes against the cleared 1
    clamped.ctx().setDepthStencilState(ds);
    clamped.depth().clear(1.0f);
    clamped.draw(tri);
    EXPECT_EQ(clamped.stats().primitivesOutside, 0u);
    EXPECT_EQ(clamped.stats().primitivesClipped, 0u);
    int expected = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            expected += inFarTriangle(i, j);
            EXPECT_EQ(clamped.count(i, j), inFarTriangle(i, j) ? 1.0f : 0.0f) << i << ", " << j;
        }
    EXPECT_EQ(expected, 1540);  // i, j >= 4, i + j <= 62: 55 + 54 + ... + 1
    EXPECT_EQ(clamped.total(), expected);
}

// ---- Guard band -----------------------------------------------------------------------------------

// Two triangles of a quad with the given NDC corners, each vertex scaled by w.
std::vector<glm::vec4> hugeQuad(const glm::vec2 (&c)[4], float w) {
    auto v = [&](int k) { return glm::vec4(c[k].x, c[k].y, 0.5f, 1.0f) * w; };
    return {v(0), v(1), v(2), v(0), v(2), v(3)};
}

TEST(GuardBand, HugeQuadInsideTheBandIsNotClipped) {
    Rig rig(64, 64);
    // Guard band edge: 1 + 2·16384 / 64 = 513 in NDC; these reach 400 (12 800 px past the screen).
    const glm::vec2 c[4] = {{-400, -400}, {400, -400}, {400, 400}, {-400, 400}};
    rig.draw(hugeQuad(c, 2.0f));
    EXPECT_EQ(rig.stats().primitivesClipped, 0u);
    EXPECT_EQ(rig.stats().cPrimitives, 2u);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) ASSERT_EQ(rig.count(x, y), 1.0f) << x << ", " << y;
}

TEST(GuardBand, HugeQuadBeyondTheBandIsClippedAndStillWatertight) {
    const glm::vec2 square[4] = {{-1e5f, -1e5f}, {1e5f, -1e5f}, {1e5f, 1e5f}, {-1e5f, 1e5f}};
    const glm::vec2 skewed[4] = {{-1e5f, -7e4f}, {1.3e5f, -1e5f}, {1e5f, 9e4f}, {-8e4f, 1.1e5f}};
    for (const auto* c : {&square, &skewed}) {
        for (float w : {1.0f, 2.0f, 0.37f}) {
            Rig rig(64, 64);
            rig.draw(hugeQuad(*c, w));
            EXPECT_EQ(rig.stats().primitivesClipped, 2u) << "w " << w;
            EXPECT_GE(rig.stats().cPrimitives, 2u);
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 64; ++x) ASSERT_EQ(rig.count(x, y), 1.0f) << x << ", " << y << " w " << w;
        }
    }
}

TEST(GuardBand, OneVertexBeyondTheBandKeepsTheVisibleShape) {
    // A(8, 8), B(56, 8) and C far below at y = 8 + 40 000 px (beyond the band), on the line x = 8:
    // the visible part is the triangle's slice, left edge x = 8, right edge from B towards C.
    Rig rig(64, 64);
    const double cy = 8 + 40000.0;
    rig.draw({screenClip(8, 8, 0.5, 64, 64), screenClip(56, 8, 0.5, 64, 64), screenClip(8, cy, 0.5, 64, 64)});
    EXPECT_EQ(rig.stats().primitivesClipped, 1u);
    auto inside = [&](double x, double y) {
        const double right = 56 - 48 * (y - 8) / (cy - 8);
        return y >= 8 && x >= 8 && x <= right;
    };
    expectRegion(rig, inside, "one vertex past the guard band");
    EXPECT_EQ(rig.count(8, 63), 1.0f);
    EXPECT_EQ(rig.count(55, 63), 1.0f);
}

// ---- Lines and points ------------------------------------------------------------------------------

TEST(ClipLines, CutAtTheGuardBandAndTheNearPlaneKeepTheirPixels) {
    {  // From (5.5, 10.5) to a million pixels to the right: cut at the guard band, row 10 from x = 5.
        Rig rig(64, 64);
        rig.draw({screenClip(5.5, 10.5, 0.5, 64, 64), screenClip(5.5 + 1e6, 10.5, 0.5, 64, 64)},
                 Topology::LineList);
        EXPECT_EQ(rig.stats().primitivesClipped, 1u);
        EXPECT_EQ(rig.stats().cPrimitives, 1u);
        for (int x = 0; x < 64; ++x) EXPECT_EQ(rig.count(x, 10), x >= 5 ? 1.0f : 0.0f) << x;
        EXPECT_EQ(rig.total(), 59);
    }
    // z from 0.5 to -0.5 along x_ndc -0.5 .. 0.5: the visible half ends at x_ndc = 0, screen x = 32.
    // Centres 16.5 .. 31.5 either way (half-open towards the end of travel), on row 32 (y = 32.0,
    // the tie goes to the larger row).
    for (bool reversed : {false, true}) {
        Rig rig(64, 64);
        std::vector<glm::vec4> line = {{-0.5f, 0, 0.5f, 1}, {0.5f, 0, -0.5f, 1}};
        if (reversed) std::swap(line[0], line[1]);
        rig.draw(line, Topology::LineList);
        EXPECT_EQ(rig.stats().primitivesClipped, 1u);
        EXPECT_EQ(rig.stats().cPrimitives, 1u);
        const int first = 16, last = 31;
        for (int x = 0; x < 64; ++x)
            EXPECT_EQ(rig.count(x, 32), x >= first && x <= last ? 1.0f : 0.0f)
                << x << (reversed ? " reversed" : "");
        EXPECT_EQ(rig.total(), last - first + 1);
    }
}

TEST(ClipPoints, PointsAreNeverCutOnlyKeptOrRejected) {
    Rig rig(64, 64);
    // In front, behind the near plane, beyond the far plane, beyond the guard band.
    rig.draw({screenClip(10.5, 10.5, 0.5, 64, 64), screenClip(20.5, 10.5, -0.1, 64, 64),
              screenClip(30.5, 10.5, 1.5, 64, 64), glm::vec4(1e4f, 0, 0.5f, 1)},
             Topology::PointList);
    EXPECT_EQ(rig.stats().cInvocations, 4u);
    EXPECT_EQ(rig.stats().cPrimitives, 1u);
    EXPECT_EQ(rig.stats().primitivesClipped, 0u);
    EXPECT_EQ(rig.stats().primitivesOutside, 3u);
    EXPECT_EQ(rig.count(10, 10), 1.0f);
    EXPECT_EQ(rig.total(), 1);
}

// ---- Trivial rejection ----------------------------------------------------------------------------

TEST(TrivialReject, WhollyLeftOfTheViewportIsOutsideNotClipped) {
    Rig rig(64, 64);
    rig.draw({{-2, 0, 0.5f, 1}, {-3, 1, 0.5f, 1}, {-1.5f, -1, 0.5f, 1}});
    EXPECT_EQ(rig.stats().cInvocations, 1u);
    EXPECT_EQ(rig.stats().primitivesOutside, 1u);
    EXPECT_EQ(rig.stats().primitivesClipped, 0u);
    EXPECT_EQ(rig.stats().cPrimitives, 0u);
    EXPECT_EQ(rig.stats().psInvocations, 0u);
    EXPECT_EQ(rig.total(), 0);
    // Also when a vertex is behind the near plane: rejected before any cut.
    rig.draw({{-2, 0, -0.5f, 1}, {-30, 1, 0.5f, 1}, {-1.5f, -1, 0.5f, 1}});
    EXPECT_EQ(rig.stats().primitivesOutside, 1u);
    EXPECT_EQ(rig.stats().primitivesClipped, 0u);
    // Left of the viewport but inside the guard band in x, with w varying.
    rig.draw({{-2 * 3.0f, 0, 0.5f, 3}, {-1.01f * 0.5f, 0.4f, 0.25f, 0.5f}, {-400, -1, 0.5f, 2}});
    EXPECT_EQ(rig.stats().primitivesOutside, 1u);
    EXPECT_EQ(rig.total(), 0);
    // Each of the other three sides.
    for (const glm::vec2 s : {glm::vec2(1, 0), glm::vec2(0, 1), glm::vec2(0, -1)}) {
        auto at = [&](float along, float across) {
            return glm::vec4(s.x * along + s.y * across, s.y * along + s.x * across, 0.5f, 1);
        };
        rig.draw({at(1.5f, 0), at(2, 1), at(1.1f, -1)});
        EXPECT_EQ(rig.stats().primitivesOutside, 1u) << s.x << ", " << s.y;
    }
    EXPECT_EQ(rig.total(), 0);
}

// ---- Non-finite positions -------------------------------------------------------------------------

TEST(NonFinite, BadVertexDropsOnlyItsTriangle) {
    // Left, middle and right triangles; the middle one gets a NaN or an infinity somewhere.
    const int W = 64, H = 64;
    const glm::vec4 left[3] = {screenClip(2, 2, 0.5, W, H), screenClip(20, 2, 0.5, W, H),
                               screenClip(2, 60, 0.5, W, H)};
    const glm::vec4 mid[3] = {screenClip(24, 2, 0.5, W, H), screenClip(40, 2, 0.5, W, H),
                              screenClip(32, 60, 0.5, W, H)};
    const glm::vec4 right[3] = {screenClip(44, 2, 0.5, W, H), screenClip(62, 2, 0.5, W, H),
                                screenClip(62, 60, 0.5, W, H)};
    struct Bad {
        int vertex, component;
        float value;
    };
    for (const Bad b :
         {Bad{1, 0, kNaN}, Bad{0, 3, kNaN}, Bad{2, 1, kInf}, Bad{1, 2, -kInf}, Bad{0, 3, kInf}}) {
        std::vector<glm::vec4> clip(left, left + 3);
        clip.insert(clip.end(), mid, mid + 3);
        clip.insert(clip.end(), right, right + 3);
        clip[3 + b.vertex][b.component] = b.value;
        Rig rig(W, H);
        ASSERT_NO_THROW(rig.draw(clip));
        const std::string what = "vertex " + std::to_string(b.vertex) + " component " +
                                 std::to_string(b.component) + " = " + std::to_string(b.value);
        EXPECT_EQ(rig.stats().cInvocations, 3u) << what;
        EXPECT_EQ(rig.stats().primitivesNonFinite, 1u) << what;
        EXPECT_EQ(rig.stats().cPrimitives, 2u) << what;
        for (int y = 0; y < H; ++y)
            for (int x = 21; x < 44; ++x)
                ASSERT_EQ(rig.count(x, y), 0.0f) << what << " at " << x << ", " << y;
        EXPECT_EQ(rig.count(3, 3), 1.0f) << what;
        EXPECT_EQ(rig.count(60, 4), 1.0f) << what;
        // Each side triangle: 18×58 half-rectangle.
        EXPECT_GT(rig.total(), 2 * 450) << what;
    }
}

// ---- Watertight after clipping --------------------------------------------------------------------

TEST(Watertight, GroundMeshCrossingTheNearPlaneCoversEachPixelOnce) {
    const int W = 128, H = 96;
    // Near plane far enough out that its cut through the ground is on screen.
    const float zNear = 1.0f;
    const glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(90.0f), float(W) / H, zNear, 30.0f);
    constexpr int kN = 12;
    const double x0 = -5, x1 = 5, z0 = 2, z1 = -10;
    for (const float yaw : {0.0f, 0.4f, -0.9f}) {
        const glm::vec3 eye(0.3f, 0.4f, 0.0f);
        const glm::vec3 target = eye + glm::vec3(std::sin(yaw) * 4, -0.5f, -std::cos(yaw) * 4);
        const glm::mat4 viewProj = proj * glm::lookAt(eye, target, glm::vec3(0, 1, 0));
        std::mt19937 rng(31);
        std::uniform_real_distribution<double> jitter(-0.2, 0.2);
        // Jittered lattice on y = 0; the outline stays the rectangle [x0, x1] × [z1, z0].
        std::vector<std::vector<glm::vec4>> lattice(kN + 1, std::vector<glm::vec4>(kN + 1));
        for (int j = 0; j <= kN; ++j)
            for (int i = 0; i <= kN; ++i) {
                const double ji = i % kN ? jitter(rng) : 0, jj = j % kN ? jitter(rng) : 0;
                const double x = x0 + (i + ji) * (x1 - x0) / kN, z = z0 + (j + jj) * (z1 - z0) / kN;
                lattice[j][i] = viewProj * glm::vec4(float(x), 0, float(z), 1);
            }
        std::vector<glm::vec4> clip;
        auto add = [&](glm::vec4 a, glm::vec4 b, glm::vec4 c) {
            if (rng() & 1) std::swap(b, c);
            clip.insert(clip.end(), {a, b, c});
        };
        for (int j = 0; j < kN; ++j)
            for (int i = 0; i < kN; ++i) {
                const auto &p00 = lattice[j][i], &p10 = lattice[j][i + 1], &p01 = lattice[j + 1][i],
                           &p11 = lattice[j + 1][i + 1];
                if (rng() & 1)
                    add(p00, p10, p11), add(p00, p11, p01);
                else
                    add(p00, p10, p01), add(p10, p11, p01);
            }
        Rig rig(W, H);
        rig.draw(clip);
        EXPECT_GT(rig.stats().primitivesClipped, 5u) << "yaw " << yaw;

        const glm::dmat4 inv = glm::inverse(glm::dmat4(viewProj));
        auto inside = [&](double sx, double sy) {
            const double nx = 2 * sx / W - 1, ny = 1 - 2 * sy / H;
            glm::dvec4 n = inv * glm::dvec4(nx, ny, 0, 1), f = inv * glm::dvec4(nx, ny, 1, 1);
            const glm::dvec3 pn = glm::dvec3(n) / n.w, pf = glm::dvec3(f) / f.w;
            if (pn.y == pf.y) return false;
            const double t = -pn.y / (pf.y - pn.y);  // from the near plane (t = 0) to the far one (t = 1)
            if (t < 0 || t > 1) return false;
            const glm::dvec3 p = pn + t * (pf - pn);
            return p.x >= x0 && p.x <= x1 && p.z <= z0 && p.z >= z1;
        };
        int inner = 0;
        expectRegion(rig, inside, "ground mesh, yaw " + std::to_string(yaw), &inner);
        EXPECT_GT(inner, W * H / 8) << "yaw " << yaw;
        // The near plane's cut crosses the screen: its bottom row is not covered everywhere.
        int bottom = 0;
        for (int x = 0; x < W; ++x) bottom += rig.count(x, H - 1) != 0;
        EXPECT_LT(bottom, W) << "yaw " << yaw;
    }
}

// ---- Huge coordinates -------------------------------------------------------------------------------

TEST(ClipperExactSum, CancellationBetweenHugeTermsLosesNothing) {
    detail::ExactSum sum;
    sum.add(1e300);
    sum.add(1.0);
    sum.add(-1e300);
    EXPECT_EQ(sum.value(), 1.0);
    // (3e38)² − (3e38)² + 2⁻¹⁰⁰: products kept exactly (the FMA's error term) cancel to the small one.
    detail::ExactSum products;
    const double big = 3e38, odd = 3.0000001e38;
    products.addProduct(big, odd);
    products.addProduct(-odd, big);
    products.add(std::ldexp(1.0, -100));
    EXPECT_EQ(products.value(), std::ldexp(1.0, -100));
}

// A triangle (−S, −S), (0, S), (S, −S) covers every pixel of a 32×32 target for any S: it covered
// 1024 for S ≤ 1e10 but 512 for S = 1e15 … 1e35 (the cut at y = −g·w came out at y = 0, as
// x + g·w rounded to x) and none at 3e38 (the distances overflowed float).
TEST(ClipperHugeCoordinates, TriangleCoversTheWholeTargetForAnyScale) {
    for (const float S : {1e3f, 1e10f, 1e15f, 1e20f, 1e25f, 1e30f, 1e35f, 3e38f, std::numeric_limits<float>::max()}) {
        for (const bool reference : {false, true}) {
            Rig rig(32, 32, {.threads = 2, .reference = reference});
            rig.draw({{-S, -S, 0.5f, 1}, {0, S, 0.5f, 1}, {S, -S, 0.5f, 1}});
            EXPECT_EQ(rig.total(), 1024) << "S = " << S << (reference ? " (reference)" : "");
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) ASSERT_EQ(rig.count(x, y), 1.0f) << x << "," << y << " S = " << S;
        }
    }
}

TEST(ClipperHugeCoordinates, QuadKeepsBothHalvesAndTheSharedEdgeOnce) {
    for (const float S : {1e10f, 1e15f, 1e25f, 1e35f, 3e38f}) {
        Rig rig(32, 32);
        rig.draw({{-S, -S, 0.5f, 1}, {-S, S, 0.5f, 1}, {S, -S, 0.5f, 1}, {S, -S, 0.5f, 1}, {-S, S, 0.5f, 1},
                  {S, S, 0.5f, 1}});
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) ASSERT_EQ(rig.count(x, y), 1.0f) << x << "," << y << " S = " << S;
    }
}

TEST(ClipperHugeCoordinates, DiagonalThroughHugeVerticesStaysOnTheDiagonal) {
    // Both ends of each cut edge are huge: the new vertex must still land on the line y = x, where
    // a + t·(b − a) with t ≈ 0.5 would put it ~g pixels off. NDC y > x is sx + sy < 32 on screen.
    for (const float S : {1e8f, 1e15f, 1e30f, 3e38f}) {
        for (const float w : {1.0f, 1e-8f, 0.5f}) {
            Rig rig(32, 32);
            rig.draw({glm::vec4(-S, -S, 0.5f, 1) * w, glm::vec4(S, S, 0.5f, 1) * w, glm::vec4(-S, S, 0.5f, 1) * w});
            expectRegion(rig, [](double sx, double sy) { return sx + sy < 32; },
                         "diagonal, S = " + std::to_string(S) + ", w = " + std::to_string(w));
        }
    }
}

}  // namespace
}  // namespace raster
