// The lecture's sprites and billboards (lecture 11, part 3), as shaders (functors) and the vertex data
// they read. The answers of the sprite-methods lab (labs/sprite-methods/), so not among the library's
// public headers (tests/lab_headers_test.py checks that no lab includes this folder).
//
// A camera-facing sprite of half-size s at centre c, three ways (the lecture's (a), (b), (c)):
//   (a) VsSpriteClassic   classic transforms: the quad's model matrix is translate(c) · R⁻¹, R the view
//                         rotation, so that V · M leaves the quad parallel to the camera plane; then
//                         the usual world-view-projection. The slide says "the inverse transpose of the
//                         view rotation": for a rotation (R⁻¹)ᵀ = R, and a quad turned by R is turned
//                         twice; what faces the camera plane is R⁻¹ = Rᵀ, the camera's axes in world
//                         space, which this shader uses.
//   (b) VsSpriteOwn       its own transform: c to camera space, the corner offsets (±s, ±s, 0) added
//                         there, then the projection.
//   (c) GsFireParticle    opened after projection (gsBillboard, fire_particle_shaders.hpp): the corners
//                         offset in clip space by ±s·(P[0][0], P[1][1]).
// The three are one quad in exact arithmetic, for any field of view and any place on the screen:
// (a)'s corner is c + Rᵀ(±s, ±s, 0), and V maps it to V·c + (±s, ±s, 0), (b)'s corner; a perspective
// matrix's first two columns are (P[0][0], 0, 0, 0) and (0, P[1][1], 0, 0), so P maps (b)'s offset to
// (c)'s. All three lie in a plane of constant view depth: a square on the screen wherever it is.
// What differs at a wide field of view, near the image's edges, is a sprite turned towards the eye
// *point* (VsSpriteFacingEye, "viewpoint-oriented"): perpendicular to the ray from the eye, it is
// stretched along the screen's radius by 1/cos θ (θ the ray's angle off the view axis), as a sphere's
// outline is, and it does not turn when the camera only rotates. tests/sprites_test.cpp measures both.
//
// Billboards that do not face the camera everywhere:
//   VsAxisBillboard       turns about a world axis only (trees): the axis stays, the quad faces the eye
//                         in the plane normal to the axis (axisBillboardCorner).
//   VsStaticBillboard     a quad fixed in the world (static billboards; several crossed ones make a
//                         billboard cloud, billboardCloud() below).
// The pixel shaders: PsFireParticle (texture × colour) for the sprites, PsAlphaTested for the forest
// (discards below an alpha threshold, so it needs depth writes and no sorting).
#pragma once

#include <cmath>
#include <cstddef>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "lecture/fire_particle_shaders.hpp"
#include "raster/labs/sprite_methods.hpp"
#include "raster/format.hpp"
#include "raster/input_layout.hpp"
#include "raster/sampler.hpp"
#include "raster/shader.hpp"
#include "raster/texture.hpp"

namespace raster::shaders {

// One corner of a sprite's quad (six a sprite: two triangles) for (a), (b) and the eye-facing sprite:
// the sprite-methods lab's format, centre, size (the quad's half-width), tint, corner (±1, ±1); (c)
// reads one FireParticleIn a sprite instead (position, size, colour). The corners' order
// (kSpriteCorners, gsBillboard's strip as two triangles) and their texture coordinates
// (spriteTexCoord) are the lab's too (raster/labs/sprite_methods.hpp).
using SpriteQuadIn = sprite_lab::SpriteCornerIn;
using sprite_lab::kSpriteCorners;
using sprite_lab::spriteTexCoord;

// (a) Classic transforms. cameraToWorld is R⁻¹ = Rᵀ (the transpose of the view matrix's upper 3×3):
// the model matrix turns the quad's plane z = 0 to the camera plane, viewProj = P · V does the rest.
struct VsSpriteClassic {
    glm::mat4 viewProj{1.0f};
    glm::mat3 cameraToWorld{1.0f};

