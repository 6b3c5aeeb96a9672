// Pipeline statistics, counted as D3D11_QUERY_DATA_PIPELINE_STATISTICS counts them, plus what the
// pipeline skipped and why. Kept per draw and summed per frame by the Context; counting costs
// a few integer adds per primitive and per quad, never a lock or an atomic.
#pragma once

#include <cstdint>
#include <string>

namespace raster {

struct PipelineStatistics {
    // D3D11_QUERY_DATA_PIPELINE_STATISTICS
    uint64_t iaVertices = 0;     // vertices read by the input assembler (indices read, cuts included)
    uint64_t iaPrimitives = 0;   // primitives assembled
    uint64_t vsInvocations = 0;  // vertex shader runs (once per distinct vertex of an instance)
    uint64_t gsInvocations = 0;
    uint64_t gsPrimitives = 0;   // primitives the geometry shader emitted
    uint64_t cInvocations = 0;   // primitives sent to the clipper
    uint64_t cPrimitives = 0;    // primitives leaving the clipper (a clipped triangle may become several)
    uint64_t psInvocations = 0;  // pixel shader runs for covered pixels (helpers and replays not counted)

    // What was skipped, and why.
    uint64_t primitivesNonFinite = 0;     // NaN/Inf position: dropped
    uint64_t primitivesOutside = 0;       // wholly outside the view volume: rejected before setup
    uint64_t primitivesClipped = 0;       // crossed a clip plane (near, far or guard band) and were cut
    uint64_t primitivesCulled = 0;        // back- or front-face culled
    uint64_t primitivesDegenerate = 0;    // zero area after snapping to 16.8 fixed point
    uint64_t primitivesNoPixels = 0;      // set up but their box holds no pixel centre in the viewport
    uint64_t rectanglesRecognized = 0;    // two-triangle strips drawn as one screen rectangle (billboards)
    uint64_t tilesBinned = 0;             // (primitive, tile) pairs the binner produced
    uint64_t tilesRejected = 0;           // tiles in a primitive's box rejected by its edge functions
    uint64_t tilesOccluded = 0;           // (primitive, tile) pairs skipped whole: the primitive's nearest
                                          // depth fails the test against the tile's farthest stored depth
    uint64_t fragmentsEarlyDepthKilled = 0;  // failed the depth test before the pixel shader ran
    uint64_t fragmentsLateDepthKilled = 0;   // failed the depth test after it (reference mode only)
    uint64_t fragmentsDiscarded = 0;      // the pixel shader returned std::nullopt
    uint64_t fragmentsBlendNoOp = 0;      // blend could not change the pixel (the eight-wide merge
                                          // may store it unchanged with its block's other pixels)
    uint64_t fragmentsBlendSaturated = 0;   // passed the depth test, but their 4×2 block was already at
                                            // the blend's ceiling (additive blend: every byte 255), which
                                            // no fragment can change: never shaded (eight-wide paths)
    uint64_t fragmentsTransparentSkipped = 0;  // passed the depth test, but the shader's output there
                                               // is known to be transparent (its texture's alpha is 0
                                               // in the whole footprint) under a blend that adds
                                               // nothing for it: never shaded (billboards, transparency.hpp)
    uint64_t fragmentsOverdrawSkipped = 0;  // passed the depth test, but a later fragment of the same
                                          // opaque draw replaced them before they were shaded: never
                                          // shaded (deferred shading, see Context::renderTiles)
    uint64_t helperInvocations = 0;       // pixel shader runs for quad helper lanes
    uint64_t derivativeReplays = 0;       // extra pixel shader runs to answer ddx/ddy
    uint64_t sortsAvoided = 0;            // draws whose blend is order-independent: no sort needed
    uint64_t drawsSpecialised = 0;        // draws whose tile loop had their depth and colour state
                                          // folded in (specialised_states.hpp); the others read the
                                          // state per fragment (traced, plain, reference or a state
                                          // the pixel shader is not specialised for): the same bits

    PipelineStatistics& operator+=(const PipelineStatistics& o);
    bool operator==(const PipelineStatistics&) const = default;
    // One "name value" line each, for `raster trace --stats` and the viewer.
    std::string toString() const;
};

}  // namespace raster
