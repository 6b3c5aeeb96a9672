// The trace as text for students and JSON for tools (trace_format.hpp).
#include "raster/trace_format.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

namespace raster {

namespace {

std::string fmt(const char* format, auto... args) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, format, args...);
    return buffer;
}

std::string vec(const glm::vec4& v) {
    if (std::isnan(v.x) && std::isnan(v.y) && std::isnan(v.z) && std::isnan(v.w)) return "-";
    return fmt("(%.4f %.4f %.4f %.4f)", v.x, v.y, v.z, v.w);
}

// JSON's numbers: the shortest decimal that reads back as the same float (the fields are floats), and
// null for NaN and ±Inf, which JSON cannot say. Objects keep their fields in the order written.
using Json = nlohmann::basic_json<nlohmann::ordered_map, std::vector, std::string, bool, std::int64_t,
                                  std::uint64_t, float>;

Json jsonNumber(float v) {
    return std::isfinite(v) ? Json(v) : Json(nullptr);
}
Json jsonVec(const glm::vec4& v) {
    if (std::isnan(v.x) && std::isnan(v.y) && std::isnan(v.z) && std::isnan(v.w)) return nullptr;
    Json out = Json::array();
    for (int c = 0; c < 4; ++c) out.push_back(jsonNumber(v[c]));
    return out;
}
// "fail", "pass", or null where no depth test ran (no depth buffer).
Json jsonDepthTest(const TraceFragment& f) {
    if (f.fate == FragmentFate::EarlyDepthFailed || f.fate == FragmentFate::LateDepthFailed) return "fail";
    return std::isnan(f.depthBefore) ? Json() : Json("pass");
}

std::string blendEquation(const RenderTargetBlendDesc& d) {
    if (!d.blendEnable) return "blend off: result = src";
    auto eq = [](Blend s, BlendOp op, Blend t) {
        const std::string src = "src*" + std::string(name(s)), dst = "dst*" + std::string(name(t));
        switch (op) {
            case BlendOp::Add:
                return src + " + " + dst;
            case BlendOp::Subtract:
                return src + " - " + dst;
            case BlendOp::RevSubtract:
                return dst + " - " + src;
            case BlendOp::Min:
                return std::string("min(src, dst)");
            case BlendOp::Max:
                return std::string("max(src, dst)");
        }
        return std::string("?");
    };
    return "rgb = " + eq(d.srcBlend, d.blendOp, d.destBlend) + ", a = " + eq(d.srcBlendAlpha, d.blendOpAlpha, d.destBlendAlpha);
}

const TraceDraw* findDraw(const Trace& trace, uint32_t draw) {
    for (const TraceDraw& d : trace.draws())
        if (d.draw == draw) return &d;
    return nullptr;
}

}  // namespace

std::string rasterizerSummary(const TraceDraw& d) {
    const RasterizerState& r = d.rasterizer;
    std::string text = "rasterizer: cull " + std::string(name(r.cullMode)) + ", fill " +
                       std::string(name(r.fillMode)) + ", front " +
                       (r.frontCounterClockwise ? "counter-clockwise" : "clockwise") + ", scissor ";
    text += r.scissorEnable
                ? fmt("[%d, %d) x [%d, %d)", r.scissorLeft, r.scissorRight, r.scissorTop, r.scissorBottom)
                : std::string("off");
    text += std::string(", depth clip ") + (r.depthClipEnable ? "on" : "off");
    if (d.coverageTest) text += ", coverage: the lab's test";
    return text;
}

std::string formatPixelHistory(const Trace& trace, int32_t x, int32_t y) {
    const std::vector<TraceFragment> history = trace.pixelHistory(x, y);
    std::ostringstream out;
    out << "pixel (" << x << ", " << y << "): " << history.size() << " fragment" << (history.size() == 1 ? "" : "s");
    if (trace.fragmentsTruncated()) out << " (trace truncated: raise TraceOptions::maxFragments)";
    out << "\n";
    uint32_t last_draw = UINT32_MAX;
    int n = 0;
    for (const TraceFragment& f : history) {
        if (f.draw != last_draw) {
            last_draw = f.draw;
            const TraceDraw* d = findDraw(trace, f.draw);
            out << "draw " << f.draw;
            if (d) {
                out << "  " << d->pixelShader << "  depth "
                    << (d->depthStencil.depthEnable
                            ? std::string(name(d->depthStencil.depthFunc)) +
                                  (d->depthStencil.depthWriteMask ? ", write" : ", no write")
                            : std::string("off"))
                    << "  " << blendEquation(d->blend.target(0)) << "\n  " << rasterizerSummary(*d);
            }
            out << "\n";
            out << "   #  prim      depth     buffer  test         shader output (rgba)                 "
                   "before -> after\n";
        }
        const bool tested = !std::isnan(f.depthBefore);
        const char* test = f.fate == FragmentFate::EarlyDepthFailed || f.fate == FragmentFate::LateDepthFailed
                               ? "fail"
                               : (tested ? "pass" : "-");
        out << fmt("%4d %5u %10.6f %10.6f  %-5s ", n++, f.primitive, f.depth, f.depthBefore, test)
            << fmt("%-13s", toString(f.fate)) << vec(f.shaderOutput) << "  " << vec(f.colorBefore) << " -> "
            << vec(f.colorAfter) << "\n";
    }
    return out.str();
}

