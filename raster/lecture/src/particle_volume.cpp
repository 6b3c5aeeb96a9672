#include "raster/media/particle_volume.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "raster/check.hpp"
#include "raster/thread_pool.hpp"

namespace raster::media {

namespace {

std::string splatProblem(size_t index, const ParticleSplat& s) {
    char text[200];
    const glm::vec3& p = s.position;
    const char* what = nullptr;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        std::snprintf(text, sizeof text, "particle volume: particle %zu's position (%g, %g, %g) is not finite", index,
                      double(p.x), double(p.y), double(p.z));
        return text;
    }
    if (!std::isfinite(s.radius) || s.radius < 0.0f)
        what = "radius (its size, metres)";
    else if (!std::isfinite(s.mass) || s.mass < 0.0f)
        what = "mass (from its opacity, m^2)";
    if (what == nullptr) return "";
    const double value = what[0] == 'r' ? double(s.radius) : double(s.mass);
    std::snprintf(text, sizeof text, "particle volume: particle %zu's %s is %g: must be finite and >= 0", index, what,
                  value);
    return text;
}

void requireGrid(const SplatGrid& g) {
    for (int a = 0; a < 3; ++a) {
        RASTER_REQUIRE(g.dims[a] >= 1, InvalidArgument,
                       "particle volume: " + std::to_string(g.dims[a]) + " voxels along axis " + "xyz"[a] +
                           " (at least 1)");
        RASTER_REQUIRE(std::isfinite(g.bounds.lo[a]) && std::isfinite(g.bounds.hi[a]) && g.bounds.lo[a] < g.bounds.hi[a],
                       InvalidArgument, std::string("particle volume: the box is empty or not finite along ") + "xyz"[a]);
    }
}

// One splat's contribution at the point c: m·W(|c − x|, R), R already drawnRadius's.
float splatAt(const ParticleSplat& s, float radius, const glm::vec3& c) {
    const glm::vec3 d = c - s.position;
    return s.mass * splatKernel(std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z), radius);
}

// The voxel indices along axis a whose centres may lie within radius of x, clamped to the grid:
// [first, last], empty where first > last. One voxel of margin each side: the kernel decides.
void voxelRange(const SplatGrid& g, int a, float x, float radius, int& first, int& last) {
    const float cell = g.cellSize()[a];
    const float lo = std::floor((x - radius - g.bounds.lo[a]) / cell - 0.5f) - 1.0f;
    const float hi = std::ceil((x + radius - g.bounds.lo[a]) / cell - 0.5f) + 1.0f;
    first = int(std::clamp(lo, 0.0f, float(g.dims[a])));
    last = int(std::clamp(hi, -1.0f, float(g.dims[a] - 1)));
}

}  // namespace

std::vector<ParticleSplat> particleSplats(std::span<const Particle> particles, float optical_depth_per_opacity,
                                          float radius_per_size) {
    std::vector<ParticleSplat> splats;
    splats.reserve(particles.size());
    for (const Particle& p : particles) {
        const float radius = radius_per_size * p.size;
        const float area = float(M_PI) * radius * radius;
        splats.push_back({p.position, radius, optical_depth_per_opacity * p.colour.a * area});
    }
    return splats;
}

float SplatGrid::drawnRadius(float radius) const {
    const glm::vec3 cell = cellSize();
    return std::max(radius, kMinSplatCells * std::max({cell.x, cell.y, cell.z}));
}

