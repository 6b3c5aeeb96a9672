#include "grade/trace_json.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>

#include "raster/check.hpp"

namespace raster::grade {
namespace {

using Json = nlohmann::json;

Json number(float v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return double(v);
}

Json floats(const float* v, size_t n) {
    Json out = Json::array();
    for (size_t i = 0; i < n; ++i) out.push_back(number(v[i]));
    return out;
}
Json floats(const std::vector<float>& v) {
    return floats(v.data(), v.size());
}
Json vec4(const glm::vec4& v) {
    return floats(&v.x, 4);
}

Json blendJson(const BlendState& blend) {
    const RenderTargetBlendDesc& t = blend.target(0);
    return {t.blendEnable,        int(t.srcBlend),       int(t.destBlend),    int(t.blendOp),
            int(t.srcBlendAlpha), int(t.destBlendAlpha), int(t.blendOpAlpha), int(t.renderTargetWriteMask)};
}

Json rasterizerJson(const TraceDraw& d) {
    const RasterizerState& r = d.rasterizer;
    return {int(r.fillMode), int(r.cullMode), r.frontCounterClockwise, r.depthClipEnable, r.scissorEnable,
            r.scissorLeft,   r.scissorTop,    r.scissorRight,          r.scissorBottom,   d.coverageTest};
}

Json drawJson(const TraceDraw& d) {
    Json vertices = Json::array(), gs = Json::array(), primitives = Json::array(), fields = Json::array();
    for (const TraceField& f : d.inputFields) fields.push_back({f.name, f.offset, f.components});
    for (const TraceVertex& v : d.vertices)
        vertices.push_back({v.instance, v.index, floats(v.output), floats(v.input)});
    for (const TraceGsVertex& v : d.gsVertices) gs.push_back({v.primitive, v.startsStrip, floats(v.values)});
    for (const TracePrimitive& p : d.primitives) {
        Json screen = Json::array();
        for (int k = 0; k < p.vertexCount && k < 4; ++k) screen.push_back(vec4(p.screen[k]));
        primitives.push_back({p.primitive, int(p.kind), int(p.fate), p.clipped, std::move(screen)});
    }
    return {
        {"draw", d.draw},
        {"shaders", {d.vertexShader, d.geometryShader, d.pixelShader}},
        {"topology", int(d.topology)},
        {"blend", blendJson(d.blend)},
        {"depth", {d.depthStencil.depthEnable, d.depthStencil.depthWriteMask, int(d.depthStencil.depthFunc)}},
        {"rasterizer", rasterizerJson(d)},
        {"layout", {d.vsPosition, d.gsPosition, d.vsFloats, d.gsFloats}},
        {"totals", {d.verticesTotal, d.gsVerticesTotal, d.primitivesTotal}},
        {"skipped", d.skipped},
        {"inputFields", std::move(fields)},
        {"vertices", std::move(vertices)},
        {"gsVertices", std::move(gs)},
        {"primitives", std::move(primitives)},
        {"primitiveVertices", {d.verticesPerPrimitive, d.primitivesPerInstance, d.primitiveVertices}}};
}

Json fragmentJson(const TraceFragment& f) {
    return {f.draw,
            f.primitive,
            f.x,
            f.y,
            number(f.depth),
            number(f.depthBefore),
            number(f.depthAfter),
            int(f.fate),
            f.shaded,
            vec4(f.shaderOutput),
            vec4(f.colorBefore),
            vec4(f.colorAfter)};
}

// ---- Reading, every value checked ----

struct Reader {
    const std::string& name;

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(ErrorCode::BadFile, name + ": pixel history: " + what);
    }
    const Json& at(const Json& j, const char* key) const {
        if (!j.is_object() || !j.contains(key)) fail(std::string("no \"") + key + "\"");
        return j[key];
    }
    const Json& item(const Json& j, size_t i, const char* what) const {
        if (!j.is_array() || i >= j.size()) fail(std::string(what) + ": too few values");
        return j[i];
    }
    const Json& array(const Json& j, const char* what) const {
        if (!j.is_array()) fail(std::string(what) + " is not an array");
        return j;
    }
    float real(const Json& j) const {
        if (j.is_number()) return float(j.get<double>());
        if (j == "nan") return std::numeric_limits<float>::quiet_NaN();
        if (j == "inf") return std::numeric_limits<float>::infinity();
        if (j == "-inf") return -std::numeric_limits<float>::infinity();
        fail("a number was expected, not " + j.dump());
    }
    uint64_t whole(const Json& j, uint64_t max) const {
        if (!j.is_number_unsigned() || j.get<uint64_t>() > max)
            fail("a whole number up to " + std::to_string(max) + " was expected, not " + j.dump());
        return j.get<uint64_t>();
    }
    int32_t integer(const Json& j) const {
        if (!j.is_number_integer()) fail("an integer was expected, not " + j.dump());
        const int64_t v = j.get<int64_t>();
        if (v < INT32_MIN || v > INT32_MAX) fail("an integer out of range: " + j.dump());
        return int32_t(v);
    }
    bool flag(const Json& j) const {
        if (!j.is_boolean()) fail("true or false was expected, not " + j.dump());
        return j.get<bool>();
    }
    std::string text(const Json& j) const {
        if (!j.is_string()) fail("a string was expected, not " + j.dump());
        return j.get<std::string>();
    }
    std::vector<float> reals(const Json& j) const {
        std::vector<float> out;
        for (const Json& v : array(j, "values")) out.push_back(real(v));
        return out;
    }
    glm::vec4 vec(const Json& j) const {
        if (!j.is_array() || j.size() != 4) fail("4 numbers were expected, not " + j.dump());
        return {real(j[0]), real(j[1]), real(j[2]), real(j[3])};
    }

