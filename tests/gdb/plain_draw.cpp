// One small draw through every stage on the plain path (ContextOptions::plain, one thread), built
// without optimisation and with debug information: the program that tests/gdb/plain_steps.py steps in
// gdb, and the one labs/README.md's gdb session uses. It prints the centre pixel, so that a run
// without gdb shows the draw did what the breakpoints see.
#include <cstdio>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"

namespace {

using namespace raster;

struct PlainIn {
    glm::vec3 position;
    glm::vec4 color;
    RASTER_INPUT_SIGNATURE(PlainIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(color, "COLOR", 0))
};
struct PlainVertex {
    glm::vec4 position;
    glm::vec4 color;
};

// Vertex shader: object space is clip space here.
struct VsPlain {
    PlainVertex operator()(const PlainIn& in) const { return {glm::vec4(in.position, 1.0f), in.color}; }
};
// Geometry shader: the triangle as it came.
struct GsPlain {
    void operator()(const Triangle<PlainVertex>& in, TriangleStream<PlainVertex, 3>& stream) const {
        for (int i = 0; i < 3; ++i) stream.Append(in[i]);
    }
};
// Pixel shader: the interpolated colour.
struct PsPlain {
    glm::vec4 operator()(const PlainVertex& in) const { return in.color; }
};

}  // namespace

int main() {
    RenderTarget color(8, 8);
    DepthTarget depth(8, 8);
    color.clear({0, 0, 0.25f, 1});
    depth.clear(1.0f);
    const std::vector<PlainIn> triangle = {{{-0.9f, -0.9f, 0.5f}, {1, 0, 0, 0.5f}},
                                           {{0.0f, 0.9f, 0.5f}, {0, 1, 0, 0.5f}},
                                           {{0.9f, -0.9f, 0.5f}, {0, 0, 1, 0.5f}}};
    const VertexBuffer vb = VertexBuffer::create(triangle);
    const InputElementDesc desc[] = {{"POSITION", 0, Format::R32G32B32_FLOAT, 0, 0},
                                     {"COLOR", 0, Format::R32G32B32A32_FLOAT, 0, 12}};
    const InputLayout layout(desc);

    Context ctx(ContextOptions{.threads = 1, .plain = true});
    ctx.setRenderTargets(&color, &depth);
    ctx.setViewport({0, 0, 8, 8, 0, 1});
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(Topology::TriangleList);
    ctx.setBlendState(BlendState::alphaBlend());
    ctx.setDepthStencilState(DepthStencilState{});
    ctx.draw(VsPlain{}, GsPlain{}, PsPlain{}, 3);

    const glm::vec4 c = color.load(4, 4);
    std::printf("pixel (4, 4): %.3f %.3f %.3f %.3f, depth %.3f\n", c.r, c.g, c.b, c.a, depth.load(4, 4));
    return 0;
}
