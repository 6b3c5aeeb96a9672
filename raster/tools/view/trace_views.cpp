#include "trace_views.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace raster::tools {
namespace {

struct Stop {
    double t;
    Rgb colour;
};
// Dark purple, red, yellow, white.
constexpr Stop kRamp[] = {
    {0.0, {40, 0, 90}}, {1.0 / 3.0, {210, 30, 40}}, {2.0 / 3.0, {255, 210, 0}}, {1.0, {255, 255, 255}}};

std::string fmt(const char* format, auto... args) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, format, args...);
    return buffer;
}

// Clips the segment a→b to the box [lo, hi]² (Liang–Barsky); false when nothing is left.
bool clipSegment(glm::dvec2& a, glm::dvec2& b, glm::dvec2 lo, glm::dvec2 hi) {
    double t0 = 0.0, t1 = 1.0;
    const glm::dvec2 d = b - a;
    const double p[4] = {-d.x, d.x, -d.y, d.y};
    const double q[4] = {a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0.0) {
            if (q[i] < 0.0) return false;
            continue;
        }
        const double t = q[i] / p[i];
        if (p[i] < 0.0)
            t0 = std::max(t0, t);
        else
            t1 = std::min(t1, t);
        if (t0 > t1) return false;
    }
    const glm::dvec2 start = a;
    a = start + d * t0;
    b = start + d * t1;
    return true;
}

}  // namespace

Rgb heatColour(uint32_t count, uint32_t max) {
    if (count == 0 || max == 0) return {0, 0, 0};
    if (count >= max) return kRamp[3].colour;
    const double t = double(count) / double(max);
    size_t i = 0;
    while (t > kRamp[i + 1].t) ++i;
    const double s = (t - kRamp[i].t) / (kRamp[i + 1].t - kRamp[i].t);
    Rgb out;
    for (int c = 0; c < 3; ++c) {
        const double a = kRamp[i].colour[c], b = kRamp[i + 1].colour[c];
        // Floored, so only count == max reaches the top stop's white.
        out[c] = uint8_t(std::floor(a + (b - a) * s));
    }
    return out;
}

std::vector<uint8_t> overdrawImage(const std::vector<uint32_t>& counts, uint32_t width, uint32_t height,
                                   uint32_t* max) {
    const size_t n = size_t(width) * height;
    uint32_t top = 0;
    for (size_t i = 0; i < std::min(n, counts.size()); ++i) top = std::max(top, counts[i]);
    std::vector<uint8_t> rgba(4 * n, 0);
    for (size_t i = 0; i < n; ++i) {
        const Rgb c = heatColour(i < counts.size() ? counts[i] : 0, top);
        rgba[4 * i] = c[0], rgba[4 * i + 1] = c[1], rgba[4 * i + 2] = c[2], rgba[4 * i + 3] = 255;
    }
    if (max) *max = top;
    return rgba;
}

void dim(std::vector<uint8_t>& rgba) {
    for (size_t i = 0; i + 3 < rgba.size(); i += 4) {
        for (int c = 0; c < 3; ++c) rgba[i + c] = uint8_t(rgba[i + c] / 3);
        rgba[i + 3] = 255;
    }
}

std::vector<uint8_t> nonFiniteImage(const std::vector<uint8_t>& rgba, const std::vector<uint32_t>& nonFinite,
                                    size_t* highlighted) {
    std::vector<uint8_t> out = rgba;
    dim(out);
    size_t count = 0;
    for (size_t i = 0; i < nonFinite.size() && 4 * i + 3 < out.size(); ++i) {
        if (nonFinite[i] == 0) continue;
        ++count;
        out[4 * i] = kNonFiniteColour[0], out[4 * i + 1] = kNonFiniteColour[1];
        out[4 * i + 2] = kNonFiniteColour[2];
    }
    if (highlighted) *highlighted = count;
    return out;
}

void Canvas::set(int32_t x, int32_t y, const Rgb& c) {
    if (x < 0 || y < 0 || uint32_t(x) >= width || uint32_t(y) >= height) return;
    uint8_t* p = &rgba[4 * (size_t(y) * width + size_t(x))];
    p[0] = c[0], p[1] = c[1], p[2] = c[2], p[3] = 255;
}

void Canvas::line(glm::vec2 a, glm::vec2 b, const Rgb& c) {
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y)) return;
    glm::dvec2 p = a, q = b;
    if (!clipSegment(p, q, {-2.0, -2.0}, {double(width) + 2.0, double(height) + 2.0})) return;
    const double steps = std::max(1.0, std::ceil(std::max(std::abs(q.x - p.x), std::abs(q.y - p.y))));
    for (double i = 0; i <= steps; ++i) {
        const glm::dvec2 s = p + (q - p) * (i / steps);
        set(int32_t(std::floor(s.x)), int32_t(std::floor(s.y)), c);
    }
}

