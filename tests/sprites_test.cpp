// The lecture's sprites and billboards (src/lecture/sprite_shaders.hpp) and the scenes that show them
// (src/scene_sprites.cpp). The three camera-facing methods, (a) classic transforms, (b) own transform
// and (c) the geometry shader, are one quad in exact arithmetic, so they draw the same picture at any
// field of view; the sprite turned to the eye point draws the same near the centre of a narrow view
// and a wider one near the edges of a wide view, by 1/cos θ. Drawn through the teaching pipeline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "lecture/sprite_shaders.hpp"
#include "raster/check.hpp"
#include "raster/image_compare.hpp"
#include "raster/scenes.hpp"
#include "raster/teaching_draw.hpp"

namespace raster {
namespace {

using shaders::FireParticleIn;
using shaders::SpriteQuadIn;

constexpr uint32_t kWidth = 320, kHeight = 180;

enum class Method { Classic, Own, Geometry, FacingEye };

// A camera with a rotation about every axis (so that (a)'s R⁻¹ is no identity) and a field of view.
struct Camera {
    glm::vec3 eye{1.0f, 0.6f, 3.0f};
    glm::mat4 view, proj;
    explicit Camera(float fov_degrees) {
        view = glm::lookAtRH(eye, glm::vec3(0.3f, 0.1f, -2.0f), glm::vec3(0.1f, 1.0f, 0.0f));
        proj = glm::perspectiveRH_ZO(glm::radians(fov_degrees), float(kWidth) / float(kHeight), 0.1f, 100.0f);
    }
    // The world point at view depth `depth` that projects to (ndc_x, ndc_y).
    glm::vec3 at(float ndc_x, float ndc_y, float depth) const {
        const glm::vec4 v(ndc_x * depth / proj[0][0], ndc_y * depth / proj[1][1], -depth, 1.0f);
        return glm::vec3(glm::inverse(view) * v);
    }
};

// Four coloured quadrants in a disc, transparent outside: a picture that shows a turned or mirrored
// texture coordinate as well as a moved edge.
Texture2D quadrantTexture() {
    constexpr uint32_t kSize = 32;
    std::vector<uint8_t> rgba(kSize * kSize * 4);
    for (uint32_t j = 0; j < kSize; ++j)
        for (uint32_t i = 0; i < kSize; ++i) {
            const float x = (float(i) + 0.5f) / kSize * 2.0f - 1.0f,
                        y = (float(j) + 0.5f) / kSize * 2.0f - 1.0f;
            uint8_t* p = &rgba[4 * (j * kSize + i)];
            p[0] = x < 0 ? 230 : 40, p[1] = y < 0 ? 220 : 50, p[2] = 120,
            p[3] = x * x + y * y <= 1.0f ? 255 : 0;
        }
    return Texture2D::fromRgba8(kSize, kSize, rgba);
}

struct Frame {
    RenderTarget color{kWidth, kHeight};
    DepthTarget depth{kWidth, kHeight};
};

// The sprites (world centre, half-size) drawn by one method, alpha tested, on black.
Frame drawSprites(Method method, const Camera& cam, const std::vector<std::pair<glm::vec3, float>>& sprites) {
    Frame f;
    Context context({2});
    beginSceneFrame(context, f.color, f.depth);
    context.setBlendState(BlendState::opaque());
    context.setDepthStencilState({true, true, ComparisonFunc::Less});
    const Texture2D texture = quadrantTexture();
    shaders::PsAlphaTested ps;
    ps.texture = &texture;
    const glm::mat4 view_proj = cam.proj * cam.view;
    if (method == Method::Geometry) {
        std::vector<FireParticleIn> points;
        for (const auto& [c, s] : sprites) points.push_back({c, s, glm::vec4(1.0f)});
        const VertexBuffer buffer = VertexBuffer::create(points);
        const InputLayout layout = shaders::spritePointLayout();
        context.setInputLayout(&layout);
        context.setVertexBuffer(0, &buffer);
        context.setPrimitiveTopology(Topology::PointList);
        const shaders::GsFireParticle gs{view_proj, {cam.proj[0][0], cam.proj[1][1]}};
        context.draw(shaders::VsFireParticle{}, gs, ps, uint32_t(points.size()));
        return f;
    }
    std::vector<SpriteQuadIn> quads;
    for (const auto& [c, s] : sprites)
        for (const glm::vec2 corner : shaders::kSpriteCorners)
            quads.push_back({c, s, glm::vec4(1.0f), corner});
    const VertexBuffer buffer = VertexBuffer::create(quads);
    const InputLayout layout = shaders::spriteQuadLayout();
    context.setInputLayout(&layout);
    context.setVertexBuffer(0, &buffer);
    context.setPrimitiveTopology(Topology::TriangleList);
    const auto count = uint32_t(quads.size());
    if (method == Method::Classic)
        context.draw(shaders::VsSpriteClassic{view_proj, glm::transpose(glm::mat3(cam.view))}, ps, count);
    else if (method == Method::Own)
        context.draw(shaders::VsSpriteOwn{cam.view, cam.proj}, ps, count);
    else
        context.draw(shaders::VsSpriteFacingEye{view_proj, cam.eye,
                                                glm::vec3(cam.view[0][1], cam.view[1][1], cam.view[2][1])},
                     ps, count);
    return f;
}

ImageDifference difference(const Frame& a, const Frame& b) {
    return compareImages(Rgba8View({a.color.rgba8(), size_t(kWidth) * kHeight * 4}, kWidth, kHeight),
                         Rgba8View({b.color.rgba8(), size_t(kWidth) * kHeight * 4}, kWidth, kHeight));
}

// The bounding box of the drawn (non-black) pixels: width, height in pixels, and how many there are.
struct Box {
    int width = 0, height = 0;
    size_t pixels = 0;
};
Box drawnBox(const Frame& f) {
    int x0 = kWidth, x1 = -1, y0 = kHeight, y1 = -1;
    Box box;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const uint8_t* p = f.color.rgba8() + 4 * (size_t(y) * kWidth + x);
            if (p[0] == 0 && p[1] == 0 && p[2] == 0) continue;
            x0 = std::min(x0, int(x)), x1 = std::max(x1, int(x)), y0 = std::min(y0, int(y)),
            y1 = std::max(y1, int(y));
            ++box.pixels;
        }
    if (x1 >= 0) box.width = x1 - x0 + 1, box.height = y1 - y0 + 1;
    return box;
}

// Sprites spread over the image at a view depth of 4: a 5×3 lattice across ±spread of NDC.
std::vector<std::pair<glm::vec3, float>> lattice(const Camera& cam, float spread) {
    std::vector<std::pair<glm::vec3, float>> sprites;
    const float size = 0.09f * 4.0f / cam.proj[1][1];  // 9 % of the image's half-height
    for (int j = -1; j <= 1; ++j)
        for (int i = -2; i <= 2; ++i)
            sprites.push_back({cam.at(spread * float(i) / 2.0f, spread * float(j), 4.0f), size});
    return sprites;
}

// Pixels allowed to differ between (a), (b) and (c): none. The three compute one quad with different
// roundings (a corner in world space first, in view space, in clip space), so an edge passing within a
// few ulps of a pixel centre could fall on either side; on these lattices none does (measured: 0 of
// 57 600 at 25° and at 120°), and the test keeps it so.
constexpr size_t kRoundingPixels = 0;

TEST(Sprites, ThreeMethodsDrawOneQuadAtNarrowFieldOfView) {
    const Camera cam(25.0f);
    const auto sprites = lattice(cam, 0.3f);
    const Frame a = drawSprites(Method::Classic, cam, sprites), b = drawSprites(Method::Own, cam, sprites);
    const Frame c = drawSprites(Method::Geometry, cam, sprites);
    EXPECT_GT(drawnBox(b).pixels, 15u * 100u) << "15 sprites of about 10×10 pixels at least";
    EXPECT_LE(difference(a, b).differing, kRoundingPixels) << "(a) against (b)";
    EXPECT_LE(difference(b, c).differing, kRoundingPixels) << "(b) against (c)";
    EXPECT_LE(difference(a, c).differing, kRoundingPixels) << "(a) against (c)";
    std::printf("narrow: (a)-(b) %zu, (b)-(c) %zu, (a)-(c) %zu pixels differ\n", difference(a, b).differing,
                difference(b, c).differing, difference(a, c).differing);
}

// At 120° the lattice reaches 90 % of the way to the image's edges, where a ray is 70° off the view
// axis: the three still draw one quad, parallel to the camera plane, so the same picture.
TEST(Sprites, ThreeMethodsDrawOneQuadAtWideFieldOfViewToo) {
    const Camera cam(120.0f);
    const auto sprites = lattice(cam, 0.9f);
    const Frame a = drawSprites(Method::Classic, cam, sprites), b = drawSprites(Method::Own, cam, sprites);
    const Frame c = drawSprites(Method::Geometry, cam, sprites);
    EXPECT_GT(drawnBox(b).pixels, 15u * 100u);
    EXPECT_LE(difference(a, b).differing, kRoundingPixels) << "(a) against (b)";
    EXPECT_LE(difference(b, c).differing, kRoundingPixels) << "(b) against (c)";
    std::printf("wide: (a)-(b) %zu, (b)-(c) %zu, (a)-(c) %zu pixels differ\n", difference(a, b).differing,
                difference(b, c).differing, difference(a, c).differing);
}

// The pixel bounding box of the points' projections (x right, y down), in pixels, in double.
glm::dvec2 projectedExtent(const Camera& cam, const std::vector<glm::vec3>& points) {
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const glm::vec3& c : points) {
        const glm::dvec4 clip = glm::dmat4(cam.proj * cam.view) * glm::dvec4(glm::dvec3(c), 1.0);
        const double x = (clip.x / clip.w + 1.0) * 0.5 * kWidth, y = (1.0 - clip.y / clip.w) * 0.5 * kHeight;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    return {x1 - x0, y1 - y0};
}

// A sprite parallel to the camera plane is a square on the screen wherever it is; one turned to the eye
// is widened along the screen's radius (by 1/cos θ for a small one, θ the ray's angle off the view axis;
// this one is large, so its near side is also taller than its far side). The drawn box matches the
// projection of the texture's disc, computed here in double, to two pixels (the disc's edge texels).
TEST(Sprites, EyeFacingSpriteWidensNearTheEdgesOfAWideView) {
    const Camera cam(120.0f);
    const float ndc_x = 0.6f, depth = 4.0f, size = 0.15f * depth / cam.proj[1][1];  // inside the image
    const glm::vec3 centre = cam.at(ndc_x, 0.0f, depth);
    const std::vector<std::pair<glm::vec3, float>> one = {{centre, size}};
    const Frame own = drawSprites(Method::Own, cam, one), facing = drawSprites(Method::FacingEye, cam, one);
    const Box plane = drawnBox(own), eye = drawnBox(facing);
    ASSERT_GT(plane.width, 20);
    EXPECT_NEAR(plane.width, plane.height, 1) << "a square on the screen";
    // The eye-facing sprite's axes, as VsSpriteFacingEye places them.
    const glm::vec3 cam_up(cam.view[0][1], cam.view[1][1], cam.view[2][1]);
    const glm::vec3 normal = glm::normalize(cam.eye - centre),
                    right = glm::normalize(glm::cross(cam_up, normal));
    const glm::vec3 up = glm::cross(normal, right);
    // The texture's disc (alpha 0 outside it) as 720 points of its outline.
    std::vector<glm::vec3> outline;
    for (int k = 0; k < 720; ++k) {
        const float phi = float(k) * 3.14159265f / 360.0f;
        outline.push_back(centre + size * (std::cos(phi) * right + std::sin(phi) * up));
    }
    const glm::dvec2 extent = projectedExtent(cam, outline);
    EXPECT_NEAR(eye.width, extent.x, 2.0) << "drawn against projected width";
    EXPECT_NEAR(eye.height, extent.y, 2.0) << "drawn against projected height";
    const double theta = std::atan(ndc_x / cam.proj[0][0]);  // 62°: 1/cos θ = 2.1 for a small sprite
    EXPECT_GT(double(eye.width) / plane.width, 1.5)
        << "θ = " << theta << ", widths " << eye.width << ", " << plane.width;
    EXPECT_GT(difference(own, facing).differing, plane.pixels / 2) << "differs over half the square's pixels";
}

// Near the centre of a narrow view the ray is almost the view axis: the eye-facing sprite is turned by
// under a degree, and its picture differs from the others' only where a colour edge of (b)'s passes:
// every differing pixel has a neighbour of another colour in (b)'s picture (edges move under a pixel).
TEST(Sprites, EyeFacingSpriteDrawsAlmostTheSameNearTheCentre) {
    const Camera cam(25.0f);
    const std::vector<std::pair<glm::vec3, float>> one = {
        {cam.at(0.05f, 0.05f, 4.0f), 0.3f * 4.0f / cam.proj[1][1]}};
    const Frame own = drawSprites(Method::Own, cam, one), facing = drawSprites(Method::FacingEye, cam, one);
    ASSERT_GT(drawnBox(own).width, 40);
    const auto pixel = [](const Frame& f, uint32_t x, uint32_t y) {
        const uint8_t* p = f.color.rgba8() + 4 * (size_t(y) * kWidth + x);
        return std::tuple<int, int, int>{p[0], p[1], p[2]};
    };
    size_t differing = 0, inside = 0;
    for (uint32_t y = 1; y + 1 < kHeight; ++y)
        for (uint32_t x = 1; x + 1 < kWidth; ++x) {
            if (pixel(own, x, y) == pixel(facing, x, y)) continue;
            ++differing;
            bool uniform = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    uniform = uniform && pixel(own, x + dx, y + dy) == pixel(own, x, y);
            inside += uniform;
        }
    EXPECT_GT(differing, 0u) << "turned by a fraction of a degree, but turned";
    EXPECT_EQ(inside, 0u) << "of " << differing << " differing pixels";
}

// ---- Billboards about an axis, and fixed ones ---------------------------------------------------------

TEST(AxisBillboard, KeepsItsAxisAndFacesTheEyeInThePlaneNormalToIt) {
    const glm::vec3 axes[] = {{0, 1, 0}, glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f))};
    const glm::vec3 eyes[] = {{0, 1.7f, 10}, {-6, 5, 2}, {3, -1, -4}};
    for (const glm::vec3 axis : axes)
        for (const glm::vec3 eye : eyes) {
            const glm::vec3 base(1.0f, 0.0f, -2.0f);
            const float half_width = 0.7f, height = 3.0f;
            const auto corner = [&](float x, float y) {
                return shaders::axisBillboardCorner(base, axis, eye, half_width, height, {x, y});
            };
            // Its side edges run along the axis, `height` long.
            for (const float x : {-1.0f, 1.0f}) {
                const glm::vec3 edge = corner(x, 1.0f) - corner(x, 0.0f);
                EXPECT_LT(glm::length(edge - height * axis), 1e-5f);
            }
            // Its width runs normal to the axis; its normal, in the plane normal to the axis, points to the
            // eye.
            const glm::vec3 across = corner(1.0f, 0.0f) - corner(-1.0f, 0.0f);
            EXPECT_NEAR(glm::length(across), 2.0f * half_width, 1e-5f);
            EXPECT_NEAR(glm::dot(across, axis), 0.0f, 1e-5f);
            const glm::vec3 normal = glm::normalize(glm::cross(across, axis));
            glm::vec3 to_eye = eye - base;
            to_eye = glm::normalize(to_eye - glm::dot(to_eye, axis) * axis);
            EXPECT_GT(glm::dot(normal, to_eye), 1.0f - 1e-5f)
                << "eye " << eye.x << "," << eye.y << "," << eye.z;
        }
    // The eye on the axis line: any orientation normal to the axis, but finite.
    const glm::vec3 c =
        shaders::axisBillboardCorner({0, 0, 0}, {0, 1, 0}, {0, 5, 0}, 1.0f, 2.0f, {1.0f, 1.0f});
    EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.z));
    EXPECT_NEAR(c.y, 2.0f, 1e-6f);
}

