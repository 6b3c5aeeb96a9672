#include "grade/diagnose.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <utility>

#include "raster/stages/7_rasterizer.hpp"

namespace raster::grade {
namespace {

template <class... Args>
std::string fmt(const char* format, Args... args) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, format, args...);
    return buffer;
}

std::string colour(const glm::vec4& c) {
    return fmt("(%.3f, %.3f, %.3f, %.3f)", c.x, c.y, c.z, c.w);
}

// Equal as recorded, NaN equal to NaN (an unshaded fragment's output is NaN on both sides).
bool same(float a, float b) {
    return a == b || (std::isnan(a) && std::isnan(b));
}
bool same(const glm::vec4& a, const glm::vec4& b) {
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.w, b.w);
}

const TraceDraw* findDraw(const Trace& trace, uint32_t draw) {
    for (const TraceDraw& d : trace.draws())
        if (d.draw == draw) return &d;
    return nullptr;
}

struct Found {
    DiagnosisStage stage;
    std::string text;
    bool nonFinite = false;  // Diagnosis::nonFiniteOutput
};

std::string blendName(Blend b) {
    return "Blend::" + std::string(name(b));
}
std::string opName(BlendOp o) {
    return "BlendOp::" + std::string(name(o));
}
std::string funcName(ComparisonFunc f) {
    return "ComparisonFunc::" + std::string(name(f));
}
const char* onOff(bool on) {
    return on ? "on" : "off";
}

void addIfDifferent(std::vector<std::string>& out, const std::string& prefix, const char* what,
                    const std::string& yours, const std::string& theirs) {
    if (yours != theirs)
        out.push_back(prefix + "your " + what + " is " + yours + " where the solution's is " + theirs);
}

// ---- Which primitive of the solution's is yours: the same vertices ----

// One input primitive in both frames: your primitive `mine` and the solution's `theirs`, the same
// number unless the draws order their primitives otherwise (alignDraw).
struct Ids {
    uint32_t mine, theirs;
};

// Whether input primitive p of d was recorded with its vertices (TraceDraw::primitiveVertices).
bool hasVertices(const TraceDraw& d, uint32_t p) {
    const uint32_t n = d.verticesPerPrimitive;
    return n != 0 && d.primitivesPerInstance != 0 && (uint64_t(p) + 1) * n <= d.primitiveVertices.size();
}
// Primitive p of a and primitive q of b are one primitive: the same instance, the same vertex indices.
bool sameVertices(const TraceDraw& a, uint32_t p, const TraceDraw& b, uint32_t q) {
    const uint32_t n = a.verticesPerPrimitive;
    return hasVertices(a, p) && hasVertices(b, q) && n == b.verticesPerPrimitive &&
           p / a.primitivesPerInstance == q / b.primitivesPerInstance &&
           std::equal(a.primitiveVertices.begin() + size_t(p) * n,
                      a.primitiveVertices.begin() + size_t(p + 1) * n,
                      b.primitiveVertices.begin() + size_t(q) * n);
}
// "(4, 5, 6)" (", instance 2" after it past the first instance).
std::string verticesText(const TraceDraw& d, uint32_t p) {
    if (!hasVertices(d, p)) return "(not recorded)";
    std::string out = "(";
    for (uint32_t k = 0; k < d.verticesPerPrimitive; ++k)
        out += fmt(k ? ", %u" : "%u", d.primitiveVertices[size_t(p) * d.verticesPerPrimitive + k]);
    out += ")";
    if (const uint32_t instance = p / d.primitivesPerInstance) out += fmt(", instance %u", instance);
    return out;
}
// How many primitives of d before p have p's vertices.
size_t occurrence(const TraceDraw& d, uint32_t p) {
    size_t k = 0;
    for (uint32_t j = 0; j < p; ++j) k += sameVertices(d, j, d, p);
    return k;
}
// The primitive of `to` with the vertices of primitive p of `from` (the k-th such for the k-th such:
// a primitive drawn twice matches twice); none when `to` has no more of them or either side did not
// record them.
std::optional<uint32_t> counterpart(const TraceDraw& from, uint32_t p, const TraceDraw& to) {
    if (!hasVertices(from, p) || to.verticesPerPrimitive != from.verticesPerPrimitive) return std::nullopt;
    size_t k = occurrence(from, p);
    const uint32_t count = uint32_t(to.primitiveVertices.size() / to.verticesPerPrimitive);
    for (uint32_t q = 0; q < count; ++q)
        if (sameVertices(from, p, to, q) && k-- == 0) return q;
    return std::nullopt;
}
// How many primitives of d have the vertices of primitive p of `of`.
size_t countWith(const TraceDraw& d, const TraceDraw& of, uint32_t p) {
    size_t k = 0;
    const uint32_t count =
        d.verticesPerPrimitive ? uint32_t(d.primitiveVertices.size() / d.verticesPerPrimitive) : 0;
    for (uint32_t q = 0; q < count; ++q) k += sameVertices(of, p, d, q);
    return k;
}

// ---- The input assembler and the vertex shader, vertex by vertex ----

// The record of buffer vertex `index` of `instance`; none when not recorded.
std::optional<size_t> vertexRecord(const TraceDraw& d, uint32_t instance, uint32_t index) {
    for (size_t i = 0; i < d.vertices.size(); ++i)
        if (d.vertices[i].index == index && d.vertices[i].instance == instance) return i;
    return std::nullopt;
}

// Records to compare for input primitive p, (yours, the solution's): the primitive's own vertices first
// when both traces recorded them; then a point list's own vertex (record p: the fetch order of a draw
// that is not indexed, instances counted on), or every record both traces hold, in order (the callers
// stop at the first pair fetched from different vertices).
std::vector<std::pair<size_t, size_t>> verticesOf(const TraceDraw& a, const TraceDraw& b, Ids p) {
    std::vector<std::pair<size_t, size_t>> out;
    if (hasVertices(a, p.mine) && hasVertices(b, p.theirs)) {
        const uint32_t n = a.verticesPerPrimitive, instance = p.mine / a.primitivesPerInstance;
        for (uint32_t k = 0; k < n && k < b.verticesPerPrimitive; ++k) {
            const auto i = vertexRecord(a, instance, a.primitiveVertices[size_t(p.mine) * n + k]);
            const auto j = vertexRecord(b, p.theirs / b.primitivesPerInstance,
                                        b.primitiveVertices[size_t(p.theirs) * b.verticesPerPrimitive + k]);
            if (i && j) out.emplace_back(*i, *j);
        }
    }
    const size_t n = std::min(a.vertices.size(), b.vertices.size());
    if (a.topology == Topology::PointList) {
        if (p.mine < n && p.theirs < n) out.emplace_back(p.mine, p.theirs);
        return out;
    }
    for (size_t i = 0; i < n; ++i) out.emplace_back(i, i);
    return out;
}

