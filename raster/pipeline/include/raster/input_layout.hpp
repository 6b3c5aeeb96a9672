// The input layout: how the input assembler turns vertex-buffer bytes into the vertex shader's
// input struct, as D3D11_INPUT_ELEMENT_DESC describes it.
//
// The layout describes memory (which slot, which byte offset, which format); the vertex shader's
// input struct describes what the shader wants (its "input signature"), declared with
// RASTER_INPUT_SIGNATURE. Elements are matched by semantic name (case-insensitive, as HLSL) and
// index. As in D3D11, an element may carry fewer components than the shader field reads: the
// missing ones read as (0, 0, 0, 1), so a float3 position feeds a float4 field with w = 1; extra
// components are ignored. A field with no element, a duplicate semantic, an element that does not
// fit its stride, or a vertex buffer missing from a slot the layout uses is an Error(LayoutMismatch)
// naming the semantic, slot and field, raised before the first draw writes anything.
//
//   struct ParticleIn {
//       glm::vec3 position;
//       RASTER_INPUT_SIGNATURE(ParticleIn, RASTER_INPUT(position, "POSITION", 0))
//   };
//   const raster::InputElementDesc desc[] = {
//       {"POSITION", 0, raster::Format::R32G32B32_FLOAT, 0, offsetof(Particle, position),
//        raster::InputClassification::PerVertexData, 0}};
//   raster::InputLayout layout(desc);
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/buffer.hpp"
#include "raster/format.hpp"

namespace raster {

enum class InputClassification : uint8_t { PerVertexData, PerInstanceData };

// D3D11_APPEND_ALIGNED_ELEMENT: place the element right after the previous one in its slot.
constexpr uint32_t kAppendAlignedElement = 0xFFFFFFFFu;
constexpr uint32_t kMaxInputSlots = 16;
// D3D11_REQ_MULTI_ELEMENT_STRUCTURE_SIZE_IN_BYTES: every element ends within this many bytes of
// its vertex (offset + size, computed in 64 bits, so that no offset near 2^32 wraps around).
constexpr uint64_t kMaxVertexStride = 2048;

struct InputElementDesc {
    const char* semanticName = "";
    uint32_t semanticIndex = 0;
    Format format = Format::Unknown;
    uint32_t inputSlot = 0;
    uint32_t alignedByteOffset = kAppendAlignedElement;
    InputClassification inputSlotClass = InputClassification::PerVertexData;
    uint32_t instanceDataStepRate = 0;  // per-instance elements advance every this many instances
};

// One field of a vertex shader's input struct: float, vec2, vec3 or vec4 at a byte offset.
struct ShaderInputField {
    const char* semanticName;
    uint32_t semanticIndex;
    uint32_t components;
    uint32_t offset;
    const char* memberName;
};

template <class T>
inline constexpr uint32_t kComponentsOf = 0;
template <>
inline constexpr uint32_t kComponentsOf<float> = 1;
template <>
inline constexpr uint32_t kComponentsOf<glm::vec2> = 2;
template <>
inline constexpr uint32_t kComponentsOf<glm::vec3> = 3;
template <>
inline constexpr uint32_t kComponentsOf<glm::vec4> = 4;

// A resolved element: where it is read from and where it goes in the shader's struct.
struct InputFetch {
    uint32_t slot = 0;
    uint32_t srcOffset = 0;       // bytes into the slot's element
    Format format = Format::Unknown;
    uint32_t dstOffset = 0;       // bytes into the shader's input struct
    uint32_t dstComponents = 0;   // floats the field holds
    bool perInstance = false;
    uint32_t stepRate = 0;
    // For messages: the element's semantic and the shader's field it feeds, as the signature names
    // them (RASTER_INPUT's string literals, which outlive any draw).
    const char* semanticName = "";
    uint32_t semanticIndex = 0;
    const char* fieldName = "";
};

class InputLayout {
public:
    InputLayout() = default;
    // Checks every element (known format, slot < kMaxInputSlots, step rate only per instance, no
    // duplicate semantic, offset a multiple of 4 and offset + size ≤ kMaxVertexStride) and resolves
    // kAppendAlignedElement. Throws Error(LayoutMismatch).
    explicit InputLayout(std::span<const InputElementDesc> elements);
    template <size_t N>
    explicit InputLayout(const InputElementDesc (&elements)[N])
        : InputLayout(std::span<const InputElementDesc>(elements, N)) {}

    struct Element {
        std::string semanticName;
        uint32_t semanticIndex;
        Format format;
        uint32_t inputSlot;
        uint32_t byteOffset;  // resolved
        InputClassification inputSlotClass;
        uint32_t instanceDataStepRate;
    };
    const std::vector<Element>& elements() const { return elements_; }

    // Matches the layout against a shader's input signature (see above) and returns the fetch
    // program, or throws Error(LayoutMismatch) naming what does not match. `shaderName` names the
    // input struct in messages.
    std::vector<InputFetch> bind(std::span<const ShaderInputField> signature, size_t structSize,
                                 const char* shaderName) const;

private:
    std::vector<Element> elements_;
};

// Reads one vertex (buffer index `vertex`, SV_InstanceID `instance` counted from 0 within the draw;
// per-instance data is element startInstance + instance / stepRate, or startInstance for rate 0) into the shader's input
// struct at `dst` (zero-filled, then (0,0,0,1) defaults for components the element lacks).
// Bounds were checked per draw by checkVertexBuffers.
void fetchVertex(std::span<const InputFetch> program, std::span<const VertexBuffer* const> slots,
                 uint32_t vertex, uint32_t instance, uint32_t startInstance, std::byte* dst);

// Throws Error(OutOfRange) or Error(LayoutMismatch) unless every slot the program reads is bound,
// its stride holds the element (the message names the element's semantic, offset, format and the
// field it feeds: a layout copied from another struct overruns it), and vertex indices up to maxVertex and instance IDs up to
// maxInstance stay inside the buffers.
void checkVertexBuffers(std::span<const InputFetch> program, std::span<const VertexBuffer* const> slots,
                        uint64_t maxVertex, uint64_t maxInstance, uint32_t startInstance);

}  // namespace raster

// Declares a vertex shader input struct's signature, inside the struct:
//   RASTER_INPUT_SIGNATURE(MyIn, RASTER_INPUT(position, "POSITION", 0), RASTER_INPUT(uv, "TEXCOORD", 0))
#define RASTER_INPUT(member, semantic, index)                                                         \
    ::raster::ShaderInputField {                                                                      \
        semantic, index, ::raster::kComponentsOf<decltype(Self_::member)>, uint32_t(offsetof(Self_, member)), \
            #member                                                                                   \
    }
#define RASTER_INPUT_SIGNATURE(Struct, ...)          \
    static auto inputSignature() {                   \
        using Self_ = Struct;                        \
        return std::array{__VA_ARGS__};              \
    }
