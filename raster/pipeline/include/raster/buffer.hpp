// Buffers: vertex, index and constant buffers, as the input assembler and shaders see them.
//
// A VertexBuffer is bytes with a stride (D3D11: a buffer plus the stride passed to
// IASetVertexBuffers); it remembers the element type it was made from only for error messages.
// An IndexBuffer holds 16- or 32-bit indices (DXGI_FORMAT_R16_UINT / R32_UINT).
// A ConstantBuffer<T> is a typed value a shader functor refers to; update() is the
// Map(WRITE_DISCARD) + memcpy of the lecture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <vector>

#include "raster/check.hpp"

namespace raster {

class VertexBuffer {
public:
    VertexBuffer() = default;

    template <class T>
    static VertexBuffer create(std::span<const T> elements) {
        static_assert(std::is_trivially_copyable_v<T>, "vertex data must be trivially copyable");
        VertexBuffer b;
        b.stride_ = uint32_t(sizeof(T));
        b.type_name_ = typeid(T).name();
        b.allocate<T>(elements.size());
        if (!elements.empty()) std::memcpy(b.bytes_.data(), elements.data(), elements.size_bytes());
        return b;
    }
    template <class T>
    static VertexBuffer create(const std::vector<T>& elements) {
        return create(std::span<const T>(elements));
    }

    // Replaces the contents (same element type and stride), like Map(WRITE_DISCARD) + memcpy.
    template <class T>
    void update(std::span<const T> elements) {
        RASTER_REQUIRE(sizeof(T) == stride_, InvalidArgument,
                       "VertexBuffer::update with elements of " + std::to_string(sizeof(T)) +
                           " bytes into a buffer of stride " + std::to_string(stride_));
        allocate<T>(elements.size());
        if (!elements.empty()) std::memcpy(bytes_.data(), elements.data(), elements.size_bytes());
    }

    uint32_t stride() const { return stride_; }
    size_t byteSize() const { return bytes_.size(); }
    size_t elementCount() const { return stride_ ? bytes_.size() / stride_ : 0; }
    const std::byte* data() const { return bytes_.data(); }
    const char* typeName() const { return type_name_; }

private:
    // Room for `count` elements of T; Error(OutOfMemory) naming the buffer if the machine has none.
    template <class T>
    void allocate(size_t count) {
        allocateOrThrow("a vertex buffer of " + std::to_string(count) + " × " + std::to_string(sizeof(T)) +
                            "-byte " + demangle(typeid(T).name()),
                        byteCount(count, sizeof(T)), [&] { bytes_.resize(count * sizeof(T)); });
    }

    std::vector<std::byte> bytes_;
    uint32_t stride_ = 0;
    const char* type_name_ = "";
};

enum class IndexFormat : uint8_t { Uint16, Uint32 };

class IndexBuffer {
public:
    IndexBuffer() = default;
    static IndexBuffer create(std::span<const uint16_t> indices) {
        IndexBuffer b;
        b.format_ = IndexFormat::Uint16;
        b.indices_.assign(indices.begin(), indices.end());
        return b;
    }
    static IndexBuffer create(std::span<const uint32_t> indices) {
        IndexBuffer b;
        b.format_ = IndexFormat::Uint32;
        b.indices_.assign(indices.begin(), indices.end());
        return b;
    }
    static IndexBuffer create(const std::vector<uint16_t>& i) { return create(std::span<const uint16_t>(i)); }
    static IndexBuffer create(const std::vector<uint32_t>& i) { return create(std::span<const uint32_t>(i)); }

    IndexFormat format() const { return format_; }
    size_t size() const { return indices_.size(); }
    // The strip-cut value of this format (0xFFFF or 0xFFFFFFFF): in a strip it restarts the strip.
    uint32_t cutValue() const { return format_ == IndexFormat::Uint16 ? 0xFFFFu : 0xFFFFFFFFu; }
    uint32_t operator[](size_t i) const { return indices_[i]; }
    const uint32_t* data() const { return indices_.data(); }

private:
    IndexFormat format_ = IndexFormat::Uint32;
    std::vector<uint32_t> indices_;  // widened once; the format is kept for the cut value and messages
};

template <class T>
class ConstantBuffer {
public:
    static_assert(std::is_trivially_copyable_v<T>, "constant buffer contents must be trivially copyable");
    ConstantBuffer() = default;
    explicit ConstantBuffer(const T& value) : value_(value) {}
    void update(const T& value) { value_ = value; }
    const T& operator*() const { return value_; }
    const T* operator->() const { return &value_; }

private:
    T value_{};
};

}  // namespace raster