const TraceField* fieldNamed(const TraceDraw& d, const std::string& name) {
    for (const TraceField& f : d.inputFields)
        if (f.name == name) return &f;
    return nullptr;
}

// A field's first `components` recorded floats; empty when the record is too short.
std::vector<float> fieldValue(const TraceVertex& v, const TraceField& f, uint32_t components) {
    if (f.offset + components > v.input.size()) return {};
    return {v.input.begin() + f.offset, v.input.begin() + f.offset + components};
}
// "(a, b, c)", or "a" for one value.
std::string values(const std::vector<float>& v) {
    std::string out = v.size() > 1 ? "(" : "";
    for (size_t i = 0; i < v.size(); ++i) out += fmt(i ? ", %.4g" : "%.4g", v[i]);
    return out + (v.size() > 1 ? ")" : "");
}
bool same(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](float x, float y) { return same(x, y); });
}

// What a wrong element reads instead, when the solution's input shows it: another field's value (an
// offset copied from that field), or the defaults (0, 0, 0, 1) past the element's last component (a
// format too narrow for the field).
std::string inputHint(const TraceDraw& theirs, const TraceVertex& b, const TraceField& field,
                      const std::vector<float>& mine, const std::vector<float>& solution) {
    for (const TraceField& other : theirs.inputFields)
        if (other.name != field.name && other.components >= mine.size() &&
            same(fieldValue(b, other, uint32_t(mine.size())), mine))
            return ": yours holds what the solution reads as " + other.name +
                   " (is the element's AlignedByteOffset that field's offsetof?)";
    static constexpr float kDefaults[4] = {0, 0, 0, 1};
    for (size_t k = 1; k < mine.size(); ++k) {
        bool defaults = true;
        for (size_t c = k; c < mine.size(); ++c) defaults = defaults && mine[c] == kDefaults[c];
        if (defaults && std::equal(mine.begin(), mine.begin() + long(k), solution.begin()))
            return fmt(
                ": yours has the first %zu component%s and the defaults (0, 0, 0, 1) after them (is the "
                "element's Format too narrow for the field?)",
                k, k == 1 ? "" : "s");
    }
    // Neither: the buffer itself may hold another value (a lab that computes its vertices, such as a
    // particle simulation's) or the element may read it otherwise.
    return ": the vertex buffer holds another value (check what your code computes and uploads into it) or "
           "the element reads it otherwise (check its Format, the field's type, and AlignedByteOffset, "
           "offsetof of the field)";
}

// The vertex shader's input, field by field by semantic: what the input assembler handed it.
std::optional<Found> inputDifference(const TraceDraw& yours, const TraceDraw& theirs, Ids p) {
    for (const auto& [i, j] : verticesOf(yours, theirs, p)) {
        const TraceVertex &a = yours.vertices[i], &b = theirs.vertices[j];
        if (a.index != b.index || a.instance != b.instance) return std::nullopt;  // other draws: not the IA
        for (const TraceField& f : yours.inputFields) {
            const TraceField* g = fieldNamed(theirs, f.name);
            if (!g) continue;
            const uint32_t n = std::min(f.components, g->components);
            const std::vector<float> mine = fieldValue(a, f, n), solution = fieldValue(b, *g, n);
            if (mine.empty() || solution.empty() || same(mine, solution)) continue;
            return Found{
                DiagnosisStage::InputAssembler,
                fmt("the input assembler fetched vertex %u (instance %u) with ", a.index, a.instance) +
                    f.name + " = " + values(mine) + " where the solution's is " + values(solution) +
                    inputHint(theirs, b, *g, mine, solution)};
        }
    }
    return std::nullopt;
}

// Clip-space position to pixels, for the whole-target viewport every scene sets (beginSceneFrame).
glm::vec2 toPixels(const glm::vec4& clip, const Trace& trace) {
    return {(clip.x / clip.w * 0.5f + 0.5f) * float(trace.width()),
            (0.5f - clip.y / clip.w * 0.5f) * float(trace.height())};
}

// "SV_Position is (...) where the solution's is (...): on screen (...) against (...); x differs by ..."
std::string positionText(const glm::vec4& mine, const glm::vec4& theirs, const Trace& trace) {
    const glm::vec2 s = toPixels(mine, trace), t = toPixels(theirs, trace);
    std::string text =
        fmt("SV_Position is (%.4g, %.4g, %.4g, %.4g) where the solution's is (%.4g, %.4g, %.4g, "
            "%.4g): on screen (%.2f, %.2f) against (%.2f, %.2f)",
            mine.x, mine.y, mine.z, mine.w, theirs.x, theirs.y, theirs.z, theirs.w, s.x, s.y, t.x, t.y);
    if (s.x != t.x) text += fmt("; x differs by %+.2f pixel", s.x - t.x);
    if (s.y != t.y) text += fmt("; y differs by %+.2f pixel", s.y - t.y);
    return text;
}

// The vertex shader's outputs given the same inputs (inputDifference found none).
std::optional<Found> vsOutputDifference(const Trace& trace, const TraceDraw& yours, const TraceDraw& theirs,
                                        Ids p) {
    if (yours.vsFloats != theirs.vsFloats || yours.vsPosition != theirs.vsPosition) return std::nullopt;
    const uint32_t at = yours.vsPosition;
    for (const auto& [i, j] : verticesOf(yours, theirs, p)) {
        const TraceVertex &a = yours.vertices[i], &b = theirs.vertices[j];
        if (a.index != b.index || a.instance != b.instance) return std::nullopt;
        const size_t n = std::min(a.output.size(), b.output.size());
        if (at + 4 <= n) {
            const glm::vec4 mine(a.output[at], a.output[at + 1], a.output[at + 2], a.output[at + 3]);
            const glm::vec4 solution(b.output[at], b.output[at + 1], b.output[at + 2], b.output[at + 3]);
            if (!same(mine, solution))
                return Found{
                    DiagnosisStage::VertexShader,
                    fmt("the vertex shader's output for vertex %u (instance %u), from the same input: its ",
                        a.index, a.instance) +
                        positionText(mine, solution, trace)};
        }
        for (size_t c = 0; c < n; ++c)
            if (!same(a.output[c], b.output[c]))
                return Found{
                    DiagnosisStage::VertexShader,
                    fmt("the vertex shader's output for vertex %u (instance %u), from the same input, "
                        "differs in float %zu: %.4g where the solution's is %.4g",
                        a.index, a.instance, c, a.output[c], b.output[c])};
    }
    return std::nullopt;
}

