#include "raster/statistics.hpp"

namespace raster {

// clang-format off
#define RASTER_STAT_FIELDS(X)                                                                           \
    X(iaVertices) X(iaPrimitives) X(vsInvocations) X(gsInvocations) X(gsPrimitives) X(cInvocations)    \
    X(cPrimitives) X(psInvocations) X(primitivesNonFinite) X(primitivesOutside) X(primitivesClipped)   \
    X(primitivesCulled) X(primitivesDegenerate) X(primitivesNoPixels) X(rectanglesRecognized)          \
    X(tilesBinned) X(tilesRejected) X(tilesOccluded)                                                   \
    X(fragmentsEarlyDepthKilled) X(fragmentsLateDepthKilled) X(fragmentsDiscarded)                     \
    X(fragmentsBlendNoOp) X(fragmentsBlendSaturated) X(fragmentsTransparentSkipped)                    \
    X(fragmentsOverdrawSkipped)                                                                        \
    X(helperInvocations) X(derivativeReplays) X(sortsAvoided) X(drawsSpecialised)
// clang-format on

PipelineStatistics& PipelineStatistics::operator+=(const PipelineStatistics& o) {
#define RASTER_ADD(f) f += o.f;
    RASTER_STAT_FIELDS(RASTER_ADD)
#undef RASTER_ADD
    return *this;
}

std::string PipelineStatistics::toString() const {
    std::string s;
#define RASTER_LINE(f) s += std::string(#f) + " " + std::to_string(f) + "\n";
    RASTER_STAT_FIELDS(RASTER_LINE)
#undef RASTER_LINE
    return s;
}

}  // namespace raster
