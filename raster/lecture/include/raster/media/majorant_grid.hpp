// A coarse grid over a medium's box and the walk of a ray through its cells (a 3D DDA, Amanatides and
// Woo 1987), with each cell's majorant: an upper bound of the extinction inside it. A march skips the
// cells whose majorant is 0 (no sample there can add anything, so skipping changes no bit) and ratio
// tracking (ratio_tracking.hpp) draws its free paths from the majorant instead of one bound for the
// whole box.
//
// Cells: the box [lo, hi] split into dims.x × dims.y × dims.z equal cells; along each axis a coordinate
// x lies in cell clamp(floor((x − lo)/size), 0, dims − 1): cells are half-open [lo_i, lo_{i+1}), the
// last one closed. A ray "crosses" a cell when its part inside the cell has positive length; the walk
// visits exactly those cells, in order along the ray (tests/ray_march_test.cpp checks this against a
// brute-force test of every cell, random rays and rays along faces and through corners), each with
// the interval [t_enter, t_exit] the ray spends in it. Where the ray leaves through an edge or a corner
// (two or three boundaries at the same t), it steps over the cells it only touches.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "raster/check.hpp"
#include "raster/media/metaballs.hpp"

namespace raster::media {

class GridFrame {
public:
    Box box;
    glm::ivec3 dims{1};

    GridFrame() = default;
    GridFrame(const Box& b, const glm::ivec3& n) : box(b), dims(n), size_((b.hi - b.lo) / glm::vec3(n)) {}

    glm::vec3 cellSize() const { return size_; }
    // The cell index along axis a of coordinate x (header: half-open, the last closed).
    int cellOf(int a, float x) const {
        const float f = std::floor((x - box.lo[a]) / size_[a]);
        const float bounded = f < -1e9f ? -1e9f : f < 1e9f ? f : 1e9f;  // NaN → 1e9: no UB in the cast
        return std::clamp(int(bounded), 0, dims[a] - 1);
    }
    // The cell holding p (a point outside the box: the nearest cell).
    glm::ivec3 cellAt(const glm::vec3& p) const { return {cellOf(0, p.x), cellOf(1, p.y), cellOf(2, p.z)}; }
    // The coordinate of boundary i along axis a (0: lo, dims: hi).
    float boundary(int a, int i) const { return i == dims[a] ? box.hi[a] : box.lo[a] + float(i) * size_[a]; }
    size_t index(const glm::ivec3& c) const { return (size_t(c.z) * dims.y + c.y) * dims.x + c.x; }
    size_t cellCount() const { return size_t(dims.x) * dims.y * dims.z; }
    Box cellBox(const glm::ivec3& c) const {
        return {{boundary(0, c.x), boundary(1, c.y), boundary(2, c.z)},
                {boundary(0, c.x + 1), boundary(1, c.y + 1), boundary(2, c.z + 1)}};
    }

private:
    glm::vec3 size_{0.0f};  // (hi − lo)/dims, metres
};

// Calls visit(cell, t_enter, t_exit) for each cell the ray o + t·d crosses within [t0, t1], in order;
// visit returns false to stop the walk. d need not be unit length; a zero d visits nothing.
template <class Visit>
void walkGrid(const GridFrame& grid, const glm::vec3& o, const glm::vec3& d, float t0, float t1, Visit&& visit) {
    if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) return;
    auto [t_in, t_out] = slabInterval(grid.box, o, d);
    float t = std::max(t_in, t0);
    const float t_end = std::min(t_out, t1);
    if (!(t < t_end)) return;
    // The first cell: the one holding the entry point, except that a ray entering on a cell's lower
    // boundary while moving down is already in the cell below (cells are half-open).
    const glm::vec3 p = o + d * t;
    glm::ivec3 cell, step;
    glm::vec3 t_next;
    for (int a = 0; a < 3; ++a) {
        cell[a] = grid.cellOf(a, p[a]);
        // Moving down from exactly a cell's lower boundary: the ray is in the cell below at once.
        if (d[a] < 0.0f && cell[a] > 0 && p[a] <= grid.boundary(a, cell[a])) --cell[a];
        step[a] = d[a] > 0.0f ? 1 : d[a] < 0.0f ? -1 : 0;
    }
    auto nextCrossing = [&](int a) {
        if (step[a] == 0) return INFINITY;
        const int b = step[a] > 0 ? cell[a] + 1 : cell[a];
        return (grid.boundary(a, b) - o[a]) / d[a];
    };
    for (int a = 0; a < 3; ++a) t_next[a] = nextCrossing(a);
    for (;;) {
        const float t_cross = std::min(std::min(t_next.x, t_next.y), t_next.z);
        const float t_leave = std::min(t_cross, t_end);
        if (t_leave > t && !visit(cell, t, t_leave)) return;
        if (t_cross >= t_end) return;
        t = std::max(t, t_cross);
        for (int a = 0; a < 3; ++a) {
            if (t_next[a] != t_cross) continue;
            cell[a] += step[a];
            if (cell[a] < 0 || cell[a] >= grid.dims[a]) return;
            t_next[a] = nextCrossing(a);
        }
    }
}