void Canvas::dot(glm::vec2 p, int r, const Rgb& c) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || std::abs(p.x) > 1e7f || std::abs(p.y) > 1e7f) return;
    const int32_t x = int32_t(std::floor(p.x)), y = int32_t(std::floor(p.y));
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) set(x + dx, y + dy, c);
}

bool clipToScreen(const glm::vec4& clip, const Viewport& viewport, glm::vec2& screen) {
    if (!(clip.w > 0.0f) || !std::isfinite(clip.x) || !std::isfinite(clip.y) || !std::isfinite(clip.w))
        return false;
    const double inv_w = 1.0 / double(clip.w);
    screen.x =
        float(viewport.topLeftX + viewport.width * 0.5 + double(clip.x) * inv_w * viewport.width * 0.5);
    screen.y =
        float(viewport.topLeftY + viewport.height * 0.5 - double(clip.y) * inv_w * viewport.height * 0.5);
    return std::isfinite(screen.x) && std::isfinite(screen.y);
}

void drawPrimitive(Canvas& canvas, const TracePrimitive& p, const Rgb& colour) {
    const auto at = [&](int i) { return glm::vec2(p.screen[i]); };
    switch (p.vertexCount) {
        case 1:
            canvas.dot(at(0), 1, colour);
            break;
        case 2:
            canvas.line(at(0), at(1), colour);
            break;
        case 3:
            canvas.line(at(0), at(1), colour), canvas.line(at(1), at(2), colour),
                canvas.line(at(2), at(0), colour);
            break;
        case 4:  // a rectangle's corners in strip order: 0 1 / 2 3
            canvas.line(at(0), at(1), colour), canvas.line(at(1), at(3), colour);
            canvas.line(at(3), at(2), colour), canvas.line(at(2), at(0), colour);
            break;
        default:
            break;
    }
}

size_t drawInputPrimitive(Canvas& canvas, const TraceDraw& draw, uint32_t primitive, const Rgb& colour) {
    size_t n = 0;
    for (const TracePrimitive& p : draw.primitives)
        if (p.primitive == primitive && p.vertexCount > 0) drawPrimitive(canvas, p, colour), ++n;
    return n;
}

size_t drawVertices(Canvas& canvas, const TraceDraw& draw, const Viewport& viewport) {
    size_t n = 0;
    if (!draw.geometryShader.empty()) {
        // The VS output feeds the GS, whose space it is in: mark where each input primitive went.
        glm::dvec2 sum{0.0};
        int count = 0;
        const auto mark = [&] {
            if (count > 0) canvas.dot(glm::vec2(sum / double(count)), 1, kVertexColour), ++n;
            sum = glm::dvec2(0.0), count = 0;
        };
        for (size_t i = 0; i < draw.gsVertices.size(); ++i) {
            const TraceGsVertex& v = draw.gsVertices[i];
            if (i > 0 && v.primitive != draw.gsVertices[i - 1].primitive) mark();
            glm::vec2 s;
            if (v.values.size() >= draw.gsPosition + 4 &&
                clipToScreen({v.values[draw.gsPosition], v.values[draw.gsPosition + 1],
                              v.values[draw.gsPosition + 2], v.values[draw.gsPosition + 3]},
                             viewport, s))
                sum += glm::dvec2(s), ++count;
        }
        mark();
        return n;
    }
    for (const TraceVertex& v : draw.vertices) {
        if (v.output.size() < draw.vsPosition + 4) continue;
        const float* p = &v.output[draw.vsPosition];
        glm::vec2 s;
        if (!clipToScreen({p[0], p[1], p[2], p[3]}, viewport, s)) continue;
        canvas.dot(s, 1, kVertexColour);
        ++n;
    }
    return n;
}