// A level camera sees an axis billboard's vertical edges as vertical lines of pixels; a camera that
// looks down sees them converge, but each stays a straight line through the projection of the axis.
TEST(AxisBillboard, VertexShaderProjectsTheTurnedCorners) {
    const glm::mat4 view_proj =
        glm::perspectiveRH_ZO(glm::radians(60.0f), 16.0f / 9.0f, 0.1f, 100.0f) *
        glm::lookAtRH(glm::vec3(0, 1.7f, 10), glm::vec3(0, 1.5f, 0), glm::vec3(0, 1, 0));
    const shaders::VsAxisBillboard vs{view_proj, {0, 1.7f, 10}, {0, 1, 0}};
    const shaders::AxisBillboardIn low{{2, 0, 1}, {0.5f, 3.0f}, glm::vec4(1.0f), {-1, 0}};
    shaders::AxisBillboardIn high = low;
    high.corner = {-1, 1};
    const glm::vec4 a = vs(low).position, b = vs(high).position;
    // Not vertical on the screen in general (perspective), but both on the same world vertical line.
    const glm::vec3 world_low =
        shaders::axisBillboardCorner(low.base, {0, 1, 0}, {0, 1.7f, 10}, 0.5f, 3.0f, {-1, 0});
    const glm::vec4 expected = view_proj * glm::vec4(world_low, 1.0f);
    EXPECT_LT(glm::length(a - expected), 1e-5f);
    const glm::vec4 expected_high = view_proj * glm::vec4(world_low + glm::vec3(0, 3, 0), 1.0f);
    EXPECT_LT(glm::length(b - expected_high), 1e-4f);
    EXPECT_EQ(vs(high).tex, glm::vec2(0.0f, 0.0f)) << "v = 0 at the top";
}

