// README's "A first program", built against an installed raster: draws the orange triangle and
// prints three pixels as RGBA8 (tests/install_test.sh checks them); exit status 1 if one is not what
// the triangle makes.
#include <cstdint>
#include <cstdio>
#include <raster/pipeline.hpp>
#include <raster/shaders/basic.hpp>
#include <raster/pipeline_impl.hpp>
#include <vector>

int main() {
    raster::RenderTarget color(256, 256);
    raster::DepthTarget depth(256, 256);
    std::vector<glm::vec3> tri = {{-0.5f, -0.5f, 0.5f}, {0.0f, 0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}};
    raster::VertexBuffer vb = raster::VertexBuffer::create(tri);
    const raster::InputElementDesc desc[] = {{"POSITION", 0, raster::Format::R32G32B32_FLOAT, 0, 0}};
    raster::InputLayout layout(desc);

    color.clear({0, 0, 0, 1});
    depth.clear(1.0f);
    raster::Context ctx;
    ctx.setRenderTargets(&color, &depth);
    ctx.setViewport({0, 0, 256, 256, 0, 1});
    ctx.setInputLayout(&layout);
    ctx.setVertexBuffer(0, &vb);
    ctx.setPrimitiveTopology(raster::Topology::TriangleList);
    ctx.draw(raster::shaders::VsTransform{}, raster::shaders::PsConstant{{1, 0.5f, 0, 1}}, 3);

    // The triangle's centre, a pixel above its apex and one below its base (row 0 on top).
    struct Probe {
        uint32_t x, y;
        uint8_t expected[4];
    };
    const Probe probes[] = {
        {128, 128, {255, 128, 0, 255}}, {128, 40, {0, 0, 0, 255}}, {128, 200, {0, 0, 0, 255}}};
    bool all_right = true;
    for (const Probe& probe : probes) {
        const uint8_t* p = color.rgba8() + 4 * (size_t(probe.y) * color.width() + probe.x);
        std::printf("pixel %u,%u: %d %d %d %d\n", probe.x, probe.y, p[0], p[1], p[2], p[3]);
        for (int c = 0; c < 4; ++c) all_right = all_right && p[c] == probe.expected[c];
    }
    return all_right ? 0 : 1;
}
