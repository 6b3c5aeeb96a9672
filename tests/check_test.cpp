// Errors and memory (check.hpp): sizes that overflow, requests larger than the machine, and
// std::bad_alloc turned into Error(OutOfMemory) with what and how much.
#include "raster/check.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <string>
#include <typeinfo>

#include <glm/glm.hpp>

namespace raster {
namespace {

TEST(Memory, ByteCountSaturatesInsteadOfWrapping) {
    EXPECT_EQ(byteCount(3, 16), 48u);
    EXPECT_EQ(byteCount(0, UINT64_MAX), 0u);
    EXPECT_EQ(byteCount(UINT64_MAX, 1), UINT64_MAX);
    EXPECT_EQ(byteCount(uint64_t(1) << 32, uint64_t(1) << 32), UINT64_MAX);  // 2^64 does not fit
    EXPECT_EQ(byteCount(4000000000u, 4000000000u), 16000000000000000000u);  // just fits
    EXPECT_EQ(byteCount(5000000000u, 4000000000u), UINT64_MAX);
}

TEST(Memory, FormatBytesNamesTheUnitAndTheExactCount) {
    EXPECT_EQ(formatBytes(0), "0 bytes");
    EXPECT_EQ(formatBytes(1023), "1023 bytes");
    EXPECT_EQ(formatBytes(1536), "1.5 KiB (1536 bytes)");
    EXPECT_EQ(formatBytes(uint64_t(1) << 30), "1.0 GiB (1073741824 bytes)");
}

TEST(Memory, RequestsBeyondTheMachineAreRefusedByName) {
    EXPECT_GT(memoryLimit(), uint64_t(1) << 20);
    EXPECT_NO_THROW(requireMemory(1 << 20, "a small thing"));
    try {
        requireMemory(UINT64_MAX, "the vertex shader outputs of 4e9 instances");
        FAIL() << "an impossible request was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::OutOfMemory);
        const std::string m = e.what();
        EXPECT_NE(m.find("the vertex shader outputs of 4e9 instances"), std::string::npos) << m;
        EXPECT_NE(m.find("more than 2^64 bytes"), std::string::npos) << m;
    }
    EXPECT_THROW(requireMemory(memoryLimit() + 1, "one byte too many"), Error);
    EXPECT_NO_THROW(requireMemory(memoryLimit(), "exactly the limit"));
}

TEST(Memory, BadAllocBecomesAnErrorNamingWhatAndHowMuch) {
    try {
        allocateOrThrow("a render target of size 16384x16384", uint64_t(1) << 30,
                        []() -> int { throw std::bad_alloc(); });
        FAIL() << "nothing was thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::OutOfMemory);
        EXPECT_EQ(std::string(e.what()),
                  "out of memory: cannot allocate 1.0 GiB (1073741824 bytes) for a render target of size 16384x16384");
    }
    EXPECT_EQ(allocateOrThrow("nothing", 0, [] { return 7; }), 7);  // what succeeds passes through
}

TEST(Demangle, NamesTypesAsTheSourceDoesAndKeepsWhatItCannotRead) {
    EXPECT_EQ(demangle(typeid(glm::vec3).name()), "glm::vec<3, float, (glm::qualifier)0>");
    EXPECT_EQ(demangle(typeid(Error).name()), "raster::Error");
    EXPECT_EQ(demangle("not a mangled name"), "not a mangled name");
}

}  // namespace
}  // namespace raster
