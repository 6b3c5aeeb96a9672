// Lab: sprites three ways and a billboard about an axis (lecture 11, part 3).
//
// Rows of camera-facing sprites floating over a meadow with firs: (a) classic transforms (red),
// (b) the sprite's own transform (green), (c) opened after projection by the geometry shader (blue),
// and a fourth row where your three methods draw the same sprites into one colour channel each
// (a red, b green, c blue): grey targets where they agree, coloured fringes where one is off. The
// firs are billboards that turn about the vertical only. Everything is alpha tested.
//
// As handed out, this file compiles and runs but draws the sprites lying flat or not at all, the
// firs turned away and every quad's transparent corners black. Fill in the five places marked
// `LAB n`, in order; each one changes the picture:
//   LAB 1  (a): the rotation that turns the sprite's quad to face the camera (classic transforms).
//   LAB 2  (b): the corner's offset, added to the centre in camera space.
//   LAB 3  (c): the geometry shader's four corners, offset in clip space.
//   LAB 4  the firs' right vector: turn about the vertical axis to face the eye.
//   LAB 5  the alpha test: discard the texels that are not opaque enough.
//
//   cmake --build build --target raster_tool && build/bin/raster view sprite-methods
//
// In the viewer, Space plays and pauses the time ('.' and ',' step it), K shows the solution's image
// and J the difference from it; click a pixel for its history. Look at labs/sprite-methods/README.md
// for what each step should show.
#include <optional>

#include "raster/labs/sprite_methods.hpp"

namespace {

using namespace raster;

// The vertex formats (SpriteCornerIn, SpritePointIn, SpritePoint, TreeCornerIn), what every pixel
// shader reads (Corner), spriteTexCoord and the scene that draws your shaders are the lab's scaffolding:
// raster/lecture/include/raster/labs/sprite_methods.hpp.
using sprite_lab::Corner;
using sprite_lab::kCamera;
using sprite_lab::SpriteCornerIn;
using sprite_lab::SpriteMethodsScene;
using sprite_lab::SpritePoint;
using sprite_lab::spriteTexCoord;
using sprite_lab::TreeCornerIn;

// ---- (a) classic transforms ------------------------------------------------------------------------

// The columns are where the quad's x, y and z go: x stays, y to −z, z (its normal) to +y.
const glm::mat3 kLyingFlat(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));

// The sprite's model is a quad in its plane z = 0, facing +z. Its model matrix turns that plane to
// the camera's and moves it to the centre; then the usual view and projection (viewProj = P·V).
struct VsSpriteClassic {
    glm::mat4 view{1.0f};      // V: world to camera
    glm::mat4 viewProj{1.0f};  // P·V

    Corner operator()(const SpriteCornerIn& in) const {
        // LAB 1: turn the quad so that it faces the camera. The view matrix's upper 3×3, R, turns
        // the world to the camera; which rotation of the quad does V then undo? (The slide says "the
        // inverse transpose of the view rotation": work out what that is for a rotation before you
        // trust it.) As handed out the quad is turned to lie flat, facing up: seen from the side.
        const glm::mat3 rotation = kLyingFlat;
        glm::mat4 model(rotation);
        model[3] = glm::vec4(in.centre, 1.0f);
        const glm::vec4 local(in.size * in.corner.x, in.size * in.corner.y, 0.0f, 1.0f);
        return {viewProj * (model * local), spriteTexCoord(in.corner), in.tint};
    }
};

// ---- (b) its own transform -------------------------------------------------------------------------

struct VsSpriteOwn {
    glm::mat4 view{1.0f}, proj{1.0f};

    Corner operator()(const SpriteCornerIn& in) const {
        glm::vec4 corner = view * glm::vec4(in.centre, 1.0f);  // the centre in camera space
        // LAB 2: add the corner's offset, (±size, ±size) from in.size and in.corner, in camera space,
        // where x is the screen's right and y its up. As handed out nothing is added: the six corners
        // sit on the centre, two triangles of no area, and the row is empty.
        return {proj * corner, spriteTexCoord(in.corner), in.tint};
    }
};

// ---- (c) opened after projection ------------------------------------------------------------------

struct GsSprite {
    glm::mat4 viewProj{1.0f}, proj{1.0f};

    void operator()(const Point<SpritePoint>& in, TriangleStream<Corner, 4>& stream) const {
        const SpritePoint& p = in[0];
        const glm::vec4 c = viewProj * p.position;
        // LAB 3: open the sprite after the projection: emit the corners c + (±bx, ±by, 0, 0) as a
        // triangle strip in the lecture's order, (+x, +y) uv (1, 0), (+x, −y) uv (1, 1), (−x, +y)
        // uv (0, 0), (−x, −y) uv (0, 1). What must bx and by be for the quad to be (b)'s, p.size world
        // units wide in camera space? (What does P do to a camera-space offset (x, y, 0, 0)?)
        // As handed out the four corners sit on the centre: nothing is drawn.
        stream.Append({c, {1, 0}, p.tint});
        stream.Append({c, {1, 1}, p.tint});
        stream.Append({c, {0, 0}, p.tint});
        stream.Append({c, {0, 1}, p.tint});
    }
};

// ---- The firs: billboards turning about the vertical ----------------------------------------------

struct VsTree {
    glm::mat4 viewProj{1.0f};
    glm::vec3 eye{0.0f};      // world space
    glm::vec3 axis{0, 1, 0};  // unit, world space: the trunk's direction

    Corner operator()(const TreeCornerIn& in) const {
        // LAB 4: the quad keeps the axis (the trunk stays upright) and turns about it to face the
        // eye: its right vector, of unit length, must be normal to the axis and to the direction
        // from the foot to the eye. (And when the eye is on the axis line?) As handed out it is the
        // world's z axis: seen from the front, each fir is edge-on, a thin sliver.
        const glm::vec3 right(0.0f, 0.0f, 1.0f);
        const glm::vec3 world =
            in.base + (in.corner.x * in.extent.x) * right + (in.corner.y * in.extent.y) * axis;
        return {viewProj * glm::vec4(world, 1.0f),
                {0.5f * (in.corner.x + 1.0f), 1.0f - in.corner.y},
                glm::vec4(1.0f)};
    }
};

// ---- The pixel shader: the alpha test -----------------------------------------------------------

// LAB 5: the alpha test. Return std::nullopt (the fragment is discarded: no colour, no depth) where the
// texel's alpha times the tint's is below one half; write the rest opaque (alpha 1), as now. As handed
// out nothing is discarded: each quad's transparent texels are drawn black and hide what is behind.
std::optional<glm::vec4> alphaTested(glm::vec4 texel, glm::vec4 tint) {
    return glm::vec4(texel.x * tint.x, texel.y * tint.y, texel.z * tint.z, 1.0f);
}

struct PsTextured {
    using Input = Corner;
    const Texture2D* texture = nullptr;
    SamplerState sampler = SamplerState::point(AddressMode::Clamp);
    std::optional<glm::vec4> operator()(const Corner& in) const {
        return alphaTested(texture->Sample(sampler, in.tex), in.tint);
    }
};

// ---- The scene (raster/labs/sprite_methods.hpp) ----------------------------------------------------

using SpritesLab = SpriteMethodsScene<VsSpriteClassic, VsSpriteOwn, GsSprite, VsTree, PsTextured>;

}  // namespace

RASTER_LAB("sprite-methods", "Lab: sprites three ways and a billboard about an axis (lecture 11, part 3)",
           SpritesLab, kCamera)
