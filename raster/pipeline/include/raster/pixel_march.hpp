// One pixel's ray march, sample by sample, for `raster trace <media scene> --pixel X,Y` and the
// viewer's march plot (Scene::pixelMarch). Plain data: no media or pipeline headers.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace raster {
namespace media {

// What one evaluated sample did, for the trace and the viewer's march plot.
struct MarchSample {
    uint32_t index = 0;
    float s = 0.0f;                    // metres from the eye
    float extinction = 0.0f;           // μ_i, 1/m
    float opticalStep = 0.0f;          // μ_i·Δs
    float transmittance = 1.0f;        // T from the eye to the sample's step, before it
    float shadowTransmittance = 1.0f;  // e^{−τ_l} (1 where μ_i = 0: no shadow ray)
    glm::vec3 added{0.0f};             // the radiance the step added to L
};

}  // namespace media

// A pixel's march: its evaluated samples in order (the others lie in skipped empty space and add
// nothing), the final radiance L (without the background), transmittance T, and the colour the pixel
// shader returns: clamp(L + T·L_bg, 0, 1) where the shader adds the background itself; where it is
// blended over what earlier draws left (`over`: ONE, INV_SRC_ALPHA, alpha 1 − T), its premultiplied
// rgb, and the pixel becomes rgb + T·dst.
struct PixelMarch {
    std::vector<media::MarchSample> samples;
    uint32_t steps = 0;              // N: the march's steps over [t0, t1]
    float t0 = 0.0f, t1 = 0.0f;      // the ray's stretch inside the medium's box, metres (t1 ≤ t0: missed)
    float ds = 0.0f;                 // Δs, metres
    glm::vec3 radiance{0.0f};        // L
    float transmittance = 1.0f;      // T
    glm::vec3 background{0.0f};      // L_bg
    glm::vec3 colour{0.0f};          // clamp(L + T·L_bg, 0, 1), or the premultiplied rgb where `over`
    bool over = false;               // blended over the pixel behind: pixel = colour + T·dst
    uint32_t densityEvaluations = 0;  // view and shadow rays
};

}  // namespace raster
