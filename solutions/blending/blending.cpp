// BEGIN NOTE
// Lab: blending, depth and sorting (lecture 11, part 3) - THE SOLUTION.
//
// The lecture's five blend and depth figures side by side, each a panel of one image: soft discs in
// front of and behind the opaque occluder (the slides' "giraffe"), coloured blue (far) to yellow
// (near) so that a wrong order shows. This is labs/blending/blending.cpp with every `LAB n` place
// filled in; its image is the one the student's is compared with (raster view blending, K and J).
// STAND-IN
//> // Lab: blending, depth and sorting (lecture 11, part 3).
//> //
//> // The lecture's five blend and depth figures side by side, each a panel of one image: soft discs in
//> // front of and behind the opaque occluder (the slides' "giraffe"), coloured blue (far) to yellow
//> // (near) so that a wrong order shows. Top row, additive blending: "blending with the depth test on",
//> // "no depth test", "depth test stays, depth write off"; bottom row, "over": "wrong order" (as the
//> // particles are stored) and "sorting" (back to front).
//> //
//> // As handed out, this file compiles and runs, but every state is D3D11's default (blending off,
//> // depth test and write): five panels of opaque squares. Fill in the six places marked `LAB n`, in
//> // order; each changes the picture (labs/blending/README.md has the table):
//> //   LAB 1  additiveBlend      LAB 2  noDepthTest      LAB 3  depthTestNoWrite      LAB 4  overBlend
//> //   LAB 5  viewDepth, the sort key                    LAB 6  drawnBefore, the comparator
//> // Write the states out field by field (raster/states.hpp: BlendState, RenderTargetBlendDesc,
//> // DepthStencilState), as you would fill D3D11_BLEND_DESC and D3D11_DEPTH_STENCIL_DESC.
//> //
//> //   cmake --build build-lab --target raster_tool && build-lab/bin/raster view blending
//> //
//> // In the viewer, K shows the solution's image and J the difference; click a pixel for its history:
//> // each fragment's draw, depth test and blend.
// END NOTE
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "raster/lab.hpp"
#include "raster/strict_weak_order.hpp"