TEST(BillboardCloud, IsCrossedVerticalQuadsFixedInTheWorld) {
    const auto cloud = shaders::billboardCloud({1, 0, 2}, 0.5f, 1.2f, 3, 0.0f, glm::vec4(1.0f));
    ASSERT_EQ(cloud.size(), 3u * 6u);
    std::vector<glm::vec3> acrosses;
    for (size_t q = 0; q < 3; ++q) {
        float lowest = 1e9f, highest = -1e9f;
        glm::vec3 centre(0.0f);
        for (size_t v = 0; v < 6; ++v) {
            const glm::vec3 p = cloud[6 * q + v].position;
            lowest = std::min(lowest, p.y), highest = std::max(highest, p.y), centre += p / 6.0f;
        }
        EXPECT_NEAR(lowest, 0.0f, 1e-6f);
        EXPECT_NEAR(highest, 1.2f, 1e-6f);
        EXPECT_NEAR(centre.x, 1.0f, 1e-5f);
        EXPECT_NEAR(centre.z, 2.0f, 1e-5f);
        acrosses.push_back(
            glm::normalize(cloud[6 * q].position - cloud[6 * q + 2].position));  // (1,1) − (−1,1)
    }
    EXPECT_NEAR(glm::dot(acrosses[0], acrosses[1]), 0.5f, 1e-5f) << "60° apart";
    EXPECT_NEAR(glm::dot(acrosses[1], acrosses[2]), 0.5f, 1e-5f);
}

