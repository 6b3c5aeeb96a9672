// Samplers: how Texture2D::Sample turns a texture coordinate into a colour. This is the
// D3D11_SAMPLER_DESC subset raster implements: point or linear filtering chosen separately for
// magnification, minification and between mip levels; five address modes per axis; a level-of-detail
// bias and clamp; a border colour. No anisotropy and no comparison filtering.
//
// Texture coordinates are normalised: (0, 0) is the top-left corner of texel (0, 0), (1, 1) the
// bottom-right corner of the last texel, and texel i's centre is at (i + 0.5) / width. Texture2D
// documents the filtering rules exactly.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace raster {

// D3D11_FILTER, split per stage as the enum's name spells it (MIN_x_MAG_y_MIP_z).
enum class Filter : uint8_t {
    Point,   // the one texel the coordinate falls in (or the nearest mip level)
    Linear,  // the 2×2 texels around the coordinate, weighted bilinearly (or two mip levels, blended)
};

// What a texel index i outside [0, n) reads, for a level n texels wide (or high); D3D11_TEXTURE_ADDRESS_MODE.
// Each axis is addressed on its own, and under linear filtering each of the two texels per axis is
// addressed on its own (so Wrap blends the last texel with the first).
enum class AddressMode : uint8_t {
    Wrap,        // i mod n: the texture repeats
    Mirror,      // repeats with every other copy flipped: −1 → 0, n → n−1 (period 2n)
    Clamp,       // clamp(i, 0, n−1): the edge texels extend outward
    Border,      // texels outside [0, n) read SamplerState::borderColor
    MirrorOnce,  // flipped once about 0 (−1 → 0, −n → n−1), then clamped like Clamp
};

struct SamplerState {
    Filter minFilter = Filter::Linear;  // when λ > 0 (the texture shrinks on screen)
    Filter magFilter = Filter::Linear;  // when λ ≤ 0 (the texture grows on screen)
    Filter mipFilter = Filter::Linear;  // Point: nearest level; Linear: blend the two nearest levels
    AddressMode addressU = AddressMode::Clamp;
    AddressMode addressV = AddressMode::Clamp;
    // Level of detail, in mip levels (1 = half the resolution): added to the computed λ, then the
    // sum is clamped to [minLod, maxLod]. maxLod may be D3D11_FLOAT32_MAX (or +inf): "no limit".
    float mipLodBias = 0.0f;
    float minLod = 0.0f;
    float maxLod = 1000.0f;
    glm::vec4 borderColor{0, 0, 0, 0};  // what AddressMode::Border reads, as the shader sees it

    // D3D11_FILTER_MIN_MAG_MIP_POINT.
    static SamplerState point(AddressMode address = AddressMode::Clamp) {
        SamplerState s;
        s.minFilter = s.magFilter = s.mipFilter = Filter::Point;
        s.addressU = s.addressV = address;
        return s;
    }
    // D3D11_FILTER_MIN_MAG_MIP_LINEAR (trilinear).
    static SamplerState linear(AddressMode address = AddressMode::Clamp) {
        SamplerState s;
        s.addressU = s.addressV = address;
        return s;
    }
    // D3D11_FILTER_MIN_MAG_LINEAR_MIP_POINT (bilinear within the nearest mip level).
    static SamplerState bilinear(AddressMode address = AddressMode::Clamp) {
        SamplerState s;
        s.mipFilter = Filter::Point;
        s.addressU = s.addressV = address;
        return s;
    }

    bool operator==(const SamplerState& other) const = default;
};

// Throws Error(InvalidState) for a state CreateSamplerState would refuse: a filter or address mode
// outside its enum, a NaN or infinite mipLodBias, a NaN minLod or maxLod, or minLod > maxLod.
// Texture2D's Sample functions assume a valid sampler (the pipeline validates at bind time); given an
// invalid one they return an unspecified colour but never read out of bounds.
void validate(const SamplerState& sampler);

}  // namespace raster