size_t drawGsOutput(Canvas& canvas, const TraceDraw& draw, const Viewport& viewport) {
    const PrimitiveKind kind = draw.primitives.empty() ? PrimitiveKind::Triangle : draw.primitives[0].kind;
    size_t strips = 0;
    std::vector<glm::vec2> screen;
    std::vector<bool> placed;
    const auto flush = [&] {
        for (size_t i = 0; i < screen.size(); ++i) {
            if (!placed[i]) continue;
            if (kind == PrimitiveKind::Point) canvas.dot(screen[i], 1, kGsColour);
            const int reach = kind == PrimitiveKind::Triangle ? 2 : kind == PrimitiveKind::Line ? 1 : 0;
            for (int k = 1; k <= reach; ++k)
                if (i + k < screen.size() && placed[i + k]) canvas.line(screen[i], screen[i + k], kGsColour);
        }
        strips += screen.empty() ? 0 : 1;
        screen.clear(), placed.clear();
    };
    uint32_t primitive = UINT32_MAX;
    for (const TraceGsVertex& v : draw.gsVertices) {
        if (v.startsStrip || v.primitive != primitive) flush();
        primitive = v.primitive;
        glm::vec2 s{0.0f};
        const bool ok = v.values.size() >= draw.gsPosition + 4 &&
                        clipToScreen({v.values[draw.gsPosition], v.values[draw.gsPosition + 1],
                                      v.values[draw.gsPosition + 2], v.values[draw.gsPosition + 3]},
                                     viewport, s);
        screen.push_back(s), placed.push_back(ok);
    }
    flush();
    return strips;
}

Rgb fateColour(const TracePrimitive& p) {
    switch (p.fate) {
        case PrimitiveFate::Rasterized:
        case PrimitiveFate::Rectangle:
            return p.clipped ? kClippedColour : kRasterizedColour;
        case PrimitiveFate::Culled:
            return kCulledColour;
        default:
            return kNoPixelsColour;
    }
}

size_t drawPrimitives(Canvas& canvas, const TraceDraw& draw) {
    size_t n = 0;
    for (const TracePrimitive& p : draw.primitives)
        if (p.vertexCount > 0) drawPrimitive(canvas, p, fateColour(p)), ++n;
    return n;
}

const TraceDraw* findTraceDraw(const Trace& trace, uint32_t draw) {
    for (const TraceDraw& d : trace.draws())
        if (d.draw == draw) return &d;
    return nullptr;
}

std::vector<std::string> compactPixelHistory(const Trace& trace, int32_t x, int32_t y, size_t maxRows) {
    const std::vector<TraceFragment> history = trace.pixelHistory(x, y);
    std::vector<std::string> lines;
    lines.push_back(fmt("pixel (%d, %d): %zu fragment%s%s   (C closes)", x, y, history.size(),
                        history.size() == 1 ? "" : "s", trace.fragmentsTruncated() ? ", truncated" : ""));
    if (history.empty()) return lines;
    lines.push_back("#\tdraw\tprim\tdepth\tbuffer\ttest\tfate\tcolour after");
    for (size_t i = 0; i < history.size() && i < maxRows; ++i) {
        const TraceFragment& f = history[i];
        const bool failed =
            f.fate == FragmentFate::EarlyDepthFailed || f.fate == FragmentFate::LateDepthFailed;
        const char* test = failed ? "fail" : std::isnan(f.depthBefore) ? "-" : "pass";
        const glm::vec4 c = f.colorAfter;
        lines.push_back(fmt("%zu\t%u\t%u\t%.5f\t%.5f\t%s\t%s\t%.3f %.3f %.3f %.3f", i, f.draw, f.primitive,
                            double(f.depth), double(f.depthBefore), test, toString(f.fate), double(c.r),
                            double(c.g), double(c.b), double(c.a)));
    }
    if (history.size() > maxRows)
        lines.push_back(fmt("... %zu more (the whole history is printed)", history.size() - maxRows));
    return lines;
}

MarchPlot marchPlot(const PixelMarch& march) {
    MarchPlot plot;
    plot.sMin = march.t0, plot.sMax = std::max(march.t1, march.t0);
    float L = 0.0f;
    plot.radiance.push_back({march.t0, 0.0f});
    plot.transmittance.push_back({march.t0, 1.0f});
    for (const media::MarchSample& s : march.samples) {
        L += (s.added.r + s.added.g + s.added.b) / 3.0f;
        const float end = s.s + 0.5f * march.ds;  // past the sample's step
        plot.radiance.push_back({end, L});
        plot.transmittance.push_back({end, s.transmittance * std::exp(-s.opticalStep)});
        plot.lMax = std::max(plot.lMax, L);
    }
    plot.radiance.push_back({plot.sMax, L});
    plot.transmittance.push_back({plot.sMax, march.transmittance});
    char text[160];
    std::snprintf(text, sizeof text, "L (mean rgb, green) and T (white) along the ray: %zu samples, L = %.4g, T = %.4g",
                  march.samples.size(), double(L), double(march.transmittance));
    plot.caption = text;
    return plot;
}

}  // namespace raster::tools