// ---- The scenes ----------------------------------------------------------------------------------------

Frame renderScene(const std::string& name, double time, unsigned threads, std::optional<float> fov = {}) {
    SceneOptions o{.width = kWidth, .height = kHeight};
    o.time = time;
    o.fovDegrees = fov;
    Frame f;
    Context context({threads});
    makeScene(name, o)->render(context, f.color, f.depth);
    return f;
}

TEST(SpritesScene, FourRowsAreDrawnTheSameAtAnyThreadCount) {
    const Frame one = renderScene("sprites", 2.0, 1), eight = renderScene("sprites", 2.0, 8);
    EXPECT_TRUE(one.color == eight.color && one.depth == eight.depth);
    // Row r's sprites are centred at NDC y = 0.62 − 0.413 r, a band of rows of pixels each.
    for (int r = 0; r < 4; ++r) {
        const float ndc_y = 0.62f - 0.413f * float(r);
        const int centre = int((1.0f - ndc_y) * 0.5f * kHeight);
        size_t drawn = 0;
        for (int y = centre - 5; y <= centre + 5; ++y)
            for (uint32_t x = 0; x < kWidth; ++x)
                drawn += one.color.rgba8()[4 * (size_t(y) * kWidth + x) + 0] > 60;
        EXPECT_GT(drawn, 9u * 4u * 11u) << "row " << r << ": nine sprites at least 4 pixels wide";
    }
}