    void blend(const Json& j, BlendState& out) const {
        RenderTargetBlendDesc& t = out.renderTarget[0];
        const uint64_t kBlendMax = uint64_t(Blend::InvSrc1Alpha), kOpMax = uint64_t(BlendOp::Max);
        t.blendEnable = flag(item(j, 0, "blend"));
        t.srcBlend = Blend(whole(item(j, 1, "blend"), kBlendMax));
        t.destBlend = Blend(whole(item(j, 2, "blend"), kBlendMax));
        t.blendOp = BlendOp(whole(item(j, 3, "blend"), kOpMax));
        t.srcBlendAlpha = Blend(whole(item(j, 4, "blend"), kBlendMax));
        t.destBlendAlpha = Blend(whole(item(j, 5, "blend"), kBlendMax));
        t.blendOpAlpha = BlendOp(whole(item(j, 6, "blend"), kOpMax));
        t.renderTargetWriteMask = uint8_t(whole(item(j, 7, "blend"), 0xF));
    }

    void rasterizer(const Json& j, TraceDraw& d) const {
        RasterizerState& r = d.rasterizer;
        r.fillMode = FillMode(whole(item(j, 0, "rasterizer"), uint64_t(FillMode::Wireframe)));
        r.cullMode = CullMode(whole(item(j, 1, "rasterizer"), uint64_t(CullMode::Back)));
        r.frontCounterClockwise = flag(item(j, 2, "rasterizer"));
        r.depthClipEnable = flag(item(j, 3, "rasterizer"));
        r.scissorEnable = flag(item(j, 4, "rasterizer"));
        r.scissorLeft = integer(item(j, 5, "rasterizer"));
        r.scissorTop = integer(item(j, 6, "rasterizer"));
        r.scissorRight = integer(item(j, 7, "rasterizer"));
        r.scissorBottom = integer(item(j, 8, "rasterizer"));
        d.coverageTest = flag(item(j, 9, "rasterizer"));
    }

