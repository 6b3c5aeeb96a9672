// Draws through the teaching pipeline (raster/teaching_pipeline.hpp): include this instead of
// raster/pipeline_impl.hpp, and every Context::draw in the file runs the library's one compiled
// pipeline with this file's shaders seen through function pointers. raster/lab.hpp includes it, so
// a lab's file compiles its own shaders and nothing of the pipeline (labs/README.md: the lab loop).
//
// A file includes one of the two: each defines Context::execute.
#pragma once

#ifdef RASTER_PIPELINE_IMPL_INCLUDED
#error "raster/teaching_draw.hpp and raster/pipeline_impl.hpp define the same draws: include one of them"
#endif
#define RASTER_TEACHING_DRAW_INCLUDED 1

#include <type_traits>

#include "raster/pipeline.hpp"
#include "raster/teaching_pipeline.hpp"

namespace raster {

template <VertexShader VS, GeometryShader GS, PixelShader PS>
void Context::execute(const VS& vs, const GS& gs, const PS& ps, const DrawCall& call) {
    const TeachingVertexShader teaching_vs = teachingVertexShader(vs);
    const TeachingPixelShader teaching_ps = teachingPixelShader(ps);
    if constexpr (std::is_same_v<GS, NoGeometryShader>)
        executeTeaching(teaching_vs, teaching_ps, call);
    else
        executeTeaching(teaching_vs, teachingGeometryShader(gs), teaching_ps, call);
}

}  // namespace raster
