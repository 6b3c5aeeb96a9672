// Voxel grids: sampling, the box maximum, raw and NanoVDB files, the cloud generator (voxel_grid.hpp).
#include "raster/media/voxel_grid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/IO.h>
#include <regex>
#include <stdexcept>

#include "raster/check.hpp"

namespace raster::media {

namespace {

void requireShape(glm::ivec3 dims, const VoxelBox& bounds, size_t count) {
    RASTER_REQUIRE(dims.x > 0 && dims.y > 0 && dims.z > 0, InvalidArgument, "voxel grid: dims must be positive");
    RASTER_REQUIRE(uint64_t(dims.x) * uint64_t(dims.y) * uint64_t(dims.z) == count, InvalidArgument,
                   "voxel grid: " + std::to_string(count) + " values for " + std::to_string(dims.x) + "x" +
                       std::to_string(dims.y) + "x" + std::to_string(dims.z) + " voxels");
    for (int a = 0; a < 3; ++a)
        RASTER_REQUIRE(std::isfinite(bounds.lo[a]) && std::isfinite(bounds.hi[a]) && bounds.lo[a] < bounds.hi[a],
                       InvalidArgument, "voxel grid: the bounds box is empty or not finite");
}

// The first value that is not a density (negative, NaN, infinite), as "<value> at voxel (x, y, z)", or "".
std::string badDensity(const std::vector<float>& v, glm::ivec3 dims) {
    for (size_t i = 0; i < v.size(); ++i) {
        if (std::isfinite(v[i]) && v[i] >= 0.0f) continue;
        const char* what = std::isnan(v[i]) ? "NaN" : std::isinf(v[i]) ? "infinite" : "negative";
        const size_t x = i % size_t(dims.x), y = i / size_t(dims.x) % size_t(dims.y),
                     z = i / (size_t(dims.x) * size_t(dims.y));
        return std::string(what) + " density at voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
               std::to_string(z) + ")";
    }
    return "";
}

// Continuous cell coordinate of world p on axis a: voxel centres at integers.
inline float cellCoord(const VoxelBox& b, glm::ivec3 dims, const glm::vec3& p, int a) {
    return (p[a] - b.lo[a]) / (b.hi[a] - b.lo[a]) * float(dims[a]) - 0.5f;
}

}  // namespace

VoxelGrid::VoxelGrid(glm::ivec3 dims, VoxelBox bounds, std::vector<float> densities)
    : dims_(dims), bounds_(bounds), type_(VoxelType::Float32), floats_(std::move(densities)) {
    requireShape(dims, bounds, floats_.size());
    const std::string bad = badDensity(floats_, dims);
    RASTER_REQUIRE(bad.empty(), InvalidArgument, "voxel grid: " + bad);
}

VoxelGrid::VoxelGrid(glm::ivec3 dims, VoxelBox bounds, std::vector<uint8_t> values, float densityScale)
    : dims_(dims), bounds_(bounds), type_(VoxelType::UInt8), scale_(densityScale), bytes_(std::move(values)) {
    requireShape(dims, bounds, bytes_.size());
    RASTER_REQUIRE(std::isfinite(densityScale) && densityScale >= 0.0f, InvalidArgument,
                   "voxel grid: the density scale must be finite and >= 0");
}

float VoxelGrid::sample(const glm::vec3& p) const {
    for (int a = 0; a < 3; ++a)
        if (!(p[a] >= bounds_.lo[a] && p[a] <= bounds_.hi[a])) return 0.0f;
    int i0[3], i1[3];
    float t[3];
    for (int a = 0; a < 3; ++a) {
        const float u = std::clamp(cellCoord(bounds_, dims_, p, a), 0.0f, float(dims_[a] - 1));
        i0[a] = std::min(int(u), dims_[a] - 1);
        i1[a] = std::min(i0[a] + 1, dims_[a] - 1);
        t[a] = u - float(i0[a]);
    }
    auto lerp = [](float a, float b, float s) { return a + (b - a) * s; };
    auto row = [&](int y, int z) { return lerp(voxel(i0[0], y, z), voxel(i1[0], y, z), t[0]); };
    const float z0 = lerp(row(i0[1], i0[2]), row(i1[1], i0[2]), t[1]);
    const float z1 = lerp(row(i0[1], i1[2]), row(i1[1], i1[2]), t[1]);
    return lerp(z0, z1, t[2]);
}

float VoxelGrid::maxInBox(const glm::vec3& lo, const glm::vec3& hi) const {
    int first[3], last[3];
    for (int a = 0; a < 3; ++a) {
        const float l = std::max(lo[a], bounds_.lo[a]), h = std::min(hi[a], bounds_.hi[a]);
        if (!(l <= h)) return 0.0f;
        // Every voxel whose trilinear support reaches into [l, h], one more each side for rounding.
        const float ul = std::floor(cellCoord(bounds_, dims_, glm::vec3(l), a)) - 1.0f;
        const float uh = std::floor(cellCoord(bounds_, dims_, glm::vec3(h), a)) + 2.0f;
        first[a] = int(std::clamp(ul, 0.0f, float(dims_[a] - 1)));
        last[a] = int(std::clamp(uh, 0.0f, float(dims_[a] - 1)));
    }
    float m = 0.0f;
    for (int z = first[2]; z <= last[2]; ++z)
        for (int y = first[1]; y <= last[1]; ++y)
            for (int x = first[0]; x <= last[0]; ++x) m = std::max(m, voxel(x, y, z));
    return m;
}

float VoxelGrid::maxDensity() const {
    if (type_ == VoxelType::UInt8)
        return bytes_.empty() ? 0.0f : float(*std::max_element(bytes_.begin(), bytes_.end())) * (scale_ / 255.0f);
    return floats_.empty() ? 0.0f : *std::max_element(floats_.begin(), floats_.end());
}

uint64_t VoxelGrid::voxelBytes() const {
    return uint64_t(dims_.x) * uint64_t(dims_.y) * uint64_t(dims_.z) * (type_ == VoxelType::UInt8 ? 1u : 4u);
}

uint64_t VoxelGrid::memoryBytes() const {
    return sizeof(*this) + bytes_.capacity() + floats_.capacity() * sizeof(float);
}

// ---- raw files ----

std::string rawVoxelFileName(const std::string& name, glm::ivec3 dims, VoxelType type) {
    return name + "_" + std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z) +
           (type == VoxelType::UInt8 ? "_uint8.raw" : "_float32.raw");
}

