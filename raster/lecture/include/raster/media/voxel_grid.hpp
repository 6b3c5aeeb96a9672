// Volume data as a voxel grid: a 3D scalar texture of density (1/m) over an axis-aligned world box.
//
// Convention (cell-centred, as a D3D11 3D texture's texels): the box [lo, hi] is cut into X×Y×Z cells
// of size (hi − lo)/dims, and voxel (i, j, k) is the density at its cell's centre,
// lo + (i + ½, j + ½, k + ½)·cell. sample(p) is trilinear between the eight nearest centres; inside the
// box but beyond the outermost centres the index is clamped to the edge (the boundary voxels' value
// holds to the box's faces); outside the box the density is exactly 0, the natural choice for a medium
// (rays clipped to the box see nothing past it).
//
// Storage: the file's own value type — uint8 kept as uint8 (value/255 × densityScale when sampled) and
// float32 as float — so the grid takes its voxels plus a fixed few dozen bytes (memoryBytes()), well
// inside the rule "voxels + 15 %". Voxels are x fastest, then y, then z.
//
// Files:
//  - raw: `name_XxYxZ_uint8.raw` or `name_XxYxZ_float32.raw`, little-endian, x fastest; the dims are
//    read from the name, the world box is the caller's (the file has none);
//  - NanoVDB `.nvdb`: the first float grid, its active voxels' bounding box densely copied, the box in
//    world space from the grid's voxel size and origin (index-to-world map).
// A file that is missing, of the wrong size for its name, truncated, not NanoVDB, of another value type,
// empty, or holding a negative, NaN or infinite density throws Error(BadFile) naming the file and the
// problem.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace raster::media {

// An axis-aligned box in world space, metres.
struct VoxelBox {
    glm::vec3 lo{0.0f};
    glm::vec3 hi{1.0f};
};

enum class VoxelType { UInt8, Float32 };

class VoxelGrid {
public:
    VoxelGrid() = default;
    // Float densities, dims.x·dims.y·dims.z of them, each finite and ≥ 0 (Error(InvalidArgument)
    // naming the first one that is not, or dims that do not match the count, or an empty box).
    VoxelGrid(glm::ivec3 dims, VoxelBox bounds, std::vector<float> densities);
    // uint8 values, sampled as value/255·densityScale (densityScale finite and ≥ 0).
    VoxelGrid(glm::ivec3 dims, VoxelBox bounds, std::vector<uint8_t> values, float densityScale);

    glm::ivec3 dims() const { return dims_; }
    const VoxelBox& bounds() const { return bounds_; }
    VoxelType type() const { return type_; }
    float densityScale() const { return scale_; }
    // The world size of one cell, metres.
    glm::vec3 cellSize() const { return (bounds_.hi - bounds_.lo) / glm::vec3(dims_); }

    // The density stored at voxel (x, y, z), 1/m; indices must be inside dims().
    float voxel(int x, int y, int z) const {
        const size_t at = size_t(x) + size_t(dims_.x) * (size_t(y) + size_t(dims_.y) * size_t(z));
        return type_ == VoxelType::UInt8 ? float(bytes_[at]) * (scale_ / 255.0f) : floats_[at];
    }
    // The voxels in storage order (header): floats for Float32 grids, bytes for UInt8 ones (the other
    // pointer is null or dangling-empty); for samplers that index them directly.
    const float* floatData() const { return floats_.data(); }
    const uint8_t* byteData() const { return bytes_.data(); }
    // Trilinear density at world position p (header: convention); 0 outside bounds().
    float sample(const glm::vec3& p) const;
    // An upper bound of sample(p) for every p in the world box [lo, hi] (the voxels of its trilinear
    // support, clamped to the grid); 0 where the box misses bounds(). For a majorant grid.
    float maxInBox(const glm::vec3& lo, const glm::vec3& hi) const;
    // The largest density of all voxels.
    float maxDensity() const;

    // Bytes the voxels take (the file's value type) and bytes this grid holds in all.
    uint64_t voxelBytes() const;
    uint64_t memoryBytes() const;

private:
    glm::ivec3 dims_{0};
    VoxelBox bounds_;
    VoxelType type_ = VoxelType::Float32;
    float scale_ = 1.0f;
    std::vector<uint8_t> bytes_;
    std::vector<float> floats_;
};

// Loads `name_XxYxZ_uint8.raw` or `name_XxYxZ_float32.raw` (header: files) over the world box bounds;
// uint8 values become value/255·densityScale. Error(BadFile) names the file and the problem.
VoxelGrid loadRawVoxelGrid(const std::string& path, const VoxelBox& bounds, float densityScale = 1.0f);
// Writes grid as a raw file of its value type (the name's dims and type are the caller's business:
// rawVoxelFileName gives the name the loader parses).
void saveRawVoxelGrid(const std::string& path, const VoxelGrid& grid);
std::string rawVoxelFileName(const std::string& name, glm::ivec3 dims, VoxelType type);

// Loads the first grid of a NanoVDB file, which must hold floats (header: files).
VoxelGrid loadNanoVdbGrid(const std::string& path);

// The cloud scene's density: an n³ float grid over the box [−1, 1]³, fbm of seeded value noise shaped
// by an ellipsoid (denser inside, a soft edge, 0 near the box's faces). Deterministic: the same n and
// seed give the same bits on every machine.
VoxelGrid makeCloudGrid(int n, uint64_t seed);

}  // namespace raster::media
