// Soft particles and off-screen particles: the depth-aware half of the lecture's particles.
//
// Soft particles. A billboard that cuts through opaque geometry shows a hard line where its plane
// enters the surface. The particle's pixel shader reads the scene's depth under the pixel (the
// opaque pass's depth target, bound as a shader resource: DepthTexture) and fades its alpha by how
// far in front of that surface it is, in view-space units:
//
//     fade = saturate((s_scene − s_particle) / fadeDistance)
//
// 0 where the particle touches the surface (or is behind it), 1 from fadeDistance in front of it on.
// s is the view-space depth, the distance along the view direction (−z_view); the particle's is its
// pixel's SV_Position.w (a billboard's clip w is its centre's −z_view), the scene's comes from the
// stored depth d by inverting glm::perspectiveRH_ZO (the scenes' projection, near n, far f):
//
//     d = f/(f − n) · (1 − n/s)   ⇔   s = n·f / (f − d·(f − n))        (DepthLinearizer)
//
// Off-screen particles (Cantlay, "High-Speed, Off-Screen Particles", GPU Gems 3, ch. 23). Smoke is
// low-frequency, so its pixels can be shaded at 1/k of the resolution in each axis (k = 2: a
// quarter of the fill, k = 4: a sixteenth): the opaque pass runs at full resolution; its depth is
// downsampled k×k → 1 (downsampleDepth); the particles are drawn into a low-resolution RGBA32F
// target against that depth, accumulating premultiplied colour and transmittance; the result is
// upsampled bilinearly and composited over the full-resolution image (frame = frame·T + colour).
//
// Which depth a low-resolution texel keeps: the chapter first point-samples one of the k×k depths,
// which lets the depth test hide a particle from every full-resolution pixel of the block when the
// sample happens to be on a near occluder although the others see it, leaving gaps of unsmoked
// background; it then takes the maximum (the farthest) of the block's depths, which is conservative:
// a particle is kept in the low-resolution texel whenever any of its full-resolution pixels would
// see it. The error that remains is on the other side of the occluder's silhouette: particles
// behind the occluder, kept for the block's far pixels, are upsampled over its near pixels too — a
// halo of smoke over the occluder's edge, one to two low-resolution texels wide. DepthDownsample::
// Farthest is that rule and the one the off-screen path uses.
//
// The halo's fix (the chapter's mixed-resolution rendering): find the low-resolution texels at depth
// discontinuities (depthEdgeMask), leave those pixels out of the composite and draw the particles
// again at full resolution on those pixels only, with a stencil-like mask that rejects every other
// pixel before its shader runs (in raster: a full-resolution depth target that is 0 off the edges,
// so the depth test Less fails there, and the scene's depth on them). See docs/SOFT_PARTICLES.md for
// the measurements (the halo's error before and after the fix, run time against error).
#pragma once

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

#include "raster/render_target.hpp"
#include "raster/scenes.hpp"
#include "raster/simd.hpp"

namespace raster {

// A DepthTarget read by a shader: Direct3D 11's R32_FLOAT shader-resource view of a D32 depth
// buffer (R32_TYPELESS). It borrows the target's texels (the target must outlive it and keep its
// size). A depth target may stay bound for the depth test while a shader reads it this way only if
// the draw does not write depth (DepthStencilState::readOnly), as D3D11 requires a read-only view.
class DepthTexture {
  public:
    DepthTexture() = default;
    explicit DepthTexture(const DepthTarget& depth)
        : texels_(depth.data()), width_(int32_t(depth.width())), height_(int32_t(depth.height())) {}

    uint32_t width() const { return uint32_t(width_); }
    uint32_t height() const { return uint32_t(height_); }
    // HLSL Load: texel (x, y), 0 outside the texture (Direct3D 11's out-of-range rule), as is every
    // texel of an empty DepthTexture.
    float load(int x, int y) const {
        if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;
        return texels_[size_t(y) * size_t(width_) + size_t(x)];
    }
    // The texel under a pixel shader's SV_Position x, y (pixel centres, x + ½): texel (⌊x⌋, ⌊y⌋),
    // clamped to the texture (a wide shader's helper lanes may lie past its edge). Scalar and eight or
    // sixteen lanes (simd.hpp) read the same texels. The texture must not be empty.
    float atPixel(float x, float y) const {
        const int32_t ix = std::min(std::max(int32_t(x), 0), width_ - 1);
        const int32_t iy = std::min(std::max(int32_t(y), 0), height_ - 1);
        return texels_[size_t(iy) * size_t(width_) + size_t(ix)];
    }
    Float8 atPixel(Float8 x, Float8 y) const {
        const Int8 ix = min(max(toInt(x), Int8(0)), Int8(width_ - 1));
        const Int8 iy = min(max(toInt(y), Int8(0)), Int8(height_ - 1));
        return gather(texels_, iy * Int8(width_) + ix);
    }
    Float8x2 atPixel(Float8x2 x, Float8x2 y) const {
        return {atPixel(x.h[0], y.h[0]), atPixel(x.h[1], y.h[1])};
    }

