// The lecture's finished fire shaders (lecture 11, part 3): gsBillboard and psFire, as the
// benchmark scenes (raster/lecture/src/scenes.cpp), the tools and the tests draw them. They are the
// billboards lab's answers, so they are not among the library's public headers: the target
// raster_lecture gives this folder to the library, the tools and the tests, never to labs/
// (tests/lab_headers_test.py checks that no lab's translation unit includes this file).
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "raster/sampler.hpp"
#include "raster/shader.hpp"
#include "raster/shaders/billboard.hpp"
#include "raster/specialised_states.hpp"
#include "raster/texture.hpp"

namespace raster::shaders {

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
    // Its draws' state (specialised_states.hpp).
    using SpecialisedStates =
        raster::SpecialisedStates<Specialise<DepthState::LessNoWrite, BlendMode::Additive>>;
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
