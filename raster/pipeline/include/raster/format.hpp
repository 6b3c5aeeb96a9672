// Formats: how an element of a buffer, a texel or a render-target pixel is stored, and the
// Direct3D 11 conversion rules between those bits and the float a shader sees.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

namespace raster {

// The DXGI_FORMAT subset raster understands. Names follow DXGI so that the lecture's code reads the same.
enum class Format : uint8_t {
    Unknown,
    R32_FLOAT,           // 1 × float32
    R32G32_FLOAT,        // 2 × float32
    R32G32B32_FLOAT,     // 3 × float32
    R32G32B32A32_FLOAT,  // 4 × float32; also a render-target and texture format
    R8G8B8A8_UNORM,      // 4 × uint8, read as n/255; also a render-target and texture format
    D32_FLOAT,           // depth target: 1 × float32 in [0, 1]
};

std::string_view formatName(Format format);
// Bytes one element occupies (0 for Unknown).
uint32_t formatSize(Format format);
// Components the shader sees (R32G32 -> 2, R8G8B8A8_UNORM -> 4).
uint32_t formatComponents(Format format);

// UNORM8 -> float: n / 255, exact to float rounding (D3D11 "UNORM -> FLOAT").
inline float unorm8ToFloat(uint8_t n) { return float(n) * (1.0f / 255.0f); }

// float -> UNORM8 by the D3D11 rule: NaN -> 0, clamp to [0, 1], scale by 255, add 0.5 and truncate
// (round half up, not half even).
inline uint8_t floatToUnorm8(float f) {
    if (!(f > 0.0f)) return 0;  // also NaN
    if (f >= 1.0f) return 255;
    return uint8_t(f * 255.0f + 0.5f);
}
inline uint8_t doubleToUnorm8(double f) {
    if (!(f > 0.0)) return 0;
    if (f >= 1.0) return 255;
    return uint8_t(f * 255.0 + 0.5);
}

}  // namespace raster
