#include "raster/check.hpp"

#include <algorithm>

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace raster {

const char* errorCodeName(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidArgument: return "invalid argument";
        case ErrorCode::InvalidState: return "invalid state";
        case ErrorCode::LayoutMismatch: return "input layout mismatch";
        case ErrorCode::OutOfRange: return "out of range";
        case ErrorCode::BadFile: return "bad file";
        case ErrorCode::ShaderError: return "shader error";
        case ErrorCode::OutOfMemory: return "out of memory";
    }
    return "error";
}

std::string formatBytes(uint64_t bytes) {
    static constexpr const char* kUnits[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double value = double(bytes);
    int unit = 0;
    while (value >= 1024.0 && unit < 6) value /= 1024.0, ++unit;
    char text[64];
    if (unit == 0)
        std::snprintf(text, sizeof text, "%llu bytes", (unsigned long long)bytes);
    else
        std::snprintf(text, sizeof text, "%.1f %s (%llu bytes)", value, kUnits[unit], (unsigned long long)bytes);
    return text;
}

uint64_t memoryLimit() {
    const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
    uint64_t limit = pages > 0 && page_size > 0 ? byteCount(uint64_t(pages), uint64_t(page_size)) : UINT64_MAX;
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) limit = std::min<uint64_t>(limit, as.rlim_cur);
    return limit;
}

void requireMemory(uint64_t bytes, const std::string& what) {
    const uint64_t limit = memoryLimit();
    RASTER_REQUIRE(bytes <= limit, OutOfMemory,
                   what + " needs " + (bytes == UINT64_MAX ? std::string("more than 2^64 bytes") : formatBytes(bytes)) +
                       ", more than the " + formatBytes(limit) + " this process may hold");
}

void checkFailed(const char* file, int line, const char* condition) {
    std::fprintf(stderr, "raster: internal check failed at %s:%d: %s\n", file, line, condition);
    std::abort();
}

}  // namespace raster
