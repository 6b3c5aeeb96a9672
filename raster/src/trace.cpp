#include "raster/trace.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace raster {

const char* toString(PrimitiveFate fate) {
    switch (fate) {
        case PrimitiveFate::Rasterized: return "rasterized";
        case PrimitiveFate::Rectangle: return "rectangle";
        case PrimitiveFate::NonFinite: return "non-finite";
        case PrimitiveFate::Outside: return "outside";
        case PrimitiveFate::Culled: return "culled";
        case PrimitiveFate::Degenerate: return "degenerate";
        case PrimitiveFate::NoPixels: return "no-pixels";
    }
    return "(invalid)";
}

const char* toString(FragmentFate fate) {
    switch (fate) {
        case FragmentFate::EarlyDepthFailed: return "depth-failed";
        case FragmentFate::LateDepthFailed: return "depth-failed-late";
        case FragmentFate::Discarded: return "discarded";
        case FragmentFate::BlendNoOp: return "blend-no-op";
        case FragmentFate::Written: return "written";
    }
    return "(invalid)";
}

void Trace::clear() {
    draws_.clear();
    fragments_.clear();
    fragments_truncated_ = false;
    std::fill(overdraw_.begin(), overdraw_.end(), 0u);
    std::fill(non_finite_.begin(), non_finite_.end(), 0u);
}

TraceDraw& Trace::beginDraw(uint32_t width, uint32_t height) {
    if (width != width_ || height != height_) {
        width_ = width, height_ = height;
        overdraw_.assign(size_t(width) * height, 0u);
        non_finite_.assign(size_t(width) * height, 0u);
    }
    draws_.emplace_back();
    return draws_.back();
}

void Trace::addFragments(const std::vector<TraceFragment>& fragments) {
    const size_t room = options_.maxFragments - std::min(options_.maxFragments, fragments_.size());
    if (fragments.size() > room) fragments_truncated_ = true;
    fragments_.insert(fragments_.end(), fragments.begin(), fragments.begin() + std::min(room, fragments.size()));
}

std::vector<TraceFragment> Trace::pixelHistory(int32_t x, int32_t y) const {
    std::vector<TraceFragment> out;
    for (const TraceFragment& f : fragments_)
        if (f.x == x && f.y == y) out.push_back(f);
    return out;
}

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

// JSON has no NaN or Inf: those become null.
std::string num(float v) { return std::isfinite(v) ? fmt("%.9g", v) : "null"; }
std::string jvec(const glm::vec4& v) {
    if (std::isnan(v.x) && std::isnan(v.y) && std::isnan(v.z) && std::isnan(v.w)) return "null";
    // Appended, not `"[" + …`: GCC 12 warns falsely (-Wrestrict) on a literal + std::string.
    std::string s = "[";
    for (int c = 0; c < 4; ++c) {
        if (c > 0) s += ',';
        s += num(v[c]);
    }
    s += ']';
    return s;
}

std::string blendEquation(const RenderTargetBlendDesc& d) {
    if (!d.blendEnable) return "blend off: result = src";
    auto eq = [](Blend s, BlendOp op, Blend t) {
        const std::string src = "src*" + std::string(name(s)), dst = "dst*" + std::string(name(t));
        switch (op) {
            case BlendOp::Add: return src + " + " + dst;
            case BlendOp::Subtract: return src + " - " + dst;
            case BlendOp::RevSubtract: return dst + " - " + src;
            case BlendOp::Min: return std::string("min(src, dst)");
            case BlendOp::Max: return std::string("max(src, dst)");
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
                    << (d->depthStencil.depthEnable ? std::string(name(d->depthStencil.depthFunc)) +
                                                          (d->depthStencil.depthWriteMask ? ", write" : ", no write")
                                                    : std::string("off"))
                    << "  " << blendEquation(d->blend.target(0));
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
    const std::vector<TraceFragment> history = trace.pixelHistory(x, y);
    std::ostringstream out;
    out << "{\"pixel\":[" << x << "," << y << "],\"truncated\":" << (trace.fragmentsTruncated() ? "true" : "false")
        << ",\"fragments\":[";
    for (size_t i = 0; i < history.size(); ++i) {
        const TraceFragment& f = history[i];
        const TraceDraw* d = findDraw(trace, f.draw);
        out << (i ? "," : "") << "{\"draw\":" << f.draw << ",\"primitive\":" << f.primitive
            << ",\"pixelShader\":\"" << (d ? d->pixelShader : "") << "\",\"depth\":" << num(f.depth)
            << ",\"depthBefore\":" << num(f.depthBefore) << ",\"depthAfter\":" << num(f.depthAfter)
            << ",\"depthTest\":"
            << (f.fate == FragmentFate::EarlyDepthFailed || f.fate == FragmentFate::LateDepthFailed
                    ? "\"fail\""
                    : (std::isnan(f.depthBefore) ? "null" : "\"pass\""))
            << ",\"fate\":\"" << toString(f.fate) << "\",\"shaded\":" << (f.shaded ? "true" : "false")
            << ",\"shaderOutput\":" << jvec(f.shaderOutput) << ",\"colorBefore\":" << jvec(f.colorBefore)
            << ",\"colorAfter\":" << jvec(f.colorAfter);
        if (d) out << ",\"blend\":\"" << blendEquation(d->blend.target(0)) << "\"";
        out << "}";
    }
    out << "]}\n";
    return out.str();
}

std::string formatDraw(const TraceDraw& d, size_t limit) {
    std::ostringstream out;
    out << "draw " << d.draw << ": VS " << d.vertexShader;
    if (!d.geometryShader.empty()) out << ", GS " << d.geometryShader;
    out << ", PS " << d.pixelShader << (d.skipped ? "  (skipped by the step limit)" : "") << "\n";
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