// ---- Geometry of one input primitive ----

// Triangles a geometry shader's output strips make for input primitive p: n − 2 per strip of n.
std::pair<size_t, size_t> gsOutput(const TraceDraw& d, uint32_t p) {
    size_t vertices = 0, triangles = 0, strip = 0;
    for (const TraceGsVertex& v : d.gsVertices) {
        if (v.primitive != p) continue;
        if (v.startsStrip) triangles += strip >= 3 ? strip - 2 : 0, strip = 0;
        ++vertices, ++strip;
    }
    triangles += strip >= 3 ? strip - 2 : 0;
    return {vertices, triangles};
}

std::vector<const TracePrimitive*> primitivesOf(const TraceDraw& d, uint32_t p) {
    std::vector<const TracePrimitive*> out;
    for (const TracePrimitive& prim : d.primitives)
        if (prim.primitive == p) out.push_back(&prim);
    return out;
}

std::optional<Found> gsCountDifference(const TraceDraw& yours, const TraceDraw& theirs, Ids p) {
    if (yours.geometryShader.empty() || theirs.geometryShader.empty()) return std::nullopt;
    const auto [your_vertices, your_triangles] = gsOutput(yours, p.mine);
    const auto [their_vertices, their_triangles] = gsOutput(theirs, p.theirs);
    if (your_vertices == their_vertices && your_triangles == their_triangles) return std::nullopt;
    return Found{DiagnosisStage::GeometryShader,
                 fmt("the geometry shader emitted %zu triangle%s (%zu vertices) for this input primitive "
                     "(solution: %zu triangle%s, %zu vertices)",
                     your_triangles, your_triangles == 1 ? "" : "s", your_vertices, their_triangles,
                     their_triangles == 1 ? "" : "s", their_vertices)};
}

// The SV_Position of each vertex the geometry shader emitted for input primitive p, in order.
std::vector<glm::vec4> gsPositions(const TraceDraw& d, uint32_t p) {
    std::vector<glm::vec4> out;
    for (const TraceGsVertex& v : d.gsVertices)
        if (v.primitive == p && v.values.size() >= d.gsPosition + 4)
            out.emplace_back(v.values[d.gsPosition], v.values[d.gsPosition + 1], v.values[d.gsPosition + 2],
                             v.values[d.gsPosition + 3]);
    return out;
}

// The geometry shader's output positions for input primitive p, vertex by vertex.
std::optional<Found> gsPositionDifference(const Trace& yours, const TraceDraw& a, const TraceDraw& b, Ids p) {
    if (a.geometryShader.empty() || a.gsFloats < 4 || b.gsFloats < 4) return std::nullopt;
    const std::vector<glm::vec4> mine = gsPositions(a, p.mine), theirs = gsPositions(b, p.theirs);
    for (size_t k = 0; k < std::min(mine.size(), theirs.size()); ++k) {
        if (same(mine[k], theirs[k])) continue;
        std::string text =
            fmt("the geometry shader output vertex %zu's ", k) + positionText(mine[k], theirs[k], yours);
        if (mine[k].w != theirs[k].w)
            text += fmt(
                "; w is %.4g where the solution's is %.4g: the rasterizer divides by w itself (was an offset "
                "added after a division by w?)",
                mine[k].w, theirs[k].w);
        return Found{DiagnosisStage::GeometryShader, text};
    }
    return std::nullopt;
}

std::optional<Found> positionDifference(const TraceDraw& yours, const TraceDraw& theirs, Ids p) {
    const bool gs = !yours.geometryShader.empty();
    const DiagnosisStage stage = gs ? DiagnosisStage::GeometryShader : DiagnosisStage::VertexShader;
    const char* shader = gs ? "geometry shader" : "vertex shader";
    const std::vector<const TracePrimitive*> a = primitivesOf(yours, p.mine),
                                             b = primitivesOf(theirs, p.theirs);
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        if (a[i]->vertexCount != b[i]->vertexCount) break;
        for (int k = 0; k < a[i]->vertexCount; ++k) {
            const glm::vec4 s = a[i]->screen[k], t = b[i]->screen[k];
            if (same(s, t)) continue;
            std::string text =
                fmt("%s output, primitive %zu after setup, vertex %d: at (%.2f, %.2f) depth %.4g where "
                    "the solution's is at (%.2f, %.2f) depth %.4g",
                    shader, i, k, s.x, s.y, s.z, t.x, t.y, t.z);
            if (s.x != t.x) text += fmt("; x differs by %+.2f pixel", s.x - t.x);
            if (s.y != t.y) text += fmt("; y differs by %+.2f pixel", s.y - t.y);
            if (s.w != t.w) text += fmt("; w differs (%.4g against %.4g)", s.w, t.w);
            return Found{stage, text};
        }
    }
    if (a.size() != b.size())
        return Found{
            DiagnosisStage::Rasterizer,
            fmt("this input primitive became %zu primitive%s after clipping and setup (solution: %zu)",
                a.size(), a.size() == 1 ? "" : "s", b.size())};
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i]->fate != b[i]->fate)
            return Found{DiagnosisStage::Rasterizer, fmt("primitive %zu after setup was %s (solution: %s)", i,
                                                         toString(a[i]->fate), toString(b[i]->fate))};
    return std::nullopt;
}

std::optional<Found> attributeDifference(const TraceDraw& yours, const TraceDraw& theirs, Ids p) {
    if (yours.geometryShader.empty() || yours.gsFloats != theirs.gsFloats) return std::nullopt;
    std::vector<const TraceGsVertex*> a, b;
    for (const TraceGsVertex& v : yours.gsVertices)
        if (v.primitive == p.mine) a.push_back(&v);
    for (const TraceGsVertex& v : theirs.gsVertices)
        if (v.primitive == p.theirs) b.push_back(&v);
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        for (size_t c = 0; c < std::min(a[i]->values.size(), b[i]->values.size()); ++c)
            if (!same(a[i]->values[c], b[i]->values[c]))
                return Found{
                    DiagnosisStage::GeometryShader,
                    fmt("the geometry shader's output vertex %zu differs in float %zu of its output: %.4g "
                        "where the solution's is %.4g",
                        i, c, a[i]->values[c], b[i]->values[c])};
    return std::nullopt;
}