// A majorant per cell of a grid over the medium's box.
struct MajorantGrid {
    GridFrame frame;
    std::vector<float> bound;  // per cell, in index order: extinction 1/m, ≥ every sample inside

    float at(const glm::ivec3& c) const { return bound[frame.index(c)]; }
};

// The majorant grid of a field given by bound(Box) → an upper bound of the extinction in the box.
// dims: 1 to 1024 cells per axis (an out-of-range size throws InvalidArgument naming it).
template <class CellBound>
MajorantGrid makeMajorantGrid(const Box& box, glm::ivec3 dims, CellBound&& cellBound) {
    for (int a = 0; a < 3; ++a)
        RASTER_REQUIRE(dims[a] >= 1 && dims[a] <= 1024, InvalidArgument,
                       "majorant grid: " + std::to_string(dims[a]) + " cells along an axis (1 to 1024)");
    MajorantGrid grid{{box, dims}, {}};
    grid.bound.resize(grid.frame.cellCount());
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const glm::ivec3 c{x, y, z};
                grid.bound[grid.frame.index(c)] = cellBound(grid.frame.cellBox(c));
            }
    return grid;
}

// Empty-space skipping for a march of n samples at t_i = t0 + (i + ½)·ds (float, as the pixel shader
// computes them): calls visit(i, cell) for each sample whose cell (the one the walk is in at t_i) has a
// majorant above 0, in increasing i, and skips the rest without touching them. Exact where the
// majorant bounds the field (every skipped sample's extinction is 0, so it would add nothing and leave
// the transmittance unchanged: the same bits). visit returns false to stop (early termination).
template <class Visit>
void forEachOccupiedSample(const MajorantGrid& grid, const glm::vec3& o, const glm::vec3& d, float t0, float ds,
                           uint32_t n, Visit&& visit) {
    auto sampleAt = [&](uint32_t i) { return t0 + (float(i) + 0.5f) * ds; };
    uint32_t next = 0;  // the first sample not yet visited or skipped
    // The first sample at or past t: from the closed form, corrected by the same comparison the
    // visit loop makes (the rounded t_i decides, not the formula).
    auto firstAtOrPast = [&](float t) {
        const float guess = std::ceil((t - t0) / ds - 0.5f);
        uint32_t j = guess <= 0.0f ? 0u : guess >= float(n) ? n : uint32_t(guess);
        j = std::max(j, next);
        while (j > next && sampleAt(j - 1) >= t) --j;
        while (j < n && sampleAt(j) < t) ++j;
        return j;
    };
    bool going = true;
    walkGrid(grid.frame, o, d, t0, t0 + float(n) * ds, [&](const glm::ivec3& cell, float, float t_exit) {
        const uint32_t end = firstAtOrPast(t_exit);
        if (grid.at(cell) > 0.0f)
            for (; next < end && going; ++next) going = visit(next, cell);
        next = std::max(next, end);
        return going && next < n;
    });
    // Samples past the walk's last exit (rounding at the far end) lie in the last cell or at most a
    // rounding error outside the box: visit them with the cell that holds their position, as the
    // march without skipping would.
    for (; next < n && going; ++next) {
        going = visit(next, grid.frame.cellAt(o + d * sampleAt(next)));
    }
}

}  // namespace raster::media
