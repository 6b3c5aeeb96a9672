// The lecture's fire billboards (lecture 11, part 3): the structs its shaders pass along and the
// pass-through vertex shader. The finished gsBillboard and psFire are the billboards lab's answers:
// they live with the benchmark scenes (raster/lecture/src/lecture/fire_shaders.hpp) and the lab's
// solution, not here.
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

// vsBillboard: pass-through; the geometry shader does the transform, so that it can open the sprite
// after the projection.
struct VsBillboard {
    BillboardVertex operator()(const BillboardIn& in) const { return {glm::vec4(in.position, 1.0f)}; }
};

}  // namespace raster::shaders