namespace {

using namespace raster;

// ---- The states ---------------------------------------------------------------------------------

// BEGIN LAB 1
// LAB 1: additive blending, for colour and alpha: SRC_ALPHA, ONE, ADD.
BlendState additiveBlend() {
    BlendState blend;
    RenderTargetBlendDesc& rt = blend.renderTarget[0];
    rt.blendEnable = true;
    rt.srcBlend = Blend::SrcAlpha, rt.destBlend = Blend::One, rt.blendOp = BlendOp::Add;
    rt.srcBlendAlpha = Blend::SrcAlpha, rt.destBlendAlpha = Blend::One, rt.blendOpAlpha = BlendOp::Add;
    return blend;
}
// STAND-IN
//> // LAB 1: additive blending (the fire's): the particle's colour, weighted by its alpha, added to
//> // what is behind it, for colour and alpha:
//> //   rgb = src.rgb * src.a + dst.rgb,   a = src.a * src.a + dst.a
//> // Used by the three panels of the top row. Does the order of the particles matter then?
//> // As handed out blending is off: each particle's quad replaces what is behind it, an opaque square.
//> BlendState additiveBlend() {
    //> BlendState blend;
    //> return blend;
//> }
// END LAB 1

// BEGIN LAB 2
// LAB 2: no depth test (and so no depth write): every fragment reaches the blend.
DepthStencilState noDepthTest() {
    DepthStencilState depth;
    depth.depthEnable = false;
    depth.depthWriteMask = false;
    return depth;
}
// STAND-IN
//> // LAB 2: the figure "no depth test: even the giraffe does not occlude": no depth test at all (and
//> // then nothing is written to the depth buffer either). The top row's middle panel.
//> // As handed out: D3D11's default, test Less and write, the same as the first panel.
//> DepthStencilState noDepthTest() {
    //> DepthStencilState depth;
    //> return depth;
//> }
// END LAB 2

// BEGIN LAB 3
// LAB 3: the depth test stays (the occluder hides what is behind it), the depth write goes (a quad's
// transparent corners must not hide the particles drawn after it).
DepthStencilState depthTestNoWrite() {
    DepthStencilState depth;
    depth.depthEnable = true;
    depth.depthWriteMask = false;
    depth.depthFunc = ComparisonFunc::Less;
    return depth;
}
// STAND-IN
//> // LAB 3: "depth test stays, depth write off": the occluder must still hide the particles behind it,
//> // but a particle must not hide the ones drawn after it (its quad's transparent corners would cut
//> // them out in squares, as the first panel shows). The top row's right panel and both "over" panels.
//> // As handed out: test and write.
//> DepthStencilState depthTestNoWrite() {
    //> DepthStencilState depth;
    //> return depth;
//> }
// END LAB 3

// BEGIN LAB 4
// LAB 4: "over": SRC_ALPHA, INV_SRC_ALPHA, ADD, for colour and alpha.
BlendState overBlend() {
    BlendState blend;
    RenderTargetBlendDesc& rt = blend.renderTarget[0];
    rt.blendEnable = true;
    rt.srcBlend = Blend::SrcAlpha, rt.destBlend = Blend::InvSrcAlpha, rt.blendOp = BlendOp::Add;
    rt.srcBlendAlpha = Blend::SrcAlpha, rt.destBlendAlpha = Blend::InvSrcAlpha,
    rt.blendOpAlpha = BlendOp::Add;
    return blend;
}
// STAND-IN
//> // LAB 4: alpha blending, "over": the particle covers what is behind it by its alpha, for colour and
//> // alpha:
//> //   rgb = src.rgb * src.a + dst.rgb * (1 - src.a),   a = src.a * src.a + dst.a * (1 - src.a)
//> // The bottom row. Why does the order matter now, and which order is right?
//> // As handed out blending is off.
//> BlendState overBlend() {
    //> BlendState blend;
    //> return blend;
//> }
// END LAB 4

// ---- The sort -----------------------------------------------------------------------------------

// A particle to sort: its index and its sort key.
struct SortItem {
    uint32_t index;
    float depth;
};

// BEGIN LAB 5
// LAB 5: the view depth, along the camera's forward axis (`ahead`, unit length), from the eye.
float viewDepth(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead) {
    return glm::dot(position - eye, ahead);
}
// STAND-IN
//> // LAB 5: the sort key: how far `position` lies in front of the eye along the camera's forward axis
//> // `ahead` (unit length), in world units (the slide's `pos·ahead`, measured from the eye).
//> // As handed out every particle has depth 0: all tied, and the sort keeps the storage order.
//> float viewDepth(glm::vec3 position, glm::vec3 eye, glm::vec3 ahead) {
    //> (void)position, (void)eye, (void)ahead;
    //> return 0.0f;
//> }
// END LAB 5

// BEGIN LAB 6
// LAB 6: back to front, the farthest first: a plain comparison of the keys, a strict weak ordering.
bool drawnBefore(const SortItem& a, const SortItem& b) {
    return a.depth > b.depth;
}
// STAND-IN
//> // LAB 6: the comparator: true when `a` must be drawn before `b`, so that "over" is right. It must be
//> // a strict weak ordering, or std::sort is undefined behaviour; the slide's
//> //     return a.pos·ahead > b.pos·ahead + 0.01;
//> // is not one (try depths 0, 0.008 and 0.016). The lab checks your comparator on the particles before
//> // it sorts, and stops with the particles that break the rule.
//> // As handed out it sorts front to back: a valid ordering, the wrong one.
//> bool drawnBefore(const SortItem& a, const SortItem& b) {
    //> return a.depth < b.depth;
//> }
// END LAB 6

// ---- The scene (the lab's own: nothing to write below) -------------------------------------------

// The figures, one panel each: top row the additive ones, bottom row "over".
struct Figure {
    const char* title;
    BlendState blend;
    DepthStencilState depth;
    bool sorted;  // back to front with viewDepth and drawnBefore; else in storage order
};
std::vector<Figure> lectureFigures() {
    const DepthStencilState testAndWrite;  // the occluder's: test Less, write
    return {{"blending with the depth test on", additiveBlend(), testAndWrite, false},
            {"no depth test: even the giraffe does not occlude", additiveBlend(), noDepthTest(), false},
            {"depth test stays, depth write off", additiveBlend(), depthTestNoWrite(), false},
            {"wrong order: back ones cover front ones", overBlend(), depthTestNoWrite(), false},
            {"sorting", overBlend(), depthTestNoWrite(), true}};
}

// World units. The particles fill a box around the occluder (x in [-0.6, 0.6], y in [-1.2, 0.4], z = 0),
// half in front of it, half behind; each is a square quad facing +z with a soft disc drawn on it.
constexpr glm::vec3 kBoxHalf{1.2f, 0.9f, 1.2f}, kBoxCentre{0.0f, -0.2f, 0.0f};
constexpr float kHalfSize = 0.15f;
constexpr float kAdditiveOpacity = 0.35f, kOverOpacity = 0.75f;
constexpr glm::vec3 kFarColour{0.1f, 0.3f, 1.0f}, kNearColour{1.0f, 0.75f, 0.1f};
constexpr uint32_t kDefaultCount = 200;
constexpr uint32_t kMaxCount = 4000;  // the comparator check takes count² calls
const SceneCamera kBlendingCamera{{0, 0.2f, 3.2f}, {0, -0.2f, 0}};

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

// The draw order of the sorted figure: the comparator checked first, then std::stable_sort, so that
// particles the comparator ties keep their storage order on every machine. A comparator that is not
// a strict weak ordering makes std::sort and std::stable_sort undefined behaviour (they may read past
// the array and crash); the check stops with the particles that break the rule instead. An insertion
// sort, defined for any comparator, would not crash, but would draw the slide's comparator's order
// without a word, and that order differs from the right one only among particles within 0.01 units.
std::vector<uint32_t> backToFront(std::span<const glm::vec3> centres, glm::vec3 eye, glm::vec3 ahead) {
    std::vector<SortItem> items(centres.size());
    for (uint32_t i = 0; i < centres.size(); ++i) items[i] = {i, viewDepth(centres[i], eye, ahead)};
    if (const auto v = findStrictWeakOrderViolation(std::span<const SortItem>(items), drawnBefore))
        throw Error(ErrorCode::InvalidArgument,
                    "blending: drawnBefore is not a strict weak ordering, and std::sort with it is undefined "
                    "behaviour: " +
                        orderViolationText(*v, "drawnBefore", [&](size_t k) {
                            return "particle " + std::to_string(items[k].index) + " (depth " +
                                   std::to_string(items[k].depth) + ")";
                        }));
    std::stable_sort(items.begin(), items.end(), drawnBefore);
    std::vector<uint32_t> order(items.size());
    for (size_t i = 0; i < items.size(); ++i) order[i] = items[i].index;
    return order;
}

// Six indices (two triangles) per particle, in the order given.
std::vector<uint32_t> quadIndices(std::span<const uint32_t> order) {
    std::vector<uint32_t> indices;
    for (const uint32_t p : order)
        for (const uint32_t corner : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(4 * p + corner);
    return indices;
}

// Five panels of (width / 3) × (height / 2) pixels: three on top, two centred below. Each draws the
// occluder (opaque: depth test and write) and then the particles with its figure's states.
class BlendingLab final : public LabScene {
  public:
    explicit BlendingLab(const SceneOptions& o)
        : panel_(panelOptions(o)), data_(panel_), figures_(lectureFigures()), layout_(kQuadElements) {
        const uint32_t count = o.count.value_or(kDefaultCount);
        if (count > kMaxCount)
            throw Error(ErrorCode::InvalidArgument,
                        "blending: count " + std::to_string(count) + " above " + std::to_string(kMaxCount));
        std::vector<QuadVertex> quads;
        makeParticles(count, o.seed, centres_, quads);
        vertices_ = VertexBuffer::create(std::span<const QuadVertex>(quads));
        vs_.viewProj = data_.viewProj;
        eye_ = panel_.camera->eye;
        ahead_ = glm::normalize(panel_.camera->target - panel_.camera->eye);
        std::vector<uint32_t> stored(count);
        std::iota(stored.begin(), stored.end(), 0u);
        stored_ = IndexBuffer::create(quadIndices(stored));
    }

    void render(Context& context, RenderTarget& color, DepthTarget& depth) override {
        beginSceneFrame(context, color, depth);  // clear, bind, viewport, no culling
        const IndexBuffer sorted = IndexBuffer::create(
            quadIndices(backToFront(centres_, eye_, ahead_)));  // every frame, as a moving camera needs
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
            context.drawIndexed(vs_, ps, uint32_t(6 * centres_.size()));  // draws 1, 3, 5, 7, 9
        }
    }

  private:
    static SceneOptions panelOptions(const SceneOptions& o) {
        SceneOptions p = o;
        p.width = std::max(1u, o.width / 3), p.height = std::max(1u, o.height / 2);
        p.count = 0;  // the occluder and the camera only
        p.camera = o.camera.value_or(kBlendingCamera);
        return p;
    }

    SceneOptions panel_;
    ParticleSceneData data_;  // the occluder and P·V for the panel's aspect
    std::vector<Figure> figures_;
    InputLayout layout_;
    std::vector<glm::vec3> centres_;
    VertexBuffer vertices_;
    IndexBuffer stored_;
    VsQuad vs_;
    glm::vec3 eye_{0.0f}, ahead_{0.0f, 0.0f, -1.0f};
};

}  // namespace

RASTER_LAB("blending", "Lab: blending, depth and sorting (lecture 11, part 3)", BlendingLab, kBlendingCamera)