SplatGrid fitSplatGrid(std::span<const ParticleSplat> splats, int longest) {
    constexpr int kPad = int(kMinSplatCells) + 1;  // voxels each side: a widened splat's reach, and one more
    RASTER_REQUIRE(longest >= 2 * kPad + 1, InvalidArgument,
                   "particle volume: " + std::to_string(longest) + " voxels along the longest axis (at least " +
                       std::to_string(2 * kPad + 1) + ")");
    if (splats.empty()) return {};
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (size_t i = 0; i < splats.size(); ++i) {
        const std::string problem = splatProblem(i, splats[i]);
        RASTER_REQUIRE(problem.empty(), InvalidArgument, problem);
        lo = glm::min(lo, splats[i].position - splats[i].radius);
        hi = glm::max(hi, splats[i].position + splats[i].radius);
    }
    const glm::vec3 extent = hi - lo;
    const float widest = std::max({extent.x, extent.y, extent.z});
    const float cell = widest > 0.0f ? widest / float(longest - 2 * kPad) : 1.0f;  // one point: voxels of 1 m
    SplatGrid g;
    for (int a = 0; a < 3; ++a) {
        // At most longest − 2·kPad inside the padding (the widest axis: exactly, whatever the rounding of
        // extent/cell; a rounding short of the extent is within the padding's spare voxel).
        g.dims[a] = std::clamp(int(std::ceil(extent[a] / cell)), 1, longest - 2 * kPad) + 2 * kPad;
        g.bounds.lo[a] = lo[a] - float(kPad) * cell;
        g.bounds.hi[a] = g.bounds.lo[a] + float(g.dims[a]) * cell;
    }
    return g;
}

glm::vec3 splatCentre(const SplatGrid& grid, int i, int j, int k) {
    return grid.bounds.lo + (glm::vec3(float(i), float(j), float(k)) + 0.5f) * grid.cellSize();
}

float splatDensity(std::span<const ParticleSplat> splats, const SplatGrid& grid, const glm::vec3& p) {
    float sum = 0.0f;
    for (const ParticleSplat& s : splats) sum += splatAt(s, grid.drawnRadius(s.radius), p);
    return sum;
}

VoxelGrid splatParticles(std::span<const ParticleSplat> splats, const SplatGrid& grid, ThreadPool* pool,
                         int slicesPerTask) {
    requireGrid(grid);
    RASTER_REQUIRE(slicesPerTask >= 1, InvalidArgument,
                   "particle volume: " + std::to_string(slicesPerTask) + " z-slices a task (at least 1)");
    for (size_t i = 0; i < splats.size(); ++i) {
        const std::string problem = splatProblem(i, splats[i]);
        RASTER_REQUIRE(problem.empty(), InvalidArgument, problem);
    }
    const glm::ivec3 n = grid.dims;
    const uint64_t count = uint64_t(n.x) * uint64_t(n.y) * uint64_t(n.z);
    std::vector<float> voxels;
    allocateOrThrow("a particle volume of " + std::to_string(n.x) + "x" + std::to_string(n.y) + "x" +
                        std::to_string(n.z) + " voxels",
                    byteCount(count, sizeof(float)), [&] { voxels.assign(size_t(count), 0.0f); });
    // Each splat's radius and its voxel range, once.
    struct Reach {
        float radius;
        int first[3], last[3];
    };
    std::vector<Reach> reach(splats.size());
    for (size_t i = 0; i < splats.size(); ++i) {
        Reach& r = reach[i];
        r.radius = grid.drawnRadius(splats[i].radius);
        for (int a = 0; a < 3; ++a) voxelRange(grid, a, splats[i].position[a], r.radius, r.first[a], r.last[a]);
    }
    const uint32_t tasks = uint32_t((n.z + slicesPerTask - 1) / slicesPerTask);
    auto slab = [&](uint32_t task) {
        const int z0 = int(task) * slicesPerTask, z1 = std::min(n.z, z0 + slicesPerTask);
        for (size_t i = 0; i < splats.size(); ++i) {  // splat order: the voxels' sums' order (header)
            const Reach& r = reach[i];
            const int k0 = std::max(z0, r.first[2]), k1 = std::min(z1 - 1, r.last[2]);
            for (int k = k0; k <= k1; ++k)
                for (int j = r.first[1]; j <= r.last[1]; ++j) {
                    float* row = voxels.data() + size_t(n.x) * (size_t(j) + size_t(n.y) * size_t(k));
                    for (int x = r.first[0]; x <= r.last[0]; ++x)
                        row[x] += splatAt(splats[i], r.radius, splatCentre(grid, x, j, k));
                }
        }
    };
    if (pool == nullptr || pool->size() == 1 || tasks <= 1) {
        for (uint32_t t = 0; t < tasks; ++t) slab(t);
    } else {
        pool->parallelFor(tasks, [&](uint32_t t, unsigned) { slab(t); });
    }
    return VoxelGrid(n, grid.bounds, std::move(voxels));
}

}  // namespace raster::media
