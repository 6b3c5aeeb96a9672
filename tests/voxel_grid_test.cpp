// Voxel grids (raster/media/voxel_grid.hpp): trilinear sampling and its convention, the box maximum
// as a majorant, raw and NanoVDB files and their errors, memory, and the cloud generator.
#include "raster/media/voxel_grid.hpp"

#include <gtest/gtest.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "raster/check.hpp"

namespace {

using raster::Error;
using raster::ErrorCode;
using namespace raster::media;
namespace fs = std::filesystem;

// A 5×4×3 grid of distinct non-negative values over [−1, 3]×[0, 2]×[1, 4].
VoxelGrid smallGrid() {
    const glm::ivec3 d(5, 4, 3);
    std::vector<float> v;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 4.0f);
    for (int i = 0; i < d.x * d.y * d.z; ++i) v.push_back(u(rng));
    return VoxelGrid(d, VoxelBox{{-1, 0, 1}, {3, 2, 4}}, std::move(v));
}

glm::vec3 centre(const VoxelGrid& g, int x, int y, int z) {
    return g.bounds().lo + (glm::vec3(x, y, z) + 0.5f) * g.cellSize();
}

// A temporary directory removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() /
               ("raster_voxel_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

// Expects load() to throw Error(BadFile) whose message names the file and contains `problem`.
template <class Load>
void expectBadFile(const std::string& path, const std::string& problem, Load&& load) {
    try {
        load();
        ADD_FAILURE() << path << ": no error, expected '" << problem << "'";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::BadFile) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
}

TEST(VoxelGrid, ExactAtVoxelCentres) {
    const VoxelGrid g = smallGrid();
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 5; ++x) EXPECT_FLOAT_EQ(g.sample(centre(g, x, y, z)), g.voxel(x, y, z));
}

TEST(VoxelGrid, LinearBetweenCentres) {
    const VoxelGrid g = smallGrid();
    for (float t : {0.0f, 0.25f, 0.5f, 0.8f, 1.0f}) {
        // Along x between (1,2,1) and (2,2,1); along all three between (1,1,0) and (2,2,1).
        const glm::vec3 a = centre(g, 1, 2, 1), b = centre(g, 2, 2, 1);
        EXPECT_NEAR(g.sample(a + t * (b - a)), (1 - t) * g.voxel(1, 2, 1) + t * g.voxel(2, 2, 1), 1e-5f);
        const glm::vec3 c = centre(g, 1, 1, 0), e = centre(g, 2, 2, 1);
        float expected = 0.0f;
        for (int corner = 0; corner < 8; ++corner) {
            const int dx = corner & 1, dy = corner >> 1 & 1, dz = corner >> 2;
            expected += (dx ? t : 1 - t) * (dy ? t : 1 - t) * (dz ? t : 1 - t) * g.voxel(1 + dx, 1 + dy, dz);
        }
        EXPECT_NEAR(g.sample(c + t * (e - c)), expected, 1e-5f);
    }
}

TEST(VoxelGrid, ClampedToEdgeInsideZeroOutside) {
    const VoxelGrid g = smallGrid();
    // Between the outermost centre and the face: the edge voxel's value.
    EXPECT_FLOAT_EQ(g.sample({-1.0f, centre(g, 0, 1, 1).y, centre(g, 0, 1, 1).z}), g.voxel(0, 1, 1));
    EXPECT_FLOAT_EQ(g.sample({3.0f, centre(g, 4, 3, 2).y, 4.0f}), g.voxel(4, 3, 2));
    for (glm::vec3 p : {glm::vec3(-1.001f, 1, 2), glm::vec3(3.001f, 1, 2), glm::vec3(0, -0.01f, 2),
                        glm::vec3(0, 2.01f, 2), glm::vec3(0, 1, 0.99f), glm::vec3(0, 1, 4.01f),
                        glm::vec3(NAN, 1, 2), glm::vec3(1e30f)})
        EXPECT_EQ(g.sample(p), 0.0f) << p.x << " " << p.y << " " << p.z;
}

TEST(VoxelGrid, MaxInBoxBoundsEverySample) {
    const VoxelGrid g = makeCloudGrid(24, 3);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.2f, 1.2f), size(0.0f, 0.3f), t(0.0f, 1.0f);
    for (int box = 0; box < 300; ++box) {
        const glm::vec3 lo(u(rng), u(rng), u(rng));
        const glm::vec3 hi = lo + glm::vec3(size(rng), size(rng), size(rng));
        const float m = g.maxInBox(lo, hi);
        EXPECT_LE(m, g.maxDensity());
        for (int s = 0; s < 40; ++s) {
            const glm::vec3 p = lo + glm::vec3(t(rng), t(rng), t(rng)) * (hi - lo);
            ASSERT_LE(g.sample(p), m) << "box " << box;
        }
        ASSERT_LE(g.sample(lo), m);
        ASSERT_LE(g.sample(hi), m);
    }
    EXPECT_EQ(g.maxInBox(glm::vec3(2), glm::vec3(3)), 0.0f);
    EXPECT_EQ(g.maxInBox(glm::vec3(-1), glm::vec3(1)), g.maxDensity());
}