  private:
    const float* texels_ = nullptr;
    int32_t width_ = 0, height_ = 0;
};

// Stored depth d ∈ [0, 1] → view-space depth s (world units along the view direction) for
// glm::perspectiveRH_ZO with these planes: s = n·f / (f − d·(f − n)); d = 0 gives n, d = 1 gives f.
struct DepthLinearizer {
    float nearPlane = 0.1f, farPlane = 100.0f;  // the scenes' (sceneProjection)
    template <class T>
    T viewDepth(T d) const {
        return T(nearPlane * farPlane) / (T(farPlane) - d * T(farPlane - nearPlane));
    }
};

// The soft-particle fade, saturate((sceneDepth − particleDepth) · inverseFadeDistance), both depths
// view-space (DepthLinearizer::viewDepth, SV_Position.w): 0 at contact and behind, 1 from
// 1 / inverseFadeDistance in front of the surface on, linear between.
template <class T>
T softFade(T sceneDepth, T particleDepth, float inverseFadeDistance) {
    return min(max((sceneDepth - particleDepth) * T(inverseFadeDistance), T(0.0f)), T(1.0f));
}

// How downsampleDepth reduces a k×k block of depths to one.
enum class DepthDownsample : uint8_t {
    Farthest,  // the maximum: the chapter's rule, never hides a particle any pixel of the block sees
    Nearest,   // the minimum: with Farthest, the depth range of a block (depthEdgeMask)
    Point,     // the block's top-left depth: the chapter's first attempt, gaps at edges
};

// A ⌈w/k⌉ × ⌈h/k⌉ depth target, texel (i, j) reduced from full-resolution pixels [k·i, k·i + k) ×
// [k·j, k·j + k) cut to the target. Error(InvalidArgument) for an empty target or k = 0.
DepthTarget downsampleDepth(const DepthTarget& full, uint32_t factor,
                            DepthDownsample rule = DepthDownsample::Farthest);

// The low-resolution texels at depth discontinuities, one byte each (1: edge), row-major: texel t is
// an edge when, over t and its 8 neighbours, the farthest view depth (of `farthest`) exceeds the
// nearest (of `nearest`) by more than `relativeStep` times the nearest. Both downsampled with the
// same factor. 3×3, so that every texel whose bilinear footprint straddles a discontinuity is in.
std::vector<uint8_t> depthEdgeMask(const DepthTarget& nearest, const DepthTarget& farthest,
                                   const DepthLinearizer& linearizer, float relativeStep);

// For measuring the halo: the full-resolution pixels within `radius` pixels (Chebyshev) of a depth
// discontinuity, one byte each: a pixel whose right or lower neighbour's view depth differs from its
// own by more than `relativeStep` times the nearer is on one, and so is that neighbour.
std::vector<uint8_t> depthEdgeBand(const DepthTarget& depth, const DepthLinearizer& linearizer,
                                   float relativeStep, uint32_t radius);

// How the `smoke` scene draws its particles.
struct OffscreenParticles {
    uint32_t factor = 1;         // 1: at full resolution, into the frame; 2: ½; 4: ¼ (any of 1..16)
    bool edgeFix = false;        // factor > 1: the edge pixels' particles again at full resolution
    float edgeStep = 0.1f;       // depthEdgeMask's relativeStep
    bool soft = true;            // the depth fade (false: hard intersections)
    float fadeDistance = 0.25f;  // world units, > 0
};

// The `smoke` scene drawn this way: makeScene("smoke", o) is makeSmokeScene(o, {}). Its options:
// count, the particle system's slots (unset: 3000; the emission rate keeps about 3/4 of them alive,
// each puff fainter the more there are); time, the clock's start (unset: 8 s); seed; camera. Error(
// InvalidArgument) for a factor outside 1..16 or a fade distance or edge step that is not finite and
// > 0; the other options as makeScene checks them (makeSmokeScene does not).
std::unique_ptr<Scene> makeSmokeScene(const SceneOptions& options, const OffscreenParticles& offscreen);

}  // namespace raster