TEST(SpritesScene, TimeScrollsTheRowsAndIsAFunctionOfTheClock) {
    EXPECT_FALSE(renderScene("sprites", 0.0, 2).color == renderScene("sprites", 1.0, 2).color);
    SceneOptions o{.width = kWidth, .height = kHeight};
    o.time = 0.5;
    const std::unique_ptr<Scene> halves = makeScene("sprites", o);
    halves->advance(0.5);
    Frame f;
    Context context({2});
    halves->render(context, f.color, f.depth);
    EXPECT_TRUE(f.color == renderScene("sprites", 1.0, 2).color);
    EXPECT_EQ(halves->time(), 1.0);
}

TEST(SpritesScene, FieldOfViewOutsideItsRangeIsRefused) {
    for (const float fov : {0.0f, -5.0f, 180.0f, NAN}) {
        SceneOptions o{.width = 8, .height = 8};
        o.fovDegrees = fov;
        try {
            makeScene("sprites", o);
            ADD_FAILURE() << fov << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("field of view"), std::string::npos) << e.what();
        }
    }
    EXPECT_FALSE(renderScene("sprites", 0.0, 2, 120.0f).color == renderScene("sprites", 0.0, 2).color);
}

// The forest's palette (src/scene_sprites.cpp): point sampling, alpha testing and opaque writes leave
// every pixel one of these, so no pixel was blended and no edge is soft.
std::set<std::tuple<int, int, int>> forestPalette() {
    return {{92, 64, 40},   {28, 84, 44},  {58, 128, 60}, {70, 110, 30},
            {120, 160, 50}, {96, 120, 70}, {84, 106, 62}, {140, 178, 230}};  // the last is the sky
}