std::optional<Found> geometryDifference(const Trace& yours, const Trace& theirs, uint32_t draw, Ids p) {
    const TraceDraw* a = findDraw(yours, draw);
    const TraceDraw* b = findDraw(theirs, draw);
    if (!a || !b)
        return Found{DiagnosisStage::Draw,
                     fmt("draw %u is in %s frame only (yours has %zu draws, the solution's %zu)", draw,
                         a ? "your" : "the solution's", yours.draws().size(), theirs.draws().size())};
    if (a->geometryShader.empty() != b->geometryShader.empty())
        return Found{DiagnosisStage::Draw, std::string("your draw ") +
                                               (a->geometryShader.empty() ? "has no" : "has a") +
                                               " geometry shader, the solution's " +
                                               (b->geometryShader.empty() ? "has none" : "has one")};
    if (a->topology != b->topology)
        return Found{DiagnosisStage::Draw, "the draw's primitive topology differs"};
    if (auto found = inputDifference(*a, *b, p)) return found;
    if (auto found = vsOutputDifference(yours, *a, *b, p)) return found;
    if (auto found = gsCountDifference(*a, *b, p)) return found;
    if (auto found = gsPositionDifference(yours, *a, *b, p)) return found;
    if (auto found = positionDifference(*a, *b, p)) return found;
    return attributeDifference(*a, *b, p);
}

// ---- One fragment against the solution's ----

bool depthPassed(const TraceFragment& f) {
    return f.fate != FragmentFate::EarlyDepthFailed && f.fate != FragmentFate::LateDepthFailed;
}

std::optional<Found> depthDifference(const TraceFragment& a, const TraceFragment& b) {
    if (depthPassed(a) != depthPassed(b)) {
        std::string text =
            fmt("your fragment %s the depth test, the solution's %s (%.4g against a stored %.4g; "
                "the solution's %.4g against %.4g)",
                depthPassed(a) ? "passed" : "failed", depthPassed(b) ? "passed" : "failed", a.depth,
                a.depthBefore, b.depth, b.depthBefore);
        if (!same(a.depthBefore, b.depthBefore))
            text += a.depthBefore < b.depthBefore
                        ? ": the stored depth is nearer in yours: is depth write on for "
                          "an earlier fragment?"
                        : ": the stored depth is farther in yours: is depth write off?";
        return Found{DiagnosisStage::DepthTest, text};
    }
    if (!same(a.depthAfter, b.depthAfter)) {
        const bool you_wrote = !same(a.depthAfter, a.depthBefore);
        return Found{
            DiagnosisStage::DepthTest,
            you_wrote
                ? fmt("your fragment wrote its depth %.4g over a stored %.4g, the solution's left %.4g: "
                      "is depth write on?",
                      a.depth, a.depthBefore, b.depthAfter)
                : fmt("your fragment left the stored depth %.4g, the solution's wrote its depth %.4g: is "
                      "depth write off?",
                      a.depthAfter, b.depthAfter)};
    }
    return std::nullopt;
}

// Your shaded fragment's output holds a NaN or an infinity where the solution's holds something else:
// named as such (a UNORM target stores NaN as 0 and ∞ as 1, so the picture alone shows only black or
// white), the channels that are, and where such values come from.
std::optional<Found> nonFiniteOutput(const TraceFragment& a, const TraceFragment& b) {
    if (!a.shaded || a.fate == FragmentFate::Discarded) return std::nullopt;
    static const char* const kChannels[4] = {"red", "green", "blue", "alpha"};
    std::string channels;
    bool nan = false;
    for (int c = 0; c < 4; ++c) {
        const float v = a.shaderOutput[c];
        if (std::isfinite(v) || same(v, b.shaderOutput[c])) continue;
        nan = nan || std::isnan(v);
        channels += std::string(channels.empty() ? "" : ", ") + kChannels[c] + " " +
                    (std::isnan(v) ? "NaN" : v > 0 ? "+inf" : "-inf");
    }
    if (channels.empty()) return std::nullopt;
    return Found{DiagnosisStage::PixelShader,
                 fmt("your pixel shader's output is %s at (%d, %d): ", nan ? "NaN" : "infinite", a.x, a.y) +
                     colour(a.shaderOutput) + " (" + channels + "), the solution's " + colour(b.shaderOutput) +
                     ": a 0/0, 0*inf, inf-inf or inf/inf on the way (a division by a value that can be 0, or "
                     "an underflow to 0 times an overflow to inf)",
                 true};
}

std::optional<Found> fragmentDifference(const TraceFragment& a, const TraceFragment& b,
                                        const std::vector<std::string>& blend_differences) {
    if (!same(a.colorBefore, b.colorBefore))
        return Found{DiagnosisStage::Blend, "the colour before this fragment is " + colour(a.colorBefore) +
                                                " where the solution's is " + colour(b.colorBefore) +
                                                ": the clear or an earlier draw left another colour"};
    if (auto found = depthDifference(a, b)) return found;
    const bool a_discarded = a.fate == FragmentFate::Discarded,
               b_discarded = b.fate == FragmentFate::Discarded;
    if (a_discarded != b_discarded)
        return Found{DiagnosisStage::PixelShader,
                     std::string("your pixel shader ") + (a_discarded ? "discarded" : "kept") +
                         " the fragment, the solution's " + (b_discarded ? "discarded it" : "kept it")};
    if (!same(a.shaderOutput, b.shaderOutput)) {
        if (auto found = nonFiniteOutput(a, b)) return found;
        return Found{DiagnosisStage::PixelShader, "your pixel shader returned " + colour(a.shaderOutput) +
                                                      ", the solution's " + colour(b.shaderOutput)};
    }
    if (!same(a.colorAfter, b.colorAfter)) {
        std::string text = "the output merger made " + colour(a.shaderOutput) + " over " +
                           colour(a.colorBefore) + " gives " + colour(a.colorAfter) + " in yours, " +
                           colour(b.colorAfter) + " in the solution's";
        if (!blend_differences.empty()) text = blend_differences.front();
        return Found{DiagnosisStage::Blend, text};
    }
    return std::nullopt;
}

// ---- Coverage: one side's primitive covers the pixel, the other's not, from the same positions ----

