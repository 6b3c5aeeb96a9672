#include "raster/input_layout.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "raster/check.hpp"

namespace raster {
namespace {

bool sameSemantic(const std::string& a, const char* b) {
    if (a.size() != std::strlen(b)) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::toupper(uint8_t(a[i])) != std::toupper(uint8_t(b[i]))) return false;
    return true;
}

std::string semanticLabel(const std::string& name, uint32_t index) { return name + std::to_string(index); }

bool isVertexFormat(Format f) {
    switch (f) {
        case Format::R32_FLOAT:
        case Format::R32G32_FLOAT:
        case Format::R32G32B32_FLOAT:
        case Format::R32G32B32A32_FLOAT:
        case Format::R8G8B8A8_UNORM: return true;
        default: return false;
    }
}

}  // namespace

InputLayout::InputLayout(std::span<const InputElementDesc> elements) {
    uint64_t next_offset[kMaxInputSlots] = {};
    for (size_t i = 0; i < elements.size(); ++i) {
        const InputElementDesc& d = elements[i];
        const std::string where = "input element " + std::to_string(i) + " (" +
                                  semanticLabel(d.semanticName ? d.semanticName : "", d.semanticIndex) + ")";
        RASTER_REQUIRE(d.semanticName && *d.semanticName, LayoutMismatch,
                       "input element " + std::to_string(i) + " has no semantic name");
        RASTER_REQUIRE(isVertexFormat(d.format), LayoutMismatch,
                       where + ": format " + std::string(formatName(d.format)) + " is not a vertex format");
        RASTER_REQUIRE(d.inputSlot < kMaxInputSlots, LayoutMismatch,
                       where + ": input slot " + std::to_string(d.inputSlot) + " is not below " +
                           std::to_string(kMaxInputSlots));
        RASTER_REQUIRE(d.inputSlotClass == InputClassification::PerInstanceData || d.instanceDataStepRate == 0,
                       LayoutMismatch, where + ": a per-vertex element must have instanceDataStepRate 0");
        // 64-bit: an offset near 2^32 plus the element's size must not wrap around below the limit.
        const uint64_t offset = d.alignedByteOffset == kAppendAlignedElement ? next_offset[d.inputSlot]
                                                                             : d.alignedByteOffset;
        RASTER_REQUIRE(offset % 4 == 0, LayoutMismatch,
                       where + ": byte offset " + std::to_string(offset) + " is not a multiple of 4");
        RASTER_REQUIRE(offset + formatSize(d.format) <= kMaxVertexStride, LayoutMismatch,
                       where + ": byte offset " + std::to_string(offset) + " + " +
                           std::to_string(formatSize(d.format)) + " bytes of " + std::string(formatName(d.format)) +
                           " ends past the largest vertex, " + std::to_string(kMaxVertexStride) + " bytes");
        for (const Element& e : elements_) {
            RASTER_REQUIRE(!sameSemantic(e.semanticName, d.semanticName) || e.semanticIndex != d.semanticIndex,
                           LayoutMismatch, where + " repeats a semantic already in the layout");
            if (e.inputSlot == d.inputSlot) {
                RASTER_REQUIRE(e.inputSlotClass == d.inputSlotClass, LayoutMismatch,
                               where + " mixes per-vertex and per-instance data in slot " +
                                   std::to_string(d.inputSlot));
            }
        }
        next_offset[d.inputSlot] = offset + formatSize(d.format);
        elements_.push_back({d.semanticName, d.semanticIndex, d.format, d.inputSlot, uint32_t(offset),
                             d.inputSlotClass, d.instanceDataStepRate});
    }
}

