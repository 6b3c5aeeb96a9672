// Stage 2, the vertex shader: fetch each distinct vertex through the input layout and run the
// student's functor on it, in parallel over blocks of vertices (each result has its own slot).
#pragma once

#include <cstring>
#include <span>
#include <vector>

#include "raster/input_layout.hpp"
#include "raster/shader.hpp"
#include "raster/stages/1_input_assembler.hpp"
#include "raster/thread_pool.hpp"

namespace raster {

// out[instance * fetch.size() + i] = vs(vertex i of `instance`).
template <class VS>
void runVertexShader(const VS& vs, std::span<const InputFetch> program, std::span<const VertexBuffer* const> slots,
                     const AssembledDraw& draw, const DrawCall& call, ThreadPool& pool,
                     std::vector<VertexShaderOutput<VS>>& out) {
    using In = VertexShaderInput<VS>;
    static_assert(std::is_trivially_copyable_v<In>, "a vertex shader's input struct must be trivially copyable");
    const uint32_t per_instance = uint32_t(draw.fetch.size());
    const uint64_t total = uint64_t(per_instance) * call.instanceCount;
    out.resize(total);
    constexpr uint32_t kBlock = 2048;
    const uint32_t blocks = uint32_t((total + kBlock - 1) / kBlock);
    pool.parallelFor(blocks, [&](uint32_t block, unsigned) {
        const uint64_t end = std::min<uint64_t>(total, uint64_t(block + 1) * kBlock);
        for (uint64_t i = uint64_t(block) * kBlock; i < end; ++i) {
            const uint32_t instance = uint32_t(i / per_instance);
            const uint32_t local = uint32_t(i % per_instance);
            In in;
            std::memset(static_cast<void*>(&in), 0, sizeof in);
            fetchVertex(program, slots, draw.fetch[local], instance, call.startInstance,
                        reinterpret_cast<std::byte*>(&in));
            out[i] = vs(in);
        }
    });
}

}  // namespace raster
