// The rasterizer lab's adversarial triangles (raster/scenes.hpp's CoverageSceneData): each set is
// placed in pixels in one quarter of the image, then mapped by the camera and to clip space.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "raster/scenes.hpp"

namespace raster {

namespace {

struct XY {
    double x, y;
};

// Additive colours, one per triangle in turn: neighbours differ, so that a centre on a shared edge
// given to the wrong one of two triangles changes the pixel; any two add to a brighter one.
const glm::vec4 kPalette[] = {{0.32f, 0.10f, 0.04f, 1}, {0.04f, 0.28f, 0.10f, 1}, {0.06f, 0.12f, 0.34f, 1},
                              {0.28f, 0.24f, 0.04f, 1}, {0.22f, 0.05f, 0.28f, 1}, {0.04f, 0.24f, 0.26f, 1}};
constexpr uint32_t kMaxSoup = 50000;

// The triangles in pixels, before the camera.
struct Builder {
    std::vector<XY> points;
    std::vector<glm::vec4> colors;

    void add(XY a, XY b, XY c, const glm::vec4& color) {
        points.insert(points.end(), {a, b, c});
        colors.insert(colors.end(), {color, color, color});
    }
    void add(XY a, XY b, XY c) { add(a, b, c, kPalette[(points.size() / 3) % std::size(kPalette)]); }
};

// splitmix64: the soup's positions, a fixed function of the seed.
struct Random {
    uint64_t state;
    double next() {  // in [0, 1)
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return double((z ^ (z >> 31)) >> 11) * 0x1p-53;
    }
};

// Two triangles sharing the diagonal through the pixel centre c, together a square of side 24 000
// pixels: every pixel is covered once, by one of them.
void addHuge(Builder& b, XY c) {
    const double k = 12000;
    const XY a{c.x - k, c.y - k}, d{c.x + k, c.y + k};
    b.add(a, {c.x + k, c.y - k}, d, {0.05f, 0.05f, 0.08f, 1});
    b.add(a, d, {c.x - k, c.y + k}, {0.08f, 0.05f, 0.05f, 1});
}

// A fan about the pixel centre c, spokes ending on pixel centres, windings alternating.
void addFan(Builder& b, XY c, double radius, uint32_t n) {
    std::vector<XY> rim(n);
    for (uint32_t i = 0; i < n; ++i) {
        const double angle = 2 * std::numbers::pi * i / n;
        rim[i] = {c.x + std::round(radius * std::cos(angle)), c.y + std::round(radius * std::sin(angle))};
    }
    for (uint32_t i = 0; i < n; ++i) {
        const XY p = rim[i], q = rim[(i + 1) % n];
        if (i % 2 == 0)
            b.add(c, p, q);
        else
            b.add(c, q, p);
    }
}

// Cells of `cell` pixels from the pixel centre `origin`, each cut by a diagonal (alternating), one
// triangle of each cell clockwise and the other counter-clockwise.
void addLattice(Builder& b, XY origin, uint32_t cell, uint32_t columns, uint32_t rows) {
    auto at = [&](uint32_t i, uint32_t j) {
        return XY{origin.x + double(i * cell), origin.y + double(j * cell)};
    };
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < columns; ++i) {
            const XY p = at(i, j), q = at(i + 1, j), r = at(i + 1, j + 1), s = at(i, j + 1);
            if ((i + j) % 2 == 0)
                b.add(p, q, r), b.add(p, s, r);
            else
                b.add(p, q, s), b.add(q, s, r);
        }
}

// Wedges under a pixel wide from one apex, sharing their long edges, and strips half a pixel high
// (wide) whose top (left) edges run along rows (columns) of pixel centres.
void addSlivers(Builder& b, XY panel, double width, double height) {
    const XY apex{panel.x + 8.5, panel.y + std::floor(height / 2) + 0.5};
    const double far = panel.x + std::floor(width) - 8.5;
    for (int k = 0; k < 40; ++k) {
        const XY p{far, apex.y + (k - 20) * 0.75}, q{far, apex.y + (k - 19) * 0.75};
        if (k % 2 == 0)
            b.add(apex, p, q);
        else
            b.add(apex, q, p);
    }
    for (int r = 0; r < 8; ++r) {
        const double y = panel.y + 10.5 + 3 * r, x0 = panel.x + 8.5,
                     x1 = panel.x + std::floor(width / 2) + 0.5;
        b.add({x0, y}, {x1, y}, {x1, y + 0.5});
        b.add({x0, y}, {x0, y + 0.5}, {x1, y + 0.5});
    }
    for (int c = 0; c < 8; ++c) {
        const double x = panel.x + 10.5 + 3 * c, y0 = panel.y + std::floor(height) - 60.5,
                     y1 = panel.y + std::floor(height) - 8.5;
        b.add({x, y0}, {x + 0.5, y0}, {x + 0.5, y1});
        b.add({x, y0}, {x, y1}, {x + 0.5, y1});
    }
}

// `count` small triangles anywhere in the panel, at positions off the 1/256 grid.
void addSoup(Builder& b, XY panel, double width, double height, uint32_t count) {
    Random random{0x5EEDull + count};
    for (uint32_t i = 0; i < count; ++i) {
        const XY c{panel.x + 4 + random.next() * (width - 8), panel.y + 4 + random.next() * (height - 8)};
        const double size = 0.3 + 5.7 * random.next() * random.next();
        XY v[3];
        for (XY& p : v) p = {c.x + size * (2 * random.next() - 1), c.y + size * (2 * random.next() - 1)};
        b.add(v[0], v[1], v[2], kPalette[i % std::size(kPalette)] * glm::vec4(0.6f, 0.6f, 0.6f, 1));
    }
}

}  // namespace