    FireCorner operator()(const SpriteQuadIn& in) const {
        glm::mat4 model(cameraToWorld);
        model[3] = glm::vec4(in.centre, 1.0f);
        const glm::vec4 local(in.size * in.corner.x, in.size * in.corner.y, 0.0f, 1.0f);
        return {viewProj * (model * local), spriteTexCoord(in.corner), in.tint};
    }
};

// (b) Its own transform: the centre to camera space, the corner added there, then the projection.
struct VsSpriteOwn {
    glm::mat4 view{1.0f}, proj{1.0f};

    FireCorner operator()(const SpriteQuadIn& in) const {
        glm::vec4 corner = view * glm::vec4(in.centre, 1.0f);
        corner.x += in.size * in.corner.x;
        corner.y += in.size * in.corner.y;
        return {proj * corner, spriteTexCoord(in.corner), in.tint};
    }
};

// The sprite turned towards the eye point: its normal is the unit vector from the centre to the eye,
// its right vector horizontal for the camera (normal to the camera's up and to that normal).
struct VsSpriteFacingEye {
    glm::mat4 viewProj{1.0f};
    glm::vec3 eye{0.0f};
    glm::vec3 cameraUp{0, 1, 0};  // world space: the second row of the view rotation

    FireCorner operator()(const SpriteQuadIn& in) const {
        const glm::vec3 normal = glm::normalize(eye - in.centre);
        const glm::vec3 right = glm::normalize(glm::cross(cameraUp, normal));
        const glm::vec3 up = glm::cross(normal, right);
        const glm::vec3 world = in.centre + in.size * (in.corner.x * right + in.corner.y * up);
        return {viewProj * glm::vec4(world, 1.0f), spriteTexCoord(in.corner), in.tint};
    }
};

// ---- Billboards that turn about an axis, or not at all -----------------------------------------------

// A corner of a billboard anchored at `base` and turning about the unit `axis`: corner (x, y) with
// x in [−1, 1] across and y in [0, 1] up the axis is base + x·halfWidth·right + y·height·axis, where
// right = axis × (eye − base), normalised, so the quad's normal right × axis points to the eye in the
// plane normal to the axis. When the eye is on the axis line, any right normal to the axis will do.
inline glm::vec3 axisBillboardCorner(glm::vec3 base, glm::vec3 axis, glm::vec3 eye, float half_width,
                                     float height, glm::vec2 corner) {
    glm::vec3 side = glm::cross(axis, eye - base);
    const float length = glm::length(side);
    if (!(length > 1e-12f))
        side = glm::cross(axis, std::abs(axis.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
    const glm::vec3 right = glm::normalize(side);
    return base + (corner.x * half_width) * right + (corner.y * height) * axis;
}

// One corner of an axis billboard (a tree): six a tree, corners (±1, 0 or 1).
struct AxisBillboardIn {
    glm::vec3 base;    // world space: the foot of the trunk
    glm::vec2 extent;  // world units: half-width, height
    glm::vec4 colour;  // tint
    glm::vec2 corner;  // x in {−1, 1}, y in {0, 1}
    RASTER_INPUT_SIGNATURE(AxisBillboardIn, RASTER_INPUT(base, "POSITION", 0),
                           RASTER_INPUT(extent, "SIZE", 0), RASTER_INPUT(colour, "COLOR", 0),
                           RASTER_INPUT(corner, "TEXCOORD", 0))
};

// Texture coordinates of an axis billboard: u across, v = 0 at the top (y = 1).
inline glm::vec2 axisBillboardTexCoord(glm::vec2 corner) {
    return {0.5f * (corner.x + 1.0f), 1.0f - corner.y};
}

struct VsAxisBillboard {
    glm::mat4 viewProj{1.0f};
    glm::vec3 eye{0.0f};
    glm::vec3 axis{0, 1, 0};  // unit, world space

    FireCorner operator()(const AxisBillboardIn& in) const {
        const glm::vec3 world = axisBillboardCorner(in.base, axis, eye, in.extent.x, in.extent.y, in.corner);
        return {viewProj * glm::vec4(world, 1.0f), axisBillboardTexCoord(in.corner), in.colour};
    }
};

// A vertex of a quad fixed in the world: static billboards, billboard clouds, the ground.
struct StaticBillboardIn {
    glm::vec3 position;  // world space
    glm::vec2 tex;
    glm::vec4 colour;
    RASTER_INPUT_SIGNATURE(StaticBillboardIn, RASTER_INPUT(position, "POSITION", 0),
                           RASTER_INPUT(tex, "TEXCOORD", 0), RASTER_INPUT(colour, "COLOR", 0))
};

struct VsStaticBillboard {
    glm::mat4 viewProj{1.0f};
    FireCorner operator()(const StaticBillboardIn& in) const {
        return {viewProj * glm::vec4(in.position, 1.0f), in.tex, in.colour};
    }
};

// Appends a quad fixed in the world, centred at `centre` with half-extents along `right` and `up`
// (world vectors), as two triangles (six vertices); v = 0 at centre + up.
inline void appendStaticBillboard(std::vector<StaticBillboardIn>& out, glm::vec3 centre, glm::vec3 right,
                                  glm::vec3 up, glm::vec4 colour) {
    for (const glm::vec2 c : kSpriteCorners)
        out.push_back({centre + c.x * right + c.y * up, spriteTexCoord(c), colour});
}

// A billboard cloud: `quads` static billboards standing on `base`, crossed about the vertical through
// it at k·180°/quads (k = 0..quads−1), each half_width wide either side and `height` tall, plus
// `turn` radians about the vertical for the whole cloud. It approximates one object from every side
// of the horizon without turning: three quads at 60° are the classic shrub.
inline std::vector<StaticBillboardIn> billboardCloud(glm::vec3 base, float half_width, float height,
                                                     int quads, float turn, glm::vec4 colour) {
    std::vector<StaticBillboardIn> out;
    const glm::vec3 up(0.0f, 0.5f * height, 0.0f);
    for (int k = 0; k < quads; ++k) {
        const float angle = turn + float(k) * 3.14159265f / float(quads);
        const glm::vec3 right(half_width * std::cos(angle), 0.0f, half_width * std::sin(angle));
        appendStaticBillboard(out, base + up, right, up, colour);
    }
    return out;
}

// Alpha testing: the texel times the tint, discarded where its alpha is below `threshold`; the rest is
// written opaque (alpha 1), so the picture needs depth writes but no sorting and has no partial pixels.
// Point sampling keeps every written colour one of the texture's (the forest's test counts on it).
struct PsAlphaTested {
    using Input = FireCorner;
    const Texture2D* texture = nullptr;
    SamplerState sampler = SamplerState::point(AddressMode::Clamp);
    float threshold = 0.5f;

    std::optional<glm::vec4> operator()(const FireCorner& in) const {
        const glm::vec4 texel = texture->Sample(sampler, in.tex);
        if (texel.w * in.colour.w < threshold) return std::nullopt;
        return glm::vec4(texel.x * in.colour.x, texel.y * in.colour.y, texel.z * in.colour.z, 1.0f);
    }
};

// ---- Input layouts: the D3D11_INPUT_ELEMENT_DESC arrays of the structs above, offsets by offsetof ----

inline InputLayout spriteQuadLayout() { return sprite_lab::spriteCornerLayout(); }

// (c)'s: one FireParticleIn a sprite.
inline InputLayout spritePointLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(FireParticleIn, position))},
        {"SIZE", 0, Format::R32_FLOAT, 0, uint32_t(offsetof(FireParticleIn, size))},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(FireParticleIn, colour))}};
    return InputLayout(elements);
}

inline InputLayout axisBillboardLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(AxisBillboardIn, base))},
        {"SIZE", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(AxisBillboardIn, extent))},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(AxisBillboardIn, colour))},
        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(AxisBillboardIn, corner))}};
    return InputLayout(elements);
}

inline InputLayout staticBillboardLayout() {
    const InputElementDesc elements[] = {
        {"POSITION", 0, Format::R32G32B32_FLOAT, 0, uint32_t(offsetof(StaticBillboardIn, position))},
        {"TEXCOORD", 0, Format::R32G32_FLOAT, 0, uint32_t(offsetof(StaticBillboardIn, tex))},
        {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, uint32_t(offsetof(StaticBillboardIn, colour))}};
    return InputLayout(elements);
}

}  // namespace raster::shaders
