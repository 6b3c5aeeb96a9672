// Particle-based volume data: the particle system's particles (raster/particles.hpp) splatted as smooth
// kernels into a voxel grid (voxel_grid.hpp), which the cloud march (cloud_march.hpp) samples and skips
// through its majorant grid like any other voxel medium. The `smoke-volume` scene draws the smoke
// scene's particles this way.
//
// The field. Each particle is a splat: a centre x_i (metres), a support radius R_i (metres) and a mass
// m_i (m², an extinction cross-section). The extinction it adds at p is m_i·W(|p − x_i|, R_i) (1/m),
// with W the normalised cubic B-spline (M4; Monaghan 1992, the SPH kernel) of support radius R:
//   W(r, R) = 8/(π·R³) · { 1 − 6q² + 6q³   for 0 ≤ q ≤ ½
//                        { 2·(1 − q)³       for ½ < q < 1          q = r/R
//                        { 0                for q ≥ 1
// in 1/m³. ∫W dV = 1 over space, so a splat carries exactly its mass; W is C² (smooth puffs, no
// visible shells), largest at the centre (8/(πR³)), falls monotonically and is exactly 0 from r = R
// on (compact: a splat touches only the voxels within R). A ray through the centre sees the optical
// depth 6·m/(πR²) (∫W dz = 6/(πR²) at r = 0), six times the splat's mean over its disc m/(πR²).
//
// From a particle (the upload's raster::Particle): R = radiusPerSize·size (size: the billboard's
// half-width), and m = opticalDepthPerOpacity·opacity·πR², opacity = colour.a (the emitter's curve at
// the particle's age): the splat's optical depth averaged over its disc is opticalDepthPerOpacity·
// opacity, so the particles' own size and opacity over life shape the volume as they shape the
// billboards.
//
// Why a grid (and not the splats evaluated per sample): a view ray takes hundreds of samples and each
// casts a shadow ray of dozens more; summing the overlapping splats there (dozens in the plume's
// core) costs far more than splatting each once into voxels that a sample reads with one trilinear
// lookup, and the grid is what the existing march, its majorant grid and its bounds already take.
//
// The grid. Cell-centred (voxel_grid.hpp): voxel (i, j, k) holds the field at its centre,
// lo + (i + ½, j + ½, k + ½)·cell (splatCentre). A splat narrower than the grid can show is widened
// to R = max(R_i, kMinSplatCells·the cell's longest edge), its mass kept: a kernel a few voxels
// across sampled at the voxel centres sums to its mass within 0.5 % (tests/particle_volume_test.cpp),
// while one narrower than a voxel could fall between the centres and vanish. What lies outside the
// box is cut off (fitSplatGrid's box holds every splat whole).
//
// Deterministic: voxel v is 0 + the splats' contributions m_i·W(|c_v − x_i|, R_i) added in splat
// order, each computed by the same expression whatever thread adds it; the threads split the grid
// into slabs of whole z-slices, each voxel written by one thread only (no atomics). So the grid is
// bit-identical for any thread count and slab size, and equals splatDensity at each voxel's centre.
//
// Bad input throws Error(InvalidArgument) naming it: a non-finite position, a negative or non-finite
// radius (the particle's size) or mass (its opacity), grid dimensions below 1, an empty or non-finite
// box.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "raster/media/voxel_grid.hpp"
#include "raster/particles.hpp"

namespace raster {
class ThreadPool;
}

namespace raster::media {

// A splat's support radius is at least this many voxels (the cell's longest edge), metres.
constexpr float kMinSplatCells = 2.0f;

// W(r, R), 1/m³ (header). r ≥ 0, R > 0.
template <class T>
T splatKernel(T r, T radius) {
    const T q = r / radius;
    if (!(q < T(1))) return T(0);
    const T norm = T(8) / (T(M_PI) * radius * radius * radius);
    if (q <= T(0.5)) return norm * (T(1) - T(6) * q * q + T(6) * q * q * q);
    const T u = T(1) - q;
    return norm * (T(2) * u * u * u);
}

struct ParticleSplat {
    glm::vec3 position{0.0f};  // metres
    float radius = 0.0f;       // support radius R, metres ≥ 0
    float mass = 0.0f;         // m², ≥ 0: the splat adds m·W(r, R) to the extinction
};

// The splats of the particle system's upload (header: R = radiusPerSize·size,
// m = opticalDepthPerOpacity·opacity·πR²), in the particles' order. Nothing is checked here
// (splatParticles does).
std::vector<ParticleSplat> particleSplats(std::span<const Particle> particles, float optical_depth_per_opacity,
                                          float radius_per_size = 1.0f);

// Where the splats go: the box cut into dims voxels (voxel_grid.hpp's convention).
struct SplatGrid {
    VoxelBox bounds;
    glm::ivec3 dims{1};

    glm::vec3 cellSize() const { return (bounds.hi - bounds.lo) / glm::vec3(dims); }
    // The radius a splat of radius R is drawn with in this grid (header: widened to kMinSplatCells).
    float drawnRadius(float radius) const;
};

// A grid of cubic voxels that holds every splat whole, its longest axis `longest` voxels (at least
// 2·kMinSplatCells + 3): the splats' supports' bounding box, padded by the cells a widened splat may
// need. No splats: the unit box [0, 1]³ in one voxel (an empty volume).
SplatGrid fitSplatGrid(std::span<const ParticleSplat> splats, int longest);

// Voxel (i, j, k)'s centre, metres: lo + (i + ½, j + ½, k + ½)·cell.
glm::vec3 splatCentre(const SplatGrid& grid, int i, int j, int k);

// The extinction at p, 1/m: 0 + Σ m_i·W(|p − x_i|, drawnRadius(R_i)) in splat order (header), the value
// the grid stores at its voxels' centres; for checks.
float splatDensity(std::span<const ParticleSplat> splats, const SplatGrid& grid, const glm::vec3& p);

// The splats into a float voxel grid of extinction (1/m) over grid.bounds (header: deterministic).
// pool may be null (one thread); slicesPerTask z-slices make one task (≥ 1; any value, the same bits).
VoxelGrid splatParticles(std::span<const ParticleSplat> splats, const SplatGrid& grid, ThreadPool* pool = nullptr,
                         int slicesPerTask = 4);

}  // namespace raster::media
