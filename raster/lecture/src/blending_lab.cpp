// The blending lab's scene, less the student's states, sort key and comparator
// (raster/labs/blending.hpp): the particles, their quads and soft discs, the sort and the panels.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "raster/labs/blending.hpp"
#include "raster/strict_weak_order.hpp"

namespace raster::blending_lab {

namespace {

// World units. The particles fill a box around the occluder (x in [-0.6, 0.6], y in [-1.2, 0.4], z = 0),
// half in front of it, half behind; each is a square quad facing +z with a soft disc drawn on it.
constexpr glm::vec3 kBoxHalf{1.2f, 0.9f, 1.2f}, kBoxCentre{0.0f, -0.2f, 0.0f};
constexpr float kHalfSize = 0.15f;
constexpr float kAdditiveOpacity = 0.35f, kOverOpacity = 0.75f;
constexpr glm::vec3 kFarColour{0.1f, 0.3f, 1.0f}, kNearColour{1.0f, 0.75f, 0.1f};
constexpr uint32_t kDefaultCount = 200;
constexpr uint32_t kMaxCount = 4000;  // the comparator check takes count² calls

struct QuadVertex {
    glm::vec3 position;  // world
    glm::vec2 uv;        // [-1, 1]² over the quad
    glm::vec3 colour;
};
struct QuadIn {
    glm::vec3 position;
    glm::vec2 uv;
    glm::vec3 colour;
    RASTER_INPUT_SIGNATURE(QuadIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(uv, "TEXCOORD", 0),
                           RASTER_INPUT(colour, "COLOR", 0))
};
struct QuadCorner {
    glm::vec4 position;
    glm::vec2 uv;
    glm::vec3 colour;
};
const InputElementDesc kQuadElements[] = {
    {"POSITION", 0, Format::R32G32B32_FLOAT, 0, offsetof(QuadVertex, position)},
    {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, offsetof(QuadVertex, uv)},
    {"COLOR", 0, Format::R32G32B32_FLOAT, 0, offsetof(QuadVertex, colour)},
};

struct VsQuad {
    glm::mat4 viewProj{1.0f};
    QuadCorner operator()(const QuadIn& in) const {
        return {viewProj * glm::vec4(in.position, 1.0f), in.uv, in.colour};
    }
};
// A disc with a soft rim: alpha = opacity·min(1, 2·(1 − r²)) inside the unit circle, 0 outside.
struct PsDisc {
    float opacity = 1.0f;
    glm::vec4 operator()(const QuadCorner& in) const {
        const float r2 = glm::dot(in.uv, in.uv);
        return {in.colour, opacity * std::clamp(2.0f * (1.0f - r2), 0.0f, 1.0f)};
    }
};

// A number in [0, 1) from (i, k), the same on every machine (SplitMix64's finaliser).
float unitHash(uint32_t i, uint32_t k) {
    uint64_t z = (uint64_t(i) << 2 | k) * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return float(double(z ^ (z >> 31)) * 0x1p-64);
}

// The particles' centres (seeded) and their quads, four vertices each.
void makeParticles(uint32_t count, uint32_t seed, std::vector<glm::vec3>& centres,
                   std::vector<QuadVertex>& quads) {
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t key = i + seed * 0x10000u;
        const glm::vec3 unit = 2.0f * glm::vec3(unitHash(key, 0), unitHash(key, 1), unitHash(key, 2)) - 1.0f;
        const glm::vec3 c = kBoxCentre + unit * kBoxHalf;
        const glm::vec3 colour = glm::mix(kFarColour, kNearColour, 0.5f * (unit.z + 1.0f));
        centres.push_back(c);
        for (const glm::vec2 uv : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
            quads.push_back({c + kHalfSize * glm::vec3(uv, 0.0f), uv, colour});
    }
}

// Six indices (two triangles) per particle, in the order given.
std::vector<uint32_t> quadIndices(std::span<const uint32_t> order) {
    std::vector<uint32_t> indices;
    for (const uint32_t p : order)
        for (const uint32_t corner : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(4 * p + corner);
    return indices;
}

SceneOptions panelOptions(const SceneOptions& o) {
    SceneOptions p = o;
    p.width = std::max(1u, o.width / 3), p.height = std::max(1u, o.height / 2);
    p.count = 0;  // the occluder and the camera only
    p.camera = o.camera.value_or(kBlendingCamera);
    return p;
}

}  // namespace

std::vector<Figure> lectureFigures(const BlendState& additive, const DepthStencilState& noTest,
                                   const DepthStencilState& testNoWrite, const BlendState& over) {
    const DepthStencilState testAndWrite;  // the occluder's: test Less, write
    return {{"blending with the depth test on", additive, testAndWrite, false},
            {"no depth test: even the giraffe does not occlude", additive, noTest, false},
            {"depth test stays, depth write off", additive, testNoWrite, false},
            {"wrong order: back ones cover front ones", over, testNoWrite, false},
            {"sorting", over, testNoWrite, true}};
}

BlendingScene::BlendingScene(const SceneOptions& o, std::vector<Figure> figures, ViewDepthFn viewDepth,
                             DrawnBeforeFn drawnBefore)
    : panel_(panelOptions(o)),
      data_(panel_),
      figures_(std::move(figures)),
      view_depth_(viewDepth),
      drawn_before_(drawnBefore),
      layout_(kQuadElements) {
    const uint32_t count = o.count.value_or(kDefaultCount);
    if (count > kMaxCount)
        throw Error(ErrorCode::InvalidArgument,
                    "blending: count " + std::to_string(count) + " above " + std::to_string(kMaxCount));
    std::vector<QuadVertex> quads;
    makeParticles(count, o.seed, centres_, quads);
    vertices_ = VertexBuffer::create(std::span<const QuadVertex>(quads));
    view_proj_ = data_.viewProj;
    eye_ = panel_.camera->eye;
    ahead_ = glm::normalize(panel_.camera->target - panel_.camera->eye);
    std::vector<uint32_t> stored(count);
    std::iota(stored.begin(), stored.end(), 0u);
    stored_ = IndexBuffer::create(quadIndices(stored));
}

// The draw order of the sorted figure: the comparator checked first, then std::stable_sort, so that
// particles the comparator ties keep their storage order on every machine. A comparator that is not
// a strict weak ordering makes std::sort and std::stable_sort undefined behaviour (they may read past
// the array and crash); the check stops with the particles that break the rule instead. An insertion
// sort, defined for any comparator, would not crash, but would draw the slide's comparator's order
// without a word, and that order differs from the right one only among particles within 0.01 units.
std::vector<uint32_t> BlendingScene::backToFront() const {
    std::vector<SortItem> items(centres_.size());
    for (uint32_t i = 0; i < centres_.size(); ++i) items[i] = {i, view_depth_(centres_[i], eye_, ahead_)};
    if (const auto v = findStrictWeakOrderViolation(std::span<const SortItem>(items), drawn_before_))
        throw Error(ErrorCode::InvalidArgument,
                    "blending: drawnBefore is not a strict weak ordering, and std::sort with it is undefined "
                    "behaviour: " +
                        orderViolationText(*v, "drawnBefore", [&](size_t k) {
                            return "particle " + std::to_string(items[k].index) + " (depth " +
                                   std::to_string(items[k].depth) + ")";
                        }));
    std::stable_sort(items.begin(), items.end(), drawn_before_);
    std::vector<uint32_t> order(items.size());
    for (size_t i = 0; i < items.size(); ++i) order[i] = items[i].index;
    return order;
}

void BlendingScene::render(Context& context, RenderTarget& color, DepthTarget& depth) {
    beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
    const IndexBuffer sorted =
        IndexBuffer::create(quadIndices(backToFront()));  // every frame, as a moving camera needs
    const VsQuad vs{view_proj_};
    const float w = float(panel_.width), h = float(panel_.height);
    for (size_t f = 0; f < figures_.size(); ++f) {
        const float x = f < 3 ? w * float(f) : w * (float(f) - 2.5f), y = f < 3 ? 0.0f : h;
        context.setViewport({x, y, w, h, 0.0f, 1.0f});
        data_.drawOccluder(context);  // draws 0, 2, 4, 6, 8
        if (centres_.empty()) continue;
        const Figure& figure = figures_[f];
        context.setInputLayout(&layout_);
        context.setVertexBuffer(0, &vertices_);
        context.setIndexBuffer(figure.sorted ? &sorted : &stored_);
        context.setPrimitiveTopology(Topology::TriangleList);
        context.setBlendState(figure.blend);
        context.setDepthStencilState(figure.depth);
        const PsDisc ps{f < 3 ? kAdditiveOpacity : kOverOpacity};
        context.drawIndexed(vs, ps, uint32_t(6 * centres_.size()));  // draws 1, 3, 5, 7, 9
    }
}

}  // namespace raster::blending_lab