// The triangle a traced primitive was set up from (its screen positions are the snapped ones, exact
// in float), clockwise on screen.
std::optional<TriangleSetup> tracedTriangle(const TracePrimitive& p) {
    if (p.kind != PrimitiveKind::Triangle || p.vertexCount != 3 || p.fate != PrimitiveFate::Rasterized)
        return std::nullopt;
    ScreenVertex s[3];
    for (int k = 0; k < 3; ++k) s[k] = {snap(p.screen[k].x), snap(p.screen[k].y), 0.0f, 1.0f};
    RasterizerState rs;
    rs.cullMode = CullMode::None;
    const uint32_t vertex[3] = {0, 1, 2};
    const PixelRect everywhere{INT32_MIN / 2, INT32_MIN / 2, INT32_MAX / 2, INT32_MAX / 2};
    TriangleSetup t;
    if (setupTriangle(s, vertex, 0, rs, everywhere, t) == SetupResult::Degenerate) return std::nullopt;
    return t;
}

// What the pixel's centre is to triangle t, in words a student can act on, given whether your
// render covered it (the solution's, by the library's rule, did the opposite): the two usual causes,
// each named when it explains the difference — the tie-break of a centre exactly on an edge, and
// coverage tested at the pixel's corner (x, y) instead of its centre. "" when neither does.
std::string coverageHint(const TriangleSetup& t, int32_t x, int32_t y, bool yours_covered) {
    std::vector<std::string> hints;
    for (int k = 0; k < 3 && hints.empty(); ++k) {
        const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        // On the edge itself: on its line and inside the other two.
        if (edgeAt(t, k, x, y) != 0 || edgeAt(t, k1, x, y) < 0 || edgeAt(t, k2, x, y) < 0) continue;
        const int32_t dx = t.x[k1] - t.x[k], dy = t.y[k1] - t.y[k];
        const char* side = dy == 0 ? (dx > 0 ? "top" : "bottom") : (dy < 0 ? "left" : "right");
        hints.push_back(
            fmt("its centre (%d.5, %d.5) lies exactly on the triangle's edge from (%.4g, %.4g) to "
                "(%.4g, %.4g), a %s edge, which %s it: the top-left rule gives a centre on an edge "
                "to the triangle only on a top or left edge: check the top-left rule",
                x, y, double(t.x[k]) / kSubpixelOne, double(t.y[k]) / kSubpixelOne,
                double(t.x[k1]) / kSubpixelOne, double(t.y[k1]) / kSubpixelOne, side,
                isTopLeft(dx, dy) ? "covers" : "does not cover"));
    }
    // The library's rule at the pixel's corner: each edge function half a pixel up and left.
    bool corner = true;
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        const int64_t shift = (int64_t(t.x[k1] - t.x[k]) - int64_t(t.y[k1] - t.y[k])) * kSubpixelHalf;
        corner = corner && edgeAt(t, k, x, y) - shift + t.bias[k] >= 0;
    }
    if (corner == yours_covered)
        hints.push_back(
            fmt("its corner (%d, %d) lies %s the triangle, and yours %s the pixel: is coverage "
                "tested at the pixel's centre (x + 0.5, y + 0.5)?",
                x, y, corner ? "inside" : "outside", yours_covered ? "covered" : "did not cover"));
    std::string text;
    for (const std::string& h : hints) text += (text.empty() ? "" : "; or ") + h;
    return text;
}

std::optional<Found> coverageDifference(const Trace& yours, uint32_t draw, Ids p, int32_t x, int32_t y,
                                        size_t mine, size_t theirs) {
    const std::string which = p.mine == p.theirs ? fmt("primitive %u", p.mine)
                                                 : fmt("primitive %u (the solution's %u)", p.mine, p.theirs);
    std::string text =
        mine > theirs
            ? fmt("your rasterizer covered pixel (%d, %d) with ", x, y) + which +
                  fmt(" %zu time%s, the solution's %zu", mine, mine == 1 ? "" : "s", theirs)
            : fmt("your rasterizer did not cover pixel (%d, %d) with ", x, y) + which +
                  fmt(" (%zu fragment%s), the solution's did (%zu)", mine, mine == 1 ? "" : "s", theirs);
    text += " from the same positions after setup";
    std::string hint;
    if (const TraceDraw* d = findDraw(yours, draw))
        for (const TracePrimitive* prim : primitivesOf(*d, p.mine))
            if (const std::optional<TriangleSetup> t = tracedTriangle(*prim); t && hint.empty())
                hint = coverageHint(*t, x, y, mine > theirs);
    text += hint.empty() ? ": compare the rasterizer state (culling, scissor) and the coverage test"
                         : ": " + hint;
    return Found{DiagnosisStage::Rasterizer, text};
}

// ---- Aligning the two histories: which fragment of yours is which of the solution's ----

// One input primitive of one draw in both frames, with its fragments at the pixel in output-merger
// order. A side whose draw lacks the primitive has none (mine or theirs empty, its fragments too).
struct Pair {
    uint32_t draw;
    std::optional<uint32_t> mine, theirs;
    std::vector<TraceFragment> a, b;  // yours of `mine`, the solution's of `theirs`
};

// The primitives of one draw at the pixel, each with its fragments, in the order the output merger
// saw them.
std::vector<std::pair<uint32_t, std::vector<TraceFragment>>> primitivesAt(
    const std::vector<TraceFragment>& history, uint32_t draw) {
    std::vector<std::pair<uint32_t, std::vector<TraceFragment>>> out;
    for (const TraceFragment& f : history) {
        if (f.draw != draw) continue;
        auto it = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.first == f.primitive; });
        if (it == out.end()) it = out.insert(out.end(), {f.primitive, {}});
        it->second.push_back(f);
    }
    return out;
}

// One draw's primitives at the pixel, aligned. By number when numbers and vertices agree (or the
// traces did not record the primitives' vertices); else by vertices (TraceDraw::primitiveVertices):
// your primitive p is the solution's q when both have the same instance and vertex indices, as when
// an index buffer is sorted otherwise. `reordered`: aligned by vertices, the same primitives as the
// solution's at the pixel, in another order.
struct DrawAlignment {
    std::vector<Pair> pairs;  // by vertices: those one side lacks first, then in the solution's order
    bool byVertices = false, reordered = false;
};

