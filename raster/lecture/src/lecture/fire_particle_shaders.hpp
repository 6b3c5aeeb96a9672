// The fire scene's shaders (lecture 11, part 3): the particle system's billboards, each with its own
// size and colour. The lecture's vsBillboard / gsBillboard / psFire carry only a position (all
// sprites alike, fire_shaders.hpp); here the vertex is the lecture's `Particle` (raster/particles.hpp)
// and size and colour travel with it:
//   vsFireParticle  pass-through of position (w = 1), size and colour;
//   gsFireParticle  opens the point after projection into a camera-facing quad of half-size `size`
//                   world units (gsBillboard with size·P[0][0], size·P[1][1] for ±billboardSize);
//   psFireParticle  the fire texture tinted by the colour: texel · colour, component by component.
// Answers of the particle lab to come, so not among the library's public headers (see
// fire_shaders.hpp and tests/lab_headers_test.py).
#pragma once

#include <cstddef>
#include <glm/glm.hpp>

#include "raster/input_layout.hpp"
#include "raster/sampler.hpp"
#include "raster/shader.hpp"
#include "raster/specialised_states.hpp"
#include "raster/texture.hpp"

namespace raster::shaders {

// What the vertex shader reads of a Particle (particleInputLayout() describes all of it).
struct FireParticleIn {
    glm::vec3 position;  // world space
    float size;          // world units: the quad's half-width
    glm::vec4 colour;    // linear rgb tint (may exceed 1: the hot core), a = opacity
    RASTER_INPUT_SIGNATURE(FireParticleIn, RASTER_INPUT(position, "POSITION", 0),
                           RASTER_INPUT(size, "SIZE", 0), RASTER_INPUT(colour, "COLOR", 0))
};

// The particle's centre, still in world space (w = 1), with its size and colour.
struct FireParticleVertex {
    glm::vec4 position;
    float size;
    glm::vec4 colour;
};

// A corner of the quad: clip space, texture coordinate, colour (the same at the four corners). A
// template over the scalar type so that the pixel shader runs eight pixels wide too.
template <class T>
struct FireCornerT {
    glm::vec<4, T> position;
    glm::vec<2, T> tex;
    glm::vec<4, T> colour;
};
using FireCorner = FireCornerT<float>;

struct VsFireParticle {
    FireParticleVertex operator()(const FireParticleIn& in) const {
        return {glm::vec4(in.position, 1.0f), in.size, in.colour};
    }
};

// gsBillboard with the particle's own size: the centre goes to clip space and the corners are offset
// there by ±size·(P[0][0], P[1][1]), so the quad faces the camera and keeps `size` world units
// (the offset is multiplied by w when the rasteriser divides). uv as the lecture's: (1,0) (1,1)
// (0,0) (0,1), one triangle strip.
struct GsFireParticle {
    glm::mat4 viewProj{1.0f};
    glm::vec2 projScale{1.0f, 1.0f};  // P[0][0], P[1][1]

    void operator()(const Point<FireParticleVertex>& in, TriangleStream<FireCorner, 4>& stream) const {
        const FireParticleVertex& p = in[0];
        const glm::vec4 c = viewProj * p.position;
        const float bx = p.size * projScale.x, by = p.size * projScale.y;
        stream.Append({c + glm::vec4(bx, by, 0, 0), {1, 0}, p.colour});
        stream.Append({c + glm::vec4(bx, -by, 0, 0), {1, 1}, p.colour});
        stream.Append({c + glm::vec4(-bx, by, 0, 0), {0, 0}, p.colour});
        stream.Append({c + glm::vec4(-bx, -by, 0, 0), {0, 1}, p.colour});
    }
};

// Written once for T = float and T = Float8 (and Float8x2): the fast path shades 4×2 pixels a call.
struct PsFireParticle {
    // Its draws' state (specialised_states.hpp).
    using SpecialisedStates = raster::SpecialisedStates<Specialise<DepthState::LessNoWrite, BlendMode::Additive>>;
    using Input = FireCorner;
    const Texture2D* fireTexture = nullptr;
    SamplerState sampler = SamplerState::bilinear(AddressMode::Clamp);

    template <class T>
    glm::vec<4, T> operator()(const FireCornerT<T>& in) const {
        const glm::vec<4, T> texel = fireTexture->Sample(sampler, in.tex);
        return {texel.x * in.colour.x, texel.y * in.colour.y, texel.z * in.colour.z, texel.w * in.colour.w};
    }
    // The output's alpha is the texel's times a finite opacity, so zero wherever the texture's is:
    // the pipeline may skip a quad's transparent corners under the additive blend (shader.hpp).
    AlphaSource alphaSource() const {
        return {fireTexture, &sampler, uint32_t(offsetof(FireCorner, tex) / sizeof(float))};
    }
};

}  // namespace raster::shaders