void saveRawVoxelGrid(const std::string& path, const VoxelGrid& grid) {
    static_assert(std::endian::native == std::endian::little, "raw voxel files are little-endian");
    std::ofstream out(path, std::ios::binary);
    RASTER_REQUIRE(out.good(), BadFile, "cannot write voxel grid '" + path + "'");
    const glm::ivec3 d = grid.dims();
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const float v = grid.voxel(x, y, z);
                if (grid.type() == VoxelType::UInt8) {
                    const float s = grid.densityScale();
                    out.put(char(uint8_t(s > 0.0f ? std::lround(v / s * 255.0f) : 0)));
                } else {
                    out.write(reinterpret_cast<const char*>(&v), sizeof v);
                }
            }
    RASTER_REQUIRE(out.good(), BadFile, "cannot write voxel grid '" + path + "'");
}

VoxelGrid loadRawVoxelGrid(const std::string& path, const VoxelBox& bounds, float densityScale) {
    static_assert(std::endian::native == std::endian::little, "raw voxel files are little-endian");
    const std::string base = path.substr(path.find_last_of('/') + 1);
    static const std::regex kName(R"(.*_([0-9]{1,9})x([0-9]{1,9})x([0-9]{1,9})_(uint8|float32)\.raw)");
    std::smatch m;
    RASTER_REQUIRE(std::regex_match(base, m, kName), BadFile,
                   "voxel grid '" + path + "': the name is not name_XxYxZ_uint8.raw or name_XxYxZ_float32.raw");
    const glm::ivec3 dims(std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]));
    RASTER_REQUIRE(dims.x > 0 && dims.y > 0 && dims.z > 0, BadFile, "voxel grid '" + path + "': a dimension is 0");
    const bool is_uint8 = m[4] == "uint8";
    const uint64_t count = uint64_t(dims.x) * uint64_t(dims.y) * uint64_t(dims.z);
    const uint64_t expected = byteCount(count, is_uint8 ? 1 : 4);
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    RASTER_REQUIRE(in.good(), BadFile, "cannot open voxel grid '" + path + "'");
    const uint64_t size = uint64_t(in.tellg());
    RASTER_REQUIRE(size >= expected, BadFile,
                   "voxel grid '" + path + "' is truncated: " + std::to_string(size) + " bytes, its name needs " +
                       std::to_string(expected));
    RASTER_REQUIRE(size == expected, BadFile,
                   "voxel grid '" + path + "' has the wrong size for its name: " + std::to_string(size) +
                       " bytes, its name needs " + std::to_string(expected));
    requireMemory(expected, "voxel grid '" + path + "'");
    in.seekg(0);
    if (is_uint8) {
        std::vector<uint8_t> v(count);
        in.read(reinterpret_cast<char*>(v.data()), std::streamsize(count));
        RASTER_REQUIRE(in.good(), BadFile, "voxel grid '" + path + "' is truncated");
        return VoxelGrid(dims, bounds, std::move(v), densityScale);
    }
    std::vector<float> v(count);
    in.read(reinterpret_cast<char*>(v.data()), std::streamsize(expected));
    RASTER_REQUIRE(in.good(), BadFile, "voxel grid '" + path + "' is truncated");
    const std::string bad = badDensity(v, dims);
    RASTER_REQUIRE(bad.empty(), BadFile, "voxel grid '" + path + "': " + bad);
    return VoxelGrid(dims, bounds, std::move(v));
}