DrawAlignment alignDraw(const Trace& yours, const Trace& theirs, uint32_t draw,
                        const std::vector<TraceFragment>& history_a,
                        const std::vector<TraceFragment>& history_b) {
    const auto mine = primitivesAt(history_a, draw), their = primitivesAt(history_b, draw);
    const TraceDraw* a = findDraw(yours, draw);
    const TraceDraw* b = findDraw(theirs, draw);
    std::vector<std::optional<uint32_t>> to_theirs, to_mine;
    bool by_number = true;
    if (a && b && a->verticesPerPrimitive != 0 && a->verticesPerPrimitive == b->verticesPerPrimitive) {
        for (const auto& [q, f] : their) to_mine.push_back(counterpart(*b, q, *a));
        for (const auto& [p, f] : mine) to_theirs.push_back(counterpart(*a, p, *b));
        for (size_t j = 0; j < their.size(); ++j) by_number = by_number && to_mine[j] == their[j].first;
        for (size_t i = 0; i < mine.size(); ++i) by_number = by_number && to_theirs[i] == mine[i].first;
    }
    DrawAlignment out;
    if (by_number) {
        std::map<uint32_t, Pair> pairs;
        for (const auto& [p, f] : mine) pairs.try_emplace(p, Pair{draw, p, p, {}, {}}).first->second.a = f;
        for (const auto& [q, f] : their) pairs.try_emplace(q, Pair{draw, q, q, {}, {}}).first->second.b = f;
        for (auto& [number, pair] : pairs) out.pairs.push_back(std::move(pair));
        return out;
    }
    out.byVertices = true;
    for (size_t j = 0; j < their.size(); ++j) {
        Pair pair{draw, to_mine[j], their[j].first, {}, their[j].second};
        for (const auto& [p, f] : mine)
            if (to_mine[j] == p) pair.a = f;
        out.pairs.push_back(std::move(pair));
    }
    std::vector<uint32_t> sequence, expected;  // the solution's numbers, in your order and in theirs
    for (const auto& [q, f] : their) expected.push_back(q);
    for (size_t i = 0; i < mine.size(); ++i) {
        if (to_theirs[i]) sequence.push_back(*to_theirs[i]);
        if (!to_theirs[i] || std::find(expected.begin(), expected.end(), *to_theirs[i]) == expected.end())
            out.pairs.push_back({draw, mine[i].first, to_theirs[i], mine[i].second, {}});
    }
    // A primitive one side lacks first (the input assembler's difference, before any fragment's), then
    // the solution's order.
    std::stable_sort(out.pairs.begin(), out.pairs.end(), [](const Pair& x, const Pair& y) {
        const auto key = [](const Pair& p) {
            return std::pair{p.mine && p.theirs, p.theirs.value_or(p.mine.value_or(0))};
        };
        return key(x) < key(y);
    });
    std::vector<uint32_t> sorted_sequence = sequence, sorted_expected = expected;
    std::sort(sorted_sequence.begin(), sorted_sequence.end());
    std::sort(sorted_expected.begin(), sorted_expected.end());
    out.reordered = sequence.size() == mine.size() && sequence.size() >= 2 &&
                    sorted_sequence == sorted_expected && sequence != expected;
    return out;
}

// A primitive one side's draw has and the other's lacks, aligned by vertices: the index buffer (or the
// draw's range) holds other primitives than the solution's.
Found missingPrimitive(const TraceDraw& yours, const TraceDraw& theirs, const Pair& pair) {
    if (pair.mine) {
        const size_t in_yours = countWith(yours, yours, *pair.mine),
                     in_theirs = countWith(theirs, yours, *pair.mine);
        return Found{
            DiagnosisStage::InputAssembler,
            fmt("your primitive %u has the vertices ", *pair.mine) + verticesText(yours, *pair.mine) +
                (in_theirs == 0
                     ? std::string(", which no primitive of the solution's draw has")
                     : fmt(", which your draw has %zu times and the solution's %zu", in_yours, in_theirs)) +
                ": your draw's index buffer (or its range) holds other primitives than the solution's "
                "(is every element drawn once, each with its own vertices?)"};
    }
    const size_t in_yours = countWith(yours, theirs, *pair.theirs),
                 in_theirs = countWith(theirs, theirs, *pair.theirs);
    return Found{DiagnosisStage::InputAssembler,
                 fmt("the solution's primitive %u, with the vertices ", *pair.theirs) +
                     verticesText(theirs, *pair.theirs) +
                     (in_yours == 0 ? std::string(", is not in your draw")
                                    : fmt(", is in your draw %zu times and in the solution's %zu", in_yours,
                                          in_theirs)) +
                     ": your draw's index buffer (or its range) holds other primitives than the solution's "
                     "(is every element drawn once, each with its own vertices?)"};
}

// ---- The draw order: the same fragments of one draw, in another order ----

// "from depth 0.9767 to 0.9519 (far to near)": the first and last depths of a draw's fragments at the
// pixel and which is nearer (the ends only: the fragments' depths between need not follow a sort by the
// elements' centres).
std::string direction(const std::vector<const TraceFragment*>& v) {
    return fmt("from depth %.4g to %.4g (%s)", v.front()->depth, v.back()->depth,
               v.front()->depth > v.back()->depth   ? "far to near"
               : v.front()->depth < v.back()->depth ? "near to far"
                                                    : "first and last at one depth");
}

constexpr const char* kOrderHint = ": is the sort key or the comparator wrong (back to front for \"over\")?";

// The order words for one draw: yours against the solution's, then `hint` (": what to check").
std::string orderText(uint32_t draw, const std::vector<const TraceFragment*>& a,
                      const std::vector<const TraceFragment*>& b, const std::string& hint = kOrderHint) {
    return fmt("your draw %u brings the solution's %zu fragments in another order: yours ", draw, a.size()) +
           direction(a) + ", the solution's " + direction(b) + hint;
}

std::vector<const TraceFragment*> pointers(const std::vector<TraceFragment>& history, uint32_t draw) {
    std::vector<const TraceFragment*> out;
    for (const TraceFragment& f : history)
        if (f.draw == draw) out.push_back(&f);
    return out;
}

// Whether a draw takes `primitives` in its vertex buffer's order: instance, then first vertex index,
// strictly ascending (an index buffer of elements as stored, never sorted).
bool inBufferOrder(const TraceDraw& d, const std::vector<uint32_t>& primitives) {
    const auto key = [&](uint32_t p) {
        return std::pair{p / d.primitivesPerInstance,
                         d.primitiveVertices[size_t(p) * d.verticesPerPrimitive]};
    };
    for (size_t i = 1; i < primitives.size(); ++i)
        if (!(key(primitives[i - 1]) < key(primitives[i]))) return false;
    return true;
}

