// The teaching pipeline's draws (raster/teaching_pipeline.hpp), compiled once: the template pipeline
// instantiated for the function-pointer shaders, through the generic depth and colour policies only
// (the same bits as the specialised ones; 6 instantiations of the tile loop per geometry-shader kind).
// These instantiations of Context::execute exist in this file only: nothing else draws with the
// Teaching* shader types directly (lab files reach them through executeTeaching).
#define RASTER_DRAWS_GENERIC_ONLY 1
#include "raster/pipeline_impl.hpp"
#include "raster/teaching_pipeline.hpp"

namespace raster {

namespace {
// The lab's pixel shader with the context's coverage test (if any) for the fill paths to find.
TeachingPixelShader withCoverage(const TeachingPixelShader& ps, CoverageTest test, const Viewport& viewport,
                                 const RasterizerState& rs) {
    TeachingPixelShader out = ps;
    out.coverage = {test, ViewportTransform(viewport), rs.frontCounterClockwise};
    return out;
}
}  // namespace

void Context::executeTeaching(const TeachingVertexShader& vs, const TeachingPixelShader& ps,
                              const DrawCall& call) {
    execute(vs, NoGeometryShader{}, withCoverage(ps, coverage_test_, viewport_, rasterizer_), call);
}

void Context::executeTeaching(const TeachingVertexShader& vs, const TeachingPointGeometryShader& gs,
                              const TeachingPixelShader& ps, const DrawCall& call) {
    execute(vs, gs, withCoverage(ps, coverage_test_, viewport_, rasterizer_), call);
}

void Context::executeTeaching(const TeachingVertexShader& vs, const TeachingTriangleGeometryShader& gs,
                              const TeachingPixelShader& ps, const DrawCall& call) {
    execute(vs, gs, withCoverage(ps, coverage_test_, viewport_, rasterizer_), call);
}

}  // namespace raster