TEST(VoxelGrid, RawRoundTripFloatAndUint8) {
    TempDir dir;
    const VoxelGrid g = smallGrid();
    const std::string f = dir.file(rawVoxelFileName("small", g.dims(), VoxelType::Float32));
    EXPECT_EQ(fs::path(f).filename(), "small_5x4x3_float32.raw");
    saveRawVoxelGrid(f, g);
    EXPECT_EQ(fs::file_size(f), 5u * 4u * 3u * 4u);
    const VoxelGrid back = loadRawVoxelGrid(f, g.bounds());
    ASSERT_EQ(back.dims(), g.dims());
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 5; ++x) EXPECT_EQ(back.voxel(x, y, z), g.voxel(x, y, z));

    std::vector<uint8_t> bytes(6 * 2 * 3);
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(i * 7);
    const VoxelGrid b(glm::ivec3(6, 2, 3), VoxelBox{}, bytes, 2.0f);
    EXPECT_EQ(b.type(), VoxelType::UInt8);
    EXPECT_FLOAT_EQ(b.voxel(5, 1, 2), float(bytes.back()) / 255.0f * 2.0f);
    const std::string fb = dir.file(rawVoxelFileName("bytes", b.dims(), VoxelType::UInt8));
    saveRawVoxelGrid(fb, b);
    const VoxelGrid bb = loadRawVoxelGrid(fb, VoxelBox{}, 2.0f);
    EXPECT_EQ(bb.type(), VoxelType::UInt8);
    EXPECT_EQ(bb.voxelBytes(), 36u);
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 6; ++x) EXPECT_EQ(bb.voxel(x, y, z), b.voxel(x, y, z));
}

TEST(VoxelGrid, RawFileErrorsNameFileAndProblem) {
    TempDir dir;
    const VoxelBox box;
    auto load = [&](const std::string& path) { return [&box, path] { loadRawVoxelGrid(path, box); }; };
    const std::string unnamed = dir.file("cloud.raw");
    writeBytes(unnamed, std::vector<char>(8));
    expectBadFile(unnamed, "name_XxYxZ_uint8.raw", load(unnamed));
    const std::string zero = dir.file("c_0x2x2_uint8.raw");
    writeBytes(zero, {});
    expectBadFile(zero, "a dimension is 0", load(zero));
    const std::string missing = dir.file("none_2x2x2_uint8.raw");
    expectBadFile(missing, "cannot open", load(missing));
    const std::string truncated = dir.file("c_2x2x2_float32.raw");
    writeBytes(truncated, std::vector<char>(31));
    expectBadFile(truncated, "is truncated: 31 bytes, its name needs 32", load(truncated));
    const std::string large = dir.file("c_2x2x2_uint8.raw");
    writeBytes(large, std::vector<char>(9));
    expectBadFile(large, "wrong size for its name: 9 bytes, its name needs 8", load(large));
    const struct {
        float value;
        const char* problem;
    } bad[] = {{-1.0f, "negative density at voxel (1, 0, 1)"},
               {NAN, "NaN density at voxel (1, 0, 1)"},
               {INFINITY, "infinite density at voxel (1, 0, 1)"}};
    for (const auto& b : bad) {
        std::vector<float> v(8, 0.5f);
        v[5] = b.value;
        const std::string f = dir.file("bad_2x2x2_float32.raw");
        writeBytes(f, std::vector<char>(reinterpret_cast<const char*>(v.data()),
                                        reinterpret_cast<const char*>(v.data() + v.size())));
        expectBadFile(f, b.problem, load(f));
    }
}

TEST(VoxelGrid, NanoVdbRoundTrip) {
    TempDir dir;
    nanovdb::GridBuilder<float> builder(0.0f);
    auto acc = builder.getAccessor();
    auto value = [](int x, int y, int z) { return 1.0f + float(x) + 10.0f * float(y) + 100.0f * float(z); };
    // Active voxels over index box [2, 5]×[−1, 2]×[3, 4].
    for (int z = 3; z <= 4; ++z)
        for (int y = -1; y <= 2; ++y)
            for (int x = 2; x <= 5; ++x) acc.setValue(nanovdb::Coord(x, y, z), value(x + 3, y + 3, z));
    const std::string f = dir.file("blob.nvdb");
    nanovdb::io::writeGrid(f, builder.getHandle(0.5, nanovdb::Vec3d(1.0, 2.0, 3.0), "density"));
    const VoxelGrid g = loadNanoVdbGrid(f);
    ASSERT_EQ(g.dims(), glm::ivec3(4, 4, 2));
    // Voxel centres at origin + index·voxelSize, the cells ± half a voxel around them.
    EXPECT_EQ(g.bounds().lo, glm::vec3(1.0f + 0.5f * 1.5f, 2.0f + 0.5f * -1.5f, 3.0f + 0.5f * 2.5f));
    EXPECT_EQ(g.bounds().hi, glm::vec3(1.0f + 0.5f * 5.5f, 2.0f + 0.5f * 2.5f, 3.0f + 0.5f * 4.5f));
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                EXPECT_EQ(g.voxel(x, y, z), value(x + 2 + 3, y - 1 + 3, z + 3));
                const glm::vec3 world(1.0f + 0.5f * float(x + 2), 2.0f + 0.5f * float(y - 1), 3.0f + 0.5f * float(z + 3));
                EXPECT_FLOAT_EQ(g.sample(world), g.voxel(x, y, z));
            }
}

