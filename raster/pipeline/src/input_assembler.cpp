#include "raster/stages/1_input_assembler.hpp"

#include <unordered_map>

#include "raster/check.hpp"

namespace raster {

PrimitiveKind primitiveKindOf(Topology topology) {
    switch (topology) {
        case Topology::PointList: return PrimitiveKind::Point;
        case Topology::LineList:
        case Topology::LineStrip: return PrimitiveKind::Line;
        case Topology::TriangleList:
        case Topology::TriangleStrip: return PrimitiveKind::Triangle;
        case Topology::Undefined:
            throw Error(ErrorCode::InvalidState,
                        "primitive topology is undefined: call setPrimitiveTopology before drawing");
    }
    throw Error(ErrorCode::InvalidState,
                "primitive topology has the invalid value " + std::to_string(int(topology)) +
                    " (not a Topology enumerator)");
}

namespace {

// Splits the vertex sequence into strips (at cuts) and forms the topology's primitives.
void formPrimitives(Topology topology, const std::vector<uint32_t>& sequence, const std::vector<bool>& cut,
                    std::vector<uint32_t>& out) {
    const size_t n = sequence.size();
    size_t strip_begin = 0;
    for (size_t end = 0; end <= n; ++end) {
        if (end < n && !cut[end]) continue;
        const uint32_t* s = sequence.data() + strip_begin;
        const size_t len = end - strip_begin;
        switch (topology) {
            case Topology::PointList:
                for (size_t i = 0; i < len; ++i) out.push_back(s[i]);
                break;
            case Topology::LineList:
                for (size_t i = 0; i + 1 < len; i += 2) out.insert(out.end(), {s[i], s[i + 1]});
                break;
            case Topology::LineStrip:
                for (size_t i = 0; i + 1 < len; ++i) out.insert(out.end(), {s[i], s[i + 1]});
                break;
            case Topology::TriangleList:
                for (size_t i = 0; i + 2 < len; i += 3) out.insert(out.end(), {s[i], s[i + 1], s[i + 2]});
                break;
            case Topology::TriangleStrip:
                for (size_t i = 0; i + 2 < len; ++i) {
                    if (i % 2 == 0)
                        out.insert(out.end(), {s[i], s[i + 1], s[i + 2]});
                    else
                        out.insert(out.end(), {s[i], s[i + 2], s[i + 1]});
                }
                break;
            case Topology::Undefined: break;
        }
        strip_begin = end;
    }
}

}  // namespace

AssembledDraw assemble(Topology topology, const DrawCall& call, const IndexBuffer* indices) {
    AssembledDraw draw;
    draw.kind = primitiveKindOf(topology);
    draw.indicesRead = call.count;
    std::vector<uint32_t> sequence;  // index into draw.fetch, per vertex read
    std::vector<bool> cut;           // a cut precedes this position (only strips have cuts)
    // Per vertex read: its fetch slot and sequence entry (4 + 4 bytes), up to three primitive
    // references (12), the cut flag; refused before allocating when the machine cannot hold it.
    requireMemory(byteCount(call.count, 21), "the input assembler's arrays for " + std::to_string(call.count) +
                                                 (call.indexed ? " indices" : " vertices"));
    sequence.reserve(call.count);
    if (!call.indexed) {
        RASTER_REQUIRE(uint64_t(call.start) + call.count <= 0xFFFFFFFFull, OutOfRange,
                       "startVertex + vertexCount overflows 32 bits");
        draw.fetch.resize(call.count);
        for (uint32_t i = 0; i < call.count; ++i) {
            draw.fetch[i] = call.start + i;
            sequence.push_back(i);
        }
        cut.assign(call.count, false);
        draw.maxFetch = call.count ? call.start + call.count - 1 : 0;
    } else {
        RASTER_REQUIRE(indices != nullptr, InvalidState, "indexed draw without an index buffer");
        RASTER_REQUIRE(uint64_t(call.start) + call.count <= indices->size(), OutOfRange,
                       "indexed draw reads indices " + std::to_string(call.start) + ".." +
                           std::to_string(uint64_t(call.start) + call.count - 1) + " but the index buffer holds " +
                           std::to_string(indices->size()));
        const bool strip = topology == Topology::LineStrip || topology == Topology::TriangleStrip;
        std::unordered_map<uint32_t, uint32_t> slot_of;
        bool pending_cut = false;
        for (uint32_t i = 0; i < call.count; ++i) {
            const uint32_t index = (*indices)[call.start + i];
            if (strip && index == indices->cutValue()) {
                pending_cut = true;
                continue;
            }
            const int64_t vertex = int64_t(index) + call.baseVertex;
            RASTER_REQUIRE(vertex >= 0 && vertex <= 0xFFFFFFFFll, OutOfRange,
                           "index " + std::to_string(index) + " at position " + std::to_string(call.start + i) +
                               " plus base vertex " + std::to_string(call.baseVertex) + " is out of range");
            auto [it, inserted] = slot_of.try_emplace(uint32_t(vertex), uint32_t(draw.fetch.size()));
            if (inserted) {
                draw.fetch.push_back(uint32_t(vertex));
                draw.maxFetch = std::max(draw.maxFetch, uint32_t(vertex));
            }
            sequence.push_back(it->second);
            cut.push_back(pending_cut);
            pending_cut = false;
        }
    }
    formPrimitives(topology, sequence, cut, draw.primitives);
    return draw;
}

}  // namespace raster