    // The vertex shader's input signature: each field inside the recorded input (checked per vertex).
    void inputFields(const Json& j, TraceDraw& d) const {
        for (const Json& f : array(at(j, "inputFields"), "inputFields")) {
            const uint32_t offset = uint32_t(whole(item(f, 1, "inputField"), 1u << 16));
            const uint32_t components = uint32_t(whole(item(f, 2, "inputField"), 4));
            if (components == 0) fail("an input field of 0 components");
            d.inputFields.push_back({text(item(f, 0, "inputField")), offset, components});
        }
    }

    void geometry(const Json& j, TraceDraw& d) const {
        inputFields(j, d);
        for (const Json& v : array(at(j, "vertices"), "vertices")) {
            TraceVertex vertex{uint32_t(whole(item(v, 0, "vertex"), UINT32_MAX)),
                               uint32_t(whole(item(v, 1, "vertex"), UINT32_MAX)), reals(item(v, 3, "vertex")),
                               reals(item(v, 2, "vertex"))};
            for (const TraceField& f : d.inputFields)
                if (f.offset + f.components > vertex.input.size())
                    fail("input field " + f.name + " lies outside a vertex's recorded input");
            d.vertices.push_back(std::move(vertex));
        }
        for (const Json& v : array(at(j, "gsVertices"), "gsVertices"))
            d.gsVertices.push_back({uint32_t(whole(item(v, 0, "gsVertex"), UINT32_MAX)),
                                    flag(item(v, 1, "gsVertex")), reals(item(v, 2, "gsVertex"))});
        for (const Json& p : array(at(j, "primitives"), "primitives")) {
            TracePrimitive out{};
            out.primitive = uint32_t(whole(item(p, 0, "primitive"), UINT32_MAX));
            out.kind = PrimitiveKind(whole(item(p, 1, "primitive"), 3));
            out.fate = PrimitiveFate(whole(item(p, 2, "primitive"), uint64_t(PrimitiveFate::NoPixels)));
            out.clipped = flag(item(p, 3, "primitive"));
            const Json& screen = array(item(p, 4, "primitive"), "screen");
            if (screen.size() > 4) fail("a primitive with more than 4 vertices");
            out.vertexCount = uint8_t(screen.size());
            for (size_t k = 0; k < screen.size(); ++k) out.screen[k] = vec(screen[k]);
            d.primitives.push_back(out);
        }
        primitiveVertices(j, d);
    }

    // Optional (a trace written before it was recorded has none): the input primitives' vertex indices.
    void primitiveVertices(const Json& j, TraceDraw& d) const {
        if (!j.contains("primitiveVertices")) return;
        const Json& p = at(j, "primitiveVertices");
        d.verticesPerPrimitive = uint32_t(whole(item(p, 0, "primitiveVertices"), 3));
        d.primitivesPerInstance = uint32_t(whole(item(p, 1, "primitiveVertices"), UINT32_MAX));
        for (const Json& v : array(item(p, 2, "primitiveVertices"), "primitiveVertices"))
            d.primitiveVertices.push_back(uint32_t(whole(v, UINT32_MAX)));
        if (d.verticesPerPrimitive == 0 ? !d.primitiveVertices.empty()
                                        : d.primitiveVertices.size() % d.verticesPerPrimitive != 0)
            fail("primitiveVertices: not a whole number of primitives");
        if (!d.primitiveVertices.empty() && d.primitivesPerInstance == 0)
            fail("primitiveVertices: primitives without an instance size");
    }