TEST(VoxelGrid, NanoVdbErrors) {
    TempDir dir;
    const std::string text = dir.file("text.nvdb");
    std::ofstream(text) << "not a volume, just text long enough to hold a header............";
    expectBadFile(text, "is not NanoVDB", [&] { loadNanoVdbGrid(text); });
    const std::string missing = dir.file("missing.nvdb");
    expectBadFile(missing, "is not NanoVDB or unreadable", [&] { loadNanoVdbGrid(missing); });

    nanovdb::GridBuilder<int32_t> ints(0);
    ints.getAccessor().setValue(nanovdb::Coord(1, 2, 3), 7);
    const std::string int_file = dir.file("ints.nvdb");
    nanovdb::io::writeGrid(int_file, ints.getHandle());
    expectBadFile(int_file, "the grid holds int32, not float", [&] { loadNanoVdbGrid(int_file); });

    nanovdb::GridBuilder<float> empty(0.0f);
    const std::string empty_file = dir.file("empty.nvdb");
    nanovdb::io::writeGrid(empty_file, empty.getHandle());
    expectBadFile(empty_file, "the grid is empty", [&] { loadNanoVdbGrid(empty_file); });

    nanovdb::GridBuilder<float> negative(0.0f);
    negative.getAccessor().setValue(nanovdb::Coord(0, 0, 0), 1.0f);
    negative.getAccessor().setValue(nanovdb::Coord(1, 0, 0), -2.0f);
    const std::string negative_file = dir.file("negative.nvdb");
    nanovdb::io::writeGrid(negative_file, negative.getHandle());
    expectBadFile(negative_file, "negative density at voxel (1, 0, 0)", [&] { loadNanoVdbGrid(negative_file); });
}

TEST(VoxelGrid, CloudGridMemoryWithinVoxelsPlus15Percent) {
    const VoxelGrid g = makeCloudGrid(256, 1);
    EXPECT_EQ(g.voxelBytes(), 256ull * 256 * 256 * 4);
    EXPECT_LE(double(g.memoryBytes()), double(g.voxelBytes()) * 1.15);
    // A cloud: dense inside, nothing at the box's faces, a fair share of empty space.
    EXPECT_GT(g.sample(glm::vec3(0.0f)), 1.0f);
    EXPECT_EQ(g.voxel(0, 0, 0), 0.0f);
    EXPECT_EQ(g.voxel(128, 255, 128), 0.0f);
}

TEST(VoxelGrid, CloudGridDeterministicAndSeeded) {
    const VoxelGrid a = makeCloudGrid(32, 5), b = makeCloudGrid(32, 5), c = makeCloudGrid(32, 6);
    int differ = 0, empty = 0;
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                ASSERT_EQ(a.voxel(x, y, z), b.voxel(x, y, z));
                differ += a.voxel(x, y, z) != c.voxel(x, y, z);
                empty += a.voxel(x, y, z) == 0.0f;
            }
    EXPECT_GT(differ, 1000);
    EXPECT_GT(empty, 32 * 32 * 32 / 3);
    EXPECT_LT(empty, 32 * 32 * 32 * 9 / 10);
}

TEST(VoxelGrid, RejectsBadConstruction) {
    EXPECT_THROW(VoxelGrid(glm::ivec3(2, 2, 2), VoxelBox{}, std::vector<float>(7)), Error);
    EXPECT_THROW(VoxelGrid(glm::ivec3(1, 1, 1), VoxelBox{}, std::vector<float>{-1.0f}), Error);
    EXPECT_THROW(VoxelGrid(glm::ivec3(1, 1, 1), VoxelBox{glm::vec3(1), glm::vec3(1)}, std::vector<float>{1.0f}),
                 Error);
    EXPECT_THROW(VoxelGrid(glm::ivec3(1, 1, 1), VoxelBox{}, std::vector<uint8_t>{1}, -1.0f), Error);
    EXPECT_THROW(makeCloudGrid(0, 1), Error);
}

}  // namespace