TEST(ForestScene, AlphaTestedTreesWithoutPartialPixelsTheSameAtAnyThreadCount) {
    const Frame one = renderScene("forest", 7.0, 1), eight = renderScene("forest", 7.0, 8);
    EXPECT_TRUE(one.color == eight.color && one.depth == eight.depth);
    const auto palette = forestPalette();
    size_t needles = 0, trunk = 0, leaves = 0, foreign = 0;
    for (uint32_t i = 0; i < kWidth * kHeight; ++i) {
        const uint8_t* p = one.color.rgba8() + 4 * i;
        const std::tuple<int, int, int> c{p[0], p[1], p[2]};
        foreign += !palette.contains(c);
        needles += c == std::tuple<int, int, int>{28, 84, 44} || c == std::tuple<int, int, int>{58, 128, 60};
        trunk += c == std::tuple<int, int, int>{92, 64, 40};
        leaves += c == std::tuple<int, int, int>{70, 110, 30} || c == std::tuple<int, int, int>{120, 160, 50};
    }
    EXPECT_EQ(foreign, 0u) << "pixels outside the palette: blended or filtered";
    EXPECT_GT(needles, size_t(kWidth * kHeight / 20)) << "trees cover 5 % of the image at least";
    EXPECT_GT(trunk, 50u);
    EXPECT_GT(leaves, 50u) << "the shrubs";
    EXPECT_FALSE(renderScene("forest", 12.0, 2).color == one.color) << "the camera moves";
}

}  // namespace
}  // namespace raster
