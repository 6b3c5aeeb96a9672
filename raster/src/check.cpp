#include "raster/check.hpp"

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
    }
    return "error";
}

void checkFailed(const char* file, int line, const char* condition) {
    std::fprintf(stderr, "raster: internal check failed at %s:%d: %s\n", file, line, condition);
    std::abort();
}

}  // namespace raster