CoverageSceneData::CoverageSceneData(const SceneOptions& o) {
    const uint32_t count = o.count.value_or(kDefaultParticleCount);
    RASTER_REQUIRE(count <= kMaxSoup, InvalidArgument,
                   "rasterizer: count " + std::to_string(count) + " is above " + std::to_string(kMaxSoup) +
                       " (the small triangles of the last quarter)");
    const double w = std::floor(o.width / 2.0), h = std::floor(o.height / 2.0);
    Builder b;
    addHuge(b, {std::floor(o.width / 2.0) + 0.5, std::floor(o.height / 2.0) + 0.5});
    addFan(b, {std::floor(w / 2) + 0.5, std::floor(h / 2) + 0.5}, std::floor(std::min(w, h) * 0.42),
           8 + 4 * (count % 5));
    const uint32_t cell = 5 + count % 4;
    const auto cells = [&](double extent) {
        return std::min<uint32_t>(48, uint32_t(std::max(0.0, extent - 16) / cell));
    };
    addLattice(b, {w + 8.5, 8.5}, cell, cells(w), cells(h));
    addSlivers(b, {0, h}, w, h);
    addSoup(b, {w, h}, w, h, count);

    // The camera: a rotation about the image's centre by the eye's azimuth and a zoom.
    const SceneCamera camera = o.camera.value_or(SceneCamera{{0, 0, 1}, {0, 0, 0}});
    const glm::dvec3 d = glm::dvec3(camera.eye) - glm::dvec3(camera.target);
    const double angle = std::atan2(d.x, d.z), zoom = 1.0 / std::max(1e-3, glm::length(d));
    const double cs = std::cos(angle) * zoom, sn = std::sin(angle) * zoom;
    const XY centre{o.width / 2.0, o.height / 2.0};
    std::vector<Vertex> vertices(b.points.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        const XY p = b.points[i];
        const double x = centre.x + (p.x - centre.x) * cs - (p.y - centre.y) * sn;
        const double y = centre.y + (p.x - centre.x) * sn + (p.y - centre.y) * cs;
        vertices[i] = {glm::vec4(float(x / o.width * 2 - 1), float(1 - y / o.height * 2), 0.5f, 1.0f),
                       b.colors[i]};
    }
    triangles = VertexBuffer::create(vertices);
    vertexCount = uint32_t(vertices.size());
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32A32_FLOAT, 0, 0},
                                     {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, 16}};
    layout = InputLayout(desc);
}

void CoverageSceneData::bind(Context& context) const {
    context.setInputLayout(&layout);
    context.setVertexBuffer(0, &triangles);
    context.setPrimitiveTopology(Topology::TriangleList);
    context.setBlendState(BlendState::additive());
    context.setDepthStencilState(DepthStencilState::disabled());
}

}  // namespace raster