// ---- NanoVDB ----

VoxelGrid loadNanoVdbGrid(const std::string& path) {
    nanovdb::GridHandle<nanovdb::HostBuffer> handle;
    try {
        handle = nanovdb::io::readGrid(path);
    } catch (const std::exception& e) {
        throw Error(ErrorCode::BadFile, "NanoVDB file '" + path + "' is not NanoVDB or unreadable: " + e.what());
    }
    RASTER_REQUIRE(handle.gridMetaData() != nullptr, BadFile, "NanoVDB file '" + path + "' holds no grid");
    const auto* grid = handle.grid<float>();
    RASTER_REQUIRE(grid != nullptr, BadFile,
                   "NanoVDB file '" + path + "': the grid holds " +
                       std::string(nanovdb::toStr(handle.gridMetaData()->gridType())) + ", not float");
    RASTER_REQUIRE(!grid->isEmpty() && !grid->indexBBox().empty(), BadFile,
                   "NanoVDB file '" + path + "': the grid is empty");
    const nanovdb::CoordBBox box = grid->indexBBox();
    const nanovdb::Coord lo = box.min(), hi = box.max();
    const glm::ivec3 dims(hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1);
    const uint64_t count = uint64_t(dims.x) * uint64_t(dims.y) * uint64_t(dims.z);
    requireMemory(byteCount(count, sizeof(float)), "NanoVDB grid '" + path + "'");
    std::vector<float> v(count);
    auto acc = grid->getAccessor();
    size_t at = 0;
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x) v[at++] = acc.getValue(nanovdb::Coord(x, y, z));
    const std::string bad = badDensity(v, dims);
    RASTER_REQUIRE(bad.empty(), BadFile, "NanoVDB file '" + path + "': " + bad);
    // Voxel centres at integer index coordinates: the cells span index ± ½.
    const nanovdb::Vec3d wlo = grid->indexToWorld(nanovdb::Vec3d(lo[0] - 0.5, lo[1] - 0.5, lo[2] - 0.5));
    const nanovdb::Vec3d whi = grid->indexToWorld(nanovdb::Vec3d(hi[0] + 0.5, hi[1] + 0.5, hi[2] + 0.5));
    VoxelBox bounds;
    for (int a = 0; a < 3; ++a) {
        bounds.lo[a] = float(std::min(wlo[a], whi[a]));
        bounds.hi[a] = float(std::max(wlo[a], whi[a]));
    }
    return VoxelGrid(dims, bounds, std::move(v));
}

// ---- the cloud generator ----