    void draw(const Json& j, TraceDraw& d) const {
        d.draw = uint32_t(whole(at(j, "draw"), UINT32_MAX));
        const Json& shaders = at(j, "shaders");
        d.vertexShader = text(item(shaders, 0, "shaders"));
        d.geometryShader = text(item(shaders, 1, "shaders"));
        d.pixelShader = text(item(shaders, 2, "shaders"));
        d.topology = Topology(whole(at(j, "topology"), uint64_t(Topology::TriangleStrip)));
        blend(at(j, "blend"), d.blend);
        const Json& depth = at(j, "depth");
        d.depthStencil.depthEnable = flag(item(depth, 0, "depth"));
        d.depthStencil.depthWriteMask = flag(item(depth, 1, "depth"));
        d.depthStencil.depthFunc =
            ComparisonFunc(whole(item(depth, 2, "depth"), uint64_t(ComparisonFunc::Always)));
        rasterizer(at(j, "rasterizer"), d);
        const Json& layout = at(j, "layout");
        d.vsPosition = uint32_t(whole(item(layout, 0, "layout"), 1u << 16));
        d.gsPosition = uint32_t(whole(item(layout, 1, "layout"), 1u << 16));
        d.vsFloats = uint32_t(whole(item(layout, 2, "layout"), 1u << 16));
        d.gsFloats = uint32_t(whole(item(layout, 3, "layout"), 1u << 16));
        const Json& totals = at(j, "totals");
        d.verticesTotal = whole(item(totals, 0, "totals"), UINT64_MAX);
        d.gsVerticesTotal = whole(item(totals, 1, "totals"), UINT64_MAX);
        d.primitivesTotal = whole(item(totals, 2, "totals"), UINT64_MAX);
        d.skipped = flag(at(j, "skipped"));
        geometry(j, d);
    }

    TraceFragment fragment(const Json& j) const {
        TraceFragment f{};
        f.draw = uint32_t(whole(item(j, 0, "fragment"), UINT32_MAX));
        f.primitive = uint32_t(whole(item(j, 1, "fragment"), UINT32_MAX));
        f.x = integer(item(j, 2, "fragment"));
        f.y = integer(item(j, 3, "fragment"));
        f.depth = real(item(j, 4, "fragment"));
        f.depthBefore = real(item(j, 5, "fragment"));
        f.depthAfter = real(item(j, 6, "fragment"));
        f.fate = FragmentFate(whole(item(j, 7, "fragment"), uint64_t(FragmentFate::Written)));
        f.shaded = flag(item(j, 8, "fragment"));
        f.shaderOutput = vec(item(j, 9, "fragment"));
        f.colorBefore = vec(item(j, 10, "fragment"));
        f.colorAfter = vec(item(j, 11, "fragment"));
        return f;
    }
};

}  // namespace

std::string traceToJson(const Trace& trace) {
    Json draws = Json::array(), fragments = Json::array();
    for (const TraceDraw& d : trace.draws()) draws.push_back(drawJson(d));
    for (const TraceFragment& f : trace.fragments()) fragments.push_back(fragmentJson(f));
    const PixelRect& r = trace.options().pixels;
    const Json out = {{"pixels", {r.x0, r.y0, r.x1, r.y1}},
                      {"size", {trace.width(), trace.height()}},
                      {"truncated", trace.fragmentsTruncated()},
                      {"draws", std::move(draws)},
                      {"fragments", std::move(fragments)}};
    return out.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

Trace traceFromJson(std::string_view json, const std::string& name) {
    const Reader read{name};
    const Json j = Json::parse(json, nullptr, false);
    if (j.is_discarded()) read.fail("not JSON");
    const Json& pixels = read.at(j, "pixels");
    TraceOptions options;
    options.pixels = {
        read.integer(read.item(pixels, 0, "pixels")), read.integer(read.item(pixels, 1, "pixels")),
        read.integer(read.item(pixels, 2, "pixels")), read.integer(read.item(pixels, 3, "pixels"))};
    Trace trace(options);
    const Json& size = read.at(j, "size");
    const uint32_t width = uint32_t(read.whole(read.item(size, 0, "size"), 1u << 16));
    const uint32_t height = uint32_t(read.whole(read.item(size, 1, "size"), 1u << 16));
    for (const Json& d : read.array(read.at(j, "draws"), "draws"))
        read.draw(d, trace.beginDraw(width, height));
    std::vector<TraceFragment> fragments;
    for (const Json& f : read.array(read.at(j, "fragments"), "fragments"))
        fragments.push_back(read.fragment(f));
    trace.addFragments(fragments);
    return trace;
}

}  // namespace raster::grade