// Aligned by vertices, the same primitives in another order: what the two orders are to each other
// (reversed; yours as stored in the vertex buffer), their numbers, then the order words. Compared
// primitive by primitive, the fragments would look like wrong geometry.
Found vertexOrderDifference(const Trace& yours, const Trace& theirs, const DrawAlignment& alignment,
                            const std::vector<TraceFragment>& history_a,
                            const std::vector<TraceFragment>& history_b, uint32_t draw) {
    std::vector<const Pair*> by_yours;
    for (const Pair& p : alignment.pairs) by_yours.push_back(&p);
    const auto first = [&](const Pair* p) {
        return std::find_if(history_a.begin(), history_a.end(), [&](const TraceFragment& f) {
            return f.draw == draw && f.primitive == *p->mine;
        });
    };
    std::sort(by_yours.begin(), by_yours.end(),
              [&](const Pair* x, const Pair* y) { return first(x) < first(y); });
    std::vector<uint32_t> mine, as_theirs,
        expected;  // yours, yours as the solution's numbers, the solution's
    for (const Pair* p : by_yours) mine.push_back(*p->mine), as_theirs.push_back(*p->theirs);
    for (const Pair& p : alignment.pairs) expected.push_back(*p.theirs);  // in the solution's order
    std::string hint = kOrderHint;
    if (std::equal(as_theirs.begin(), as_theirs.end(), expected.rbegin()))
        hint =
            ": yours is the solution's order reversed: is the comparator's comparison the wrong way round "
            "(back to front, the farthest first, for \"over\")?";
    else if (inBufferOrder(*findDraw(yours, draw), mine) && !inBufferOrder(*findDraw(theirs, draw), expected))
        hint =
            ": yours takes them in the vertex buffer's order, as stored, the solution's not: are they "
            "sorted at all (is the sort key each element's own view depth, and is the sorted order the one "
            "drawn)?";
    std::string numbers_yours, numbers_theirs;
    for (size_t i = 0; i < mine.size() && i < 8; ++i) {
        numbers_yours += fmt(i ? ", %u" : "%u", mine[i]);
        numbers_theirs += fmt(i ? ", %u" : "%u", as_theirs[i]);
    }
    if (mine.size() > 8) numbers_yours += ", ...", numbers_theirs += ", ...";
    return Found{DiagnosisStage::Blend,
                 orderText(draw, pointers(history_a, draw), pointers(history_b, draw), hint) +
                     " (the same primitives, by their vertices: your " + numbers_yours +
                     " in your order are the solution's " + numbers_theirs + ")"};
}

// Without the primitives' vertices: a draw whose fragments at the pixel are the solution's (depth and
// shader output, as a multiset) in another sequence: the primitives were drawn in another order.
std::optional<std::pair<uint32_t, Found>> orderDifference(const std::vector<TraceFragment>& yours,
                                                          const std::vector<TraceFragment>& theirs) {
    std::map<uint32_t, std::pair<std::vector<const TraceFragment*>, std::vector<const TraceFragment*>>> draws;
    for (const TraceFragment& f : yours) draws[f.draw].first.push_back(&f);
    for (const TraceFragment& f : theirs) draws[f.draw].second.push_back(&f);
    const auto sameFragment = [](const TraceFragment* a, const TraceFragment* b) {
        return same(a->depth, b->depth) && same(a->shaderOutput, b->shaderOutput);
    };
    const auto before = [](const TraceFragment* a, const TraceFragment* b) {
        const auto key = [](const TraceFragment* f) {
            return std::array<float, 5>{f->depth, f->shaderOutput.r, f->shaderOutput.g, f->shaderOutput.b,
                                        f->shaderOutput.a};
        };
        return key(a) < key(b);  // NaN outputs compare false both ways: tied, and then compared by same()
    };
    for (auto& [draw, pair] : draws) {
        auto& [a, b] = pair;
        if (a.size() != b.size() || a.size() < 2 || std::equal(a.begin(), a.end(), b.begin(), sameFragment))
            continue;
        std::vector<const TraceFragment*> x = a, y = b;
        std::stable_sort(x.begin(), x.end(), before);
        std::stable_sort(y.begin(), y.end(), before);
        if (!std::equal(x.begin(), x.end(), y.begin(), sameFragment)) continue;
        return std::pair{draw, Found{DiagnosisStage::Blend, orderText(draw, a, b)}};
    }
    return std::nullopt;
}

// The first difference at one primitive: geometry, then coverage, then fragment by fragment.
std::optional<Found> pairDifference(const Trace& yours, const Trace& theirs, const Pair& pair,
                                    bool by_vertices) {
    const TraceDraw* da = findDraw(yours, pair.draw);
    const TraceDraw* db = findDraw(theirs, pair.draw);
    if (by_vertices && da && db && (!pair.mine || !pair.theirs)) return missingPrimitive(*da, *db, pair);
    const Ids ids{*pair.mine, *pair.theirs};
    if (auto found = geometryDifference(yours, theirs, pair.draw, ids)) return found;
    const std::vector<TraceFragment>&a = pair.a, &b = pair.b;
    if (a.size() != b.size()) {
        const int32_t x = !a.empty() ? a.front().x : b.front().x, y = !a.empty() ? a.front().y : b.front().y;
        return coverageDifference(yours, pair.draw, ids, x, y, a.size(), b.size());
    }
    std::vector<std::string> blend_differences;
    for (const std::string& line : drawStateDifferences(yours, theirs, pair.draw))
        if (line.find(" blend: ") != std::string::npos)
            blend_differences.push_back(line.substr(line.find(": ") + 2));
    for (size_t i = 0; i < a.size(); ++i)
        if (auto found = fragmentDifference(a[i], b[i], blend_differences)) return found;
    return std::nullopt;
}

// "pixel (x, y), draw d, primitive p: ", or "..., your primitive p (the solution's q): " when aligned by
// vertices; "pixel (x, y), draw d: " for a primitive one side lacks (the text names it).
std::string where(int32_t x, int32_t y, const Pair& pair) {
    if (!pair.mine || !pair.theirs) return fmt("pixel (%d, %d), draw %u: ", x, y, pair.draw);
    if (*pair.mine == *pair.theirs)
        return fmt("pixel (%d, %d), draw %u, primitive %u: ", x, y, pair.draw, *pair.mine);
    return fmt("pixel (%d, %d), draw %u, your primitive %u (the solution's %u): ", x, y, pair.draw,
               *pair.mine, *pair.theirs);
}

}  // namespace

const char* stageName(DiagnosisStage stage) {
    switch (stage) {
        case DiagnosisStage::None:
            return "none";
        case DiagnosisStage::Draw:
            return "draw";
        case DiagnosisStage::InputAssembler:
            return "input assembler";
        case DiagnosisStage::VertexShader:
            return "vertex shader";
        case DiagnosisStage::GeometryShader:
            return "geometry shader";
        case DiagnosisStage::Rasterizer:
            return "rasterizer";
        case DiagnosisStage::DepthTest:
            return "depth test";
        case DiagnosisStage::PixelShader:
            return "pixel shader";
        case DiagnosisStage::Blend:
            return "blend";
    }
    return "?";
}