std::string pixelHistoryJson(const Trace& trace, int32_t x, int32_t y) {
    Json fragments = Json::array();
    for (const TraceFragment& f : trace.pixelHistory(x, y)) {
        const TraceDraw* d = findDraw(trace, f.draw);
        Json fragment = {{"draw", f.draw},
                         {"primitive", f.primitive},
                         {"pixelShader", d ? d->pixelShader : std::string()},
                         {"depth", jsonNumber(f.depth)},
                         {"depthBefore", jsonNumber(f.depthBefore)},
                         {"depthAfter", jsonNumber(f.depthAfter)},
                         {"depthTest", jsonDepthTest(f)},
                         {"fate", toString(f.fate)},
                         {"shaded", f.shaded},
                         {"shaderOutput", jsonVec(f.shaderOutput)},
                         {"colorBefore", jsonVec(f.colorBefore)},
                         {"colorAfter", jsonVec(f.colorAfter)}};
        if (d) fragment["blend"] = blendEquation(d->blend.target(0));
        if (d) fragment["rasterizer"] = rasterizerSummary(*d);
        fragments.push_back(std::move(fragment));
    }
    const Json history = {
        {"pixel", {x, y}}, {"truncated", trace.fragmentsTruncated()}, {"fragments", std::move(fragments)}};
    // Names that are not UTF-8 (a shader's type name is whatever the compiler made of it) are
    // written with U+FFFD in place of the bad bytes rather than failing the whole history.
    return history.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string formatDraw(const TraceDraw& d, size_t limit) {
    std::ostringstream out;
    out << "draw " << d.draw << ": VS " << d.vertexShader;
    if (!d.geometryShader.empty()) out << ", GS " << d.geometryShader;
    out << ", PS " << d.pixelShader << (d.skipped ? "  (skipped by the step limit)" : "") << "\n";
    out << rasterizerSummary(d) << "\n";
    auto floats = [](const std::vector<float>& v, uint32_t from, uint32_t count) {
        std::string s = "(";
        for (uint32_t i = 0; i < count && from + i < v.size(); ++i) {
            if (i) s += " ";
            s += fmt("%.4g", v[from + i]);
        }
        return s + ")";
    };
    out << "input assembler → vertex shader: " << d.verticesTotal << " invocations\n";
    for (size_t i = 0; i < d.vertices.size() && i < limit; ++i) {
        const TraceVertex& v = d.vertices[i];
        out << fmt("  vertex %u instance %u  in:", v.index, v.instance);
        for (const TraceField& f : d.inputFields) out << " " << f.name << "=" << floats(v.input, f.offset, f.components);
        out << "  out: SV_Position=" << floats(v.output, d.vsPosition, 4);
        if (d.vsFloats > 4) out << " attributes=" << floats(v.output, d.vsPosition == 0 ? 4 : 0, d.vsFloats - 4);
        out << "\n";
    }
    if (!d.geometryShader.empty()) {
        out << "geometry shader output: " << d.gsVerticesTotal << " vertices\n";
        for (size_t i = 0; i < d.gsVertices.size() && i < limit; ++i) {
            const TraceGsVertex& v = d.gsVertices[i];
            out << fmt("  prim %u %s SV_Position=", v.primitive, v.startsStrip ? "strip>" : "      ")
                << floats(v.values, d.gsPosition, 4);
            if (d.gsFloats > 4) out << " attributes=" << floats(v.values, d.gsPosition == 0 ? 4 : 0, d.gsFloats - 4);
            out << "\n";
        }
    }
    out << "clip → setup: " << d.primitivesTotal << " primitives\n";
    for (size_t i = 0; i < d.primitives.size() && i < limit; ++i) {
        const TracePrimitive& p = d.primitives[i];
        out << fmt("  prim %u %-10s%s", p.primitive, toString(p.fate), p.clipped ? " clipped" : "");
        for (int k = 0; k < p.vertexCount; ++k)
            out << fmt("  (%.2f, %.2f, z %.5f)", p.screen[k].x, p.screen[k].y, p.screen[k].z);
        out << "\n";
    }
    out << d.stats.toString();
    return out.str();
}

}  // namespace raster