namespace {

// splitmix64's finaliser: a well-mixed 64-bit hash.
uint64_t mix(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// A value in [0, 1) at lattice point (x, y, z) of octave o.
float latticeValue(uint64_t seed, int o, int x, int y, int z) {
    const uint64_t h = mix(seed ^ mix(uint64_t(uint32_t(x)) | (uint64_t(uint32_t(y)) << 32)) ^
                           mix(uint64_t(uint32_t(z)) | (uint64_t(uint32_t(o)) << 32)));
    return float(h >> 40) * (1.0f / 16777216.0f);
}

// One octave of value noise: its lattice values tabulated over the lattice points that the grid's
// samples reach (the hash once per point, not eight times per sample), smoothstep-interpolated.
class NoiseOctave {
public:
    // Lattice coordinates p·frequency + offset for p in [−1, 1].
    NoiseOctave(uint64_t seed, int octave, float frequency, float offset) {
        first_ = int(std::floor(offset - frequency)) - 1;
        size_ = int(std::floor(offset + frequency)) + 2 - first_ + 1;
        values_.resize(size_t(size_) * size_t(size_) * size_t(size_));
        size_t at = 0;
        for (int z = 0; z < size_; ++z)
            for (int y = 0; y < size_; ++y)
                for (int x = 0; x < size_; ++x)
                    values_[at++] = latticeValue(seed, octave, first_ + x, first_ + y, first_ + z);
    }
    // Value noise at p (lattice units), in [0, 1).
    float operator()(const glm::vec3& p) const {
        const glm::vec3 f = glm::floor(p);
        const glm::ivec3 i = glm::ivec3(f) - first_;
        const glm::vec3 t = p - f;
        const glm::vec3 s = t * t * (3.0f - 2.0f * t);
        auto at = [&](int dx, int dy, int dz) {
            return values_[size_t(i.x + dx) + size_t(size_) * (size_t(i.y + dy) + size_t(size_) * size_t(i.z + dz))];
        };
        auto lerp = [](float a, float b, float u) { return a + (b - a) * u; };
        const float y0 = lerp(lerp(at(0, 0, 0), at(1, 0, 0), s.x), lerp(at(0, 1, 0), at(1, 1, 0), s.x), s.y);
        const float y1 = lerp(lerp(at(0, 0, 1), at(1, 0, 1), s.x), lerp(at(0, 1, 1), at(1, 1, 1), s.x), s.y);
        return lerp(y0, y1, s.z);
    }

private:
    int first_ = 0, size_ = 0;
    std::vector<float> values_;
};

}  // namespace

VoxelGrid makeCloudGrid(int n, uint64_t seed) {
    RASTER_REQUIRE(n > 0 && n <= 2048, InvalidArgument, "makeCloudGrid: n must be in [1, 2048]");
    const uint64_t count = uint64_t(n) * uint64_t(n) * uint64_t(n);
    requireMemory(byteCount(count, sizeof(float)), "cloud grid");
    std::vector<float> v(count, 0.0f);
    constexpr int kOctaves = 5;
    constexpr float kDensity = 8.0f;   // peak extinction, 1/m
    constexpr float kErosion = 0.6f;   // how far the noise moves the ellipsoid's edge, in units of r
    constexpr float kOffset = 17.0f;   // keeps lattice coordinates positive
    const glm::vec3 radii(0.85f, 0.5f, 0.7f);
    std::vector<NoiseOctave> octaves;
    for (int o = 0; o < kOctaves; ++o) octaves.emplace_back(seed, o, 4.0f * float(1 << o), kOffset);
    size_t at = 0;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x, ++at) {
                const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f) / float(n) * 2.0f - 1.0f;  // [−1, 1]³
                const float r = glm::length(p / radii);
                // fbm < 1, so the eroded shape below is ≤ 1 − r + kErosion/2: nothing beyond that.
                if (r >= 1.0f + 0.5f * kErosion) continue;
                float fbm = 0.0f, amplitude = 0.5f, frequency = 4.0f;
                for (int o = 0; o < kOctaves; ++o) {
                    fbm += amplitude * octaves[size_t(o)](p * frequency + kOffset);
                    amplitude *= 0.5f;
                    frequency *= 2.0f;
                }
                // The ellipsoid's falloff eroded by the noise: 0 beyond r ≈ 1.
                const float shape = 1.0f - r + kErosion * (fbm - 0.5f);
                v[at] = kDensity * std::clamp(shape * 3.0f, 0.0f, 1.0f);
            }
    return VoxelGrid(glm::ivec3(n), VoxelBox{glm::vec3(-1.0f), glm::vec3(1.0f)}, std::move(v));
}

}  // namespace raster::media