std::vector<std::string> drawStateDifferences(const Trace& submission, const Trace& solution, uint32_t draw) {
    const TraceDraw* a = findDraw(submission, draw);
    const TraceDraw* b = findDraw(solution, draw);
    std::vector<std::string> out;
    if (!a || !b) return out;
    const RenderTargetBlendDesc &x = a->blend.target(0), &y = b->blend.target(0);
    const std::string blend = fmt("draw %u blend: ", draw);
    addIfDifferent(out, blend, "blending", onOff(x.blendEnable), onOff(y.blendEnable));
    if (x.blendEnable || y.blendEnable) {
        addIfDifferent(out, blend, "source factor", blendName(x.srcBlend), blendName(y.srcBlend));
        addIfDifferent(out, blend, "destination factor", blendName(x.destBlend), blendName(y.destBlend));
        addIfDifferent(out, blend, "operation", opName(x.blendOp), opName(y.blendOp));
        addIfDifferent(out, blend, "alpha source factor", blendName(x.srcBlendAlpha),
                       blendName(y.srcBlendAlpha));
        addIfDifferent(out, blend, "alpha destination factor", blendName(x.destBlendAlpha),
                       blendName(y.destBlendAlpha));
        addIfDifferent(out, blend, "alpha operation", opName(x.blendOpAlpha), opName(y.blendOpAlpha));
    }
    addIfDifferent(out, blend, "write mask", fmt("0x%X", x.renderTargetWriteMask),
                   fmt("0x%X", y.renderTargetWriteMask));
    const RasterizerState &r = a->rasterizer, &t = b->rasterizer;
    const std::string rasterizer = fmt("draw %u rasterizer: ", draw);
    addIfDifferent(out, rasterizer, "cull mode", "CullMode::" + std::string(name(r.cullMode)),
                   "CullMode::" + std::string(name(t.cullMode)));
    addIfDifferent(out, rasterizer, "fill mode", "FillMode::" + std::string(name(r.fillMode)),
                   "FillMode::" + std::string(name(t.fillMode)));
    addIfDifferent(out, rasterizer, "front face", r.frontCounterClockwise ? "counter-clockwise" : "clockwise",
                   t.frontCounterClockwise ? "counter-clockwise" : "clockwise");
    auto scissor = [](const RasterizerState& s) {
        return s.scissorEnable
                   ? fmt("[%d, %d) x [%d, %d)", s.scissorLeft, s.scissorRight, s.scissorTop, s.scissorBottom)
                   : std::string("off");
    };
    addIfDifferent(out, rasterizer, "scissor", scissor(r), scissor(t));
    addIfDifferent(out, rasterizer, "depth clip", onOff(r.depthClipEnable), onOff(t.depthClipEnable));
    addIfDifferent(out, rasterizer, "coverage", a->coverageTest ? "the lab's test" : "the library's rule",
                   b->coverageTest ? "the lab's test" : "the library's rule");
    const DepthStencilState &p = a->depthStencil, &q = b->depthStencil;
    const std::string depth = fmt("draw %u depth-stencil: ", draw);
    addIfDifferent(out, depth, "depth test", onOff(p.depthEnable), onOff(q.depthEnable));
    if (p.depthEnable || q.depthEnable) {
        addIfDifferent(out, depth, "depth write", onOff(p.depthWriteMask), onOff(q.depthWriteMask));
        addIfDifferent(out, depth, "depth function", funcName(p.depthFunc), funcName(q.depthFunc));
    }
    return out;
}
Diagnosis diagnosePixel(const Trace& submission, const Trace& solution, int32_t x, int32_t y) {
    Diagnosis d;
    const std::vector<TraceFragment>&mine = submission.pixelHistory(x, y),
          &theirs = solution.pixelHistory(x, y);
    std::vector<uint32_t> draws;
    for (const auto* history : {&mine, &theirs})
        for (const TraceFragment& f : *history) draws.push_back(f.draw);
    std::sort(draws.begin(), draws.end());
    draws.erase(std::unique(draws.begin(), draws.end()), draws.end());
    std::vector<DrawAlignment> alignments;
    for (const uint32_t draw : draws)
        alignments.push_back(alignDraw(submission, solution, draw, mine, theirs));
    // The order first: compared primitive by primitive, another order would read as other geometry.
    std::optional<std::pair<uint32_t, Found>> order;
    for (size_t k = 0; k < draws.size() && !order; ++k)
        if (alignments[k].reordered)
            order = std::pair{
                draws[k], vertexOrderDifference(submission, solution, alignments[k], mine, theirs, draws[k])};
    if (!order) order = orderDifference(mine, theirs);
    if (order) {
        d.stage = order->second.stage;
        d.headline = fmt("pixel (%d, %d), draw %u: ", x, y, order->first) + order->second.text;
        const std::vector<std::string> states = drawStateDifferences(submission, solution, order->first);
        if (!states.empty())  // a state to fix as well, whatever the order (the sort changes no state)
            d.headline += "; besides, " + states.front().substr(states.front().find(": ") + 2);
        d.details = states;
        alignments.clear();
    }
    for (const DrawAlignment& alignment : alignments) {
        for (const Pair& pair : alignment.pairs) {
            const std::optional<Found> found =
                pairDifference(submission, solution, pair, alignment.byVertices);
            if (!found) continue;
            d.stage = found->stage;
            d.nonFiniteOutput = found->nonFinite;
            d.headline = where(x, y, pair) + found->text;
            d.details = drawStateDifferences(submission, solution, pair.draw);
            break;
        }
        if (d.stage != DiagnosisStage::None) break;
    }
    if (d.stage == DiagnosisStage::None) {
        d.headline =
            fmt("pixel (%d, %d): its history is the same in your render and the solution's (%zu fragments)",
                x, y, mine.size());
        const size_t count = std::max(submission.draws().size(), solution.draws().size());
        for (uint32_t draw = 0; draw < count; ++draw)
            for (const std::string& line : drawStateDifferences(submission, solution, draw))
                d.details.push_back(line);
    }
    d.details.push_back(
        fmt("fragments at this pixel: %zu in yours, %zu in the solution's", mine.size(), theirs.size()));
    return d;
}

}  // namespace raster::grade
