// Stage 1, the input assembler: which vertices to fetch and how they form primitives.
//
// Topologies as D3D11: point list, line list/strip, triangle list/strip. In a triangle strip the
// odd triangles swap their last two vertices, (i, i+2, i+1), so that every triangle of the strip
// keeps the winding of the first. In an indexed strip the cut value (0xFFFF for 16-bit indices,
// 0xFFFFFFFF for 32-bit) ends the strip and starts a new one. An indexed draw runs the vertex
// shader once per distinct index (a perfect post-transform cache), in order of first use.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/buffer.hpp"
#include "raster/shader.hpp"

namespace raster {

// One Draw*/DrawIndexed* call's arguments.
struct DrawCall {
    bool indexed = false;
    uint32_t count = 0;          // vertexCount, or indexCount when indexed
    uint32_t start = 0;          // startVertex, or startIndex when indexed
    int32_t baseVertex = 0;      // added to every index
    uint32_t instanceCount = 1;
    uint32_t startInstance = 0;
};

struct AssembledDraw {
    PrimitiveKind kind = PrimitiveKind::Triangle;
    std::vector<uint32_t> fetch;       // buffer vertex index of each distinct vertex of one instance
    std::vector<uint32_t> primitives;  // per primitive, int(kind) indices into `fetch`
    uint32_t primitiveCount() const { return uint32_t(primitives.size() / uint32_t(kind)); }
    uint64_t indicesRead = 0;          // per instance
    uint32_t maxFetch = 0;             // largest buffer vertex index fetched
};

PrimitiveKind primitiveKindOf(Topology topology);

// Builds the vertex and primitive lists of one instance. Throws Error(InvalidState) for an
// undefined topology, Error(OutOfRange) for an index range past the index buffer or an index plus
// base vertex below zero. Vertex-buffer bounds are checked separately (checkVertexBuffers).
AssembledDraw assemble(Topology topology, const DrawCall& call, const IndexBuffer* indices);

}  // namespace raster