std::vector<InputFetch> InputLayout::bind(std::span<const ShaderInputField> signature, size_t structSize,
                                          const char* shaderName) const {
    std::vector<InputFetch> program;
    for (const ShaderInputField& f : signature) {
        const std::string field = std::string(shaderName) + "::" + f.memberName + " (" +
                                  semanticLabel(f.semanticName, f.semanticIndex) + ")";
        RASTER_REQUIRE(f.components >= 1 && f.components <= 4, LayoutMismatch,
                       field + " is not a float, vec2, vec3 or vec4");
        RASTER_REQUIRE(uint64_t(f.offset) + 4 * f.components <= structSize, LayoutMismatch,
                       field + " lies outside its struct");
        auto it = std::find_if(elements_.begin(), elements_.end(), [&](const Element& e) {
            return sameSemantic(e.semanticName, f.semanticName) && e.semanticIndex == f.semanticIndex;
        });
        if (it == elements_.end()) {
            std::string have;
            for (const Element& e : elements_) have += (have.empty() ? "" : ", ") + semanticLabel(e.semanticName, e.semanticIndex);
            throw Error(ErrorCode::LayoutMismatch, "vertex shader input " + field +
                                                       " has no element in the input layout (it has: " +
                                                       (have.empty() ? "nothing" : have) + ")");
        }
        for (const InputFetch& p : program) {
            const bool overlap = f.offset < p.dstOffset + 4 * p.dstComponents && p.dstOffset < f.offset + 4 * f.components;
            RASTER_REQUIRE(!overlap, LayoutMismatch, field + " overlaps another field of the signature");
        }
        program.push_back({it->inputSlot, it->byteOffset, it->format, f.offset, f.components,
                           it->inputSlotClass == InputClassification::PerInstanceData, it->instanceDataStepRate,
                           f.semanticName, f.semanticIndex, f.memberName});
    }
    return program;
}

void checkVertexBuffers(std::span<const InputFetch> program, std::span<const VertexBuffer* const> slots,
                        uint64_t maxVertex, uint64_t maxInstance, uint32_t startInstance) {
    for (const InputFetch& p : program) {
        const std::string where = "input slot " + std::to_string(p.slot);
        RASTER_REQUIRE(p.slot < slots.size() && slots[p.slot] != nullptr, LayoutMismatch,
                       where + " is read by the input layout but no vertex buffer is bound to it");
        const VertexBuffer& vb = *slots[p.slot];
        // A layout written for another struct (another field order, a copied offset) reads past the
        // vertex: name the element and the field it feeds, so that the culprit is the first word read.
        const uint64_t end = uint64_t(p.srcOffset) + formatSize(p.format);
        RASTER_REQUIRE(end <= vb.stride(), LayoutMismatch,
                       where + ": element " + semanticLabel(p.semanticName, p.semanticIndex) + " (feeding `" +
                           p.fieldName + "`) at byte " + std::to_string(p.srcOffset) + " + " +
                           std::to_string(formatSize(p.format)) + " bytes of " + std::string(formatName(p.format)) +
                           " ends at byte " + std::to_string(end) + ", which does not fit the buffer's stride of " +
                           std::to_string(vb.stride()) + " bytes (the size of its vertex struct): check the "
                           "element's AlignedByteOffset (offsetof) and Format");
        const uint64_t last =
            p.perInstance ? startInstance + (p.stepRate == 0 ? 0 : maxInstance / p.stepRate) : maxVertex;
        RASTER_REQUIRE(last < vb.elementCount(), OutOfRange,
                       where + ": the draw reads " + (p.perInstance ? "instance element " : "vertex ") +
                           std::to_string(last) + " but the buffer holds " + std::to_string(vb.elementCount()));
    }
}

void fetchVertex(std::span<const InputFetch> program, std::span<const VertexBuffer* const> slots,
                 uint32_t vertex, uint32_t instance, uint32_t startInstance, std::byte* dst) {
    for (const InputFetch& p : program) {
        const VertexBuffer& vb = *slots[p.slot];
        const uint64_t element =
            p.perInstance ? uint64_t(startInstance) + (p.stepRate == 0 ? 0 : instance / p.stepRate) : vertex;
        const std::byte* src = vb.data() + element * vb.stride() + p.srcOffset;
        float v[4] = {0, 0, 0, 1};
        if (p.format == Format::R8G8B8A8_UNORM) {
            for (int c = 0; c < 4; ++c) v[c] = unorm8ToFloat(uint8_t(src[c]));
        } else {
            std::memcpy(v, src, formatSize(p.format));
        }
        std::memcpy(dst + p.dstOffset, v, 4 * p.dstComponents);
    }
}

}  // namespace raster
