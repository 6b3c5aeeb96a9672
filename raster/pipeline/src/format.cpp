#include "raster/format.hpp"

namespace raster {

std::string_view formatName(Format format) {
    switch (format) {
        case Format::Unknown: return "UNKNOWN";
        case Format::R32_FLOAT: return "R32_FLOAT";
        case Format::R32G32_FLOAT: return "R32G32_FLOAT";
        case Format::R32G32B32_FLOAT: return "R32G32B32_FLOAT";
        case Format::R32G32B32A32_FLOAT: return "R32G32B32A32_FLOAT";
        case Format::R8G8B8A8_UNORM: return "R8G8B8A8_UNORM";
        case Format::D32_FLOAT: return "D32_FLOAT";
    }
    return "?";
}

uint32_t formatSize(Format format) {
    switch (format) {
        case Format::Unknown: return 0;
        case Format::R32_FLOAT: return 4;
        case Format::R32G32_FLOAT: return 8;
        case Format::R32G32B32_FLOAT: return 12;
        case Format::R32G32B32A32_FLOAT: return 16;
        case Format::R8G8B8A8_UNORM: return 4;
        case Format::D32_FLOAT: return 4;
    }
    return 0;
}

uint32_t formatComponents(Format format) {
    switch (format) {
        case Format::Unknown: return 0;
        case Format::R32_FLOAT: return 1;
        case Format::R32G32_FLOAT: return 2;
        case Format::R32G32B32_FLOAT: return 3;
        case Format::R32G32B32A32_FLOAT: return 4;
        case Format::R8G8B8A8_UNORM: return 4;
        case Format::D32_FLOAT: return 1;
    }
    return 0;
}

}  // namespace raster
