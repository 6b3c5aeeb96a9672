// The lecture's fire billboards (lecture 11, part 3): vsBillboard, gsBillboard, psFire.
//
// HLSL of the slides, for comparison:
//   VsosBillboard vsBillboard(IaosBillboard input) { output.pos = float4(input.pos, 1); }
//   [maxvertexcount(4)] void gsBillboard(point VsosBillboard input[1],
//                                        inout TriangleStream<GsosBillboard> stream) { ... }
//   float4 psFire(GsosBillboard input) : SV_Target { return billboardTexture.Sample(ss, input.tex); }
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/sampler.hpp"
#include "raster/shader.hpp"
#include "raster/texture.hpp"

namespace raster::shaders {

// IaosBillboard: one particle as the input assembler hands it over.
struct BillboardIn {
    glm::vec3 position;  // world space
    RASTER_INPUT_SIGNATURE(BillboardIn, RASTER_INPUT(position, "POSITION", 0))
};

// VsosBillboard: the particle's centre, still in world space (w = 1).
struct BillboardVertex {
    glm::vec4 position;
};

// GsosBillboard: a corner of the billboard, clip space, with its texture coordinate. A template
// over the scalar type so that the pixel shader can also run eight pixels wide (simd.hpp).
template <class T>
struct BillboardCornerT {
    glm::vec<4, T> position;
    glm::vec<2, T> tex;
};
using BillboardCorner = BillboardCornerT<float>;

// Pass-through: the geometry shader does the transform, so that it can open the sprite after projection.
struct VsBillboard {
    BillboardVertex operator()(const BillboardIn& in) const { return {glm::vec4(in.position, 1.0f)}; }
};

// Opens the sprite after projection (method (c) of the lecture): the centre goes to clip space and
// the four corners are offset there by ±billboardSize·(1, 1), so the sprite always faces the camera
// and keeps a constant world size (the offset is multiplied by w when the rasteriser divides).
struct GsBillboard {
    glm::mat4 viewProj{1.0f};
    glm::vec2 billboardSize{0.1f, 0.1f};  // world half-size times P[0][0] and P[1][1]

    void operator()(const Point<BillboardVertex>& in, TriangleStream<BillboardCorner, 4>& stream) const {
        const glm::vec4 c = viewProj * in[0].position;
        const float bx = billboardSize.x, by = billboardSize.y;
        stream.Append({c + glm::vec4(bx, by, 0, 0), {1, 0}});
        stream.Append({c + glm::vec4(bx, -by, 0, 0), {1, 1}});
        stream.Append({c + glm::vec4(-bx, by, 0, 0), {0, 0}});
        stream.Append({c + glm::vec4(-bx, -by, 0, 0), {0, 1}});
    }
};

// Written once for T = float and T = Float8: the pipeline shades 4×2 pixels per call where it can.
struct PsFire {
    using Input = BillboardCorner;
    const Texture2D* billboardTexture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);

    template <class T>
    glm::vec<4, T> operator()(const BillboardCornerT<T>& in) const {
        return billboardTexture->Sample(sampler, in.tex);
    }
    // The output is the sample, so its alpha is zero where the texture's is (shader.hpp): the
    // pipeline may skip a sprite's transparent corners.
    AlphaSource alphaSource() const {
        return {billboardTexture, &sampler, uint32_t(offsetof(BillboardCorner, tex) / sizeof(float))};
    }
};

}  // namespace raster::shaders
