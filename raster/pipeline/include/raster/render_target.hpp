// Render targets: what the output merger writes. A colour target is R8G8B8A8_UNORM or
// R32G32B32A32_FLOAT; a depth target is D32_FLOAT. Row 0 is the top row of the picture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/format.hpp"

namespace raster {

namespace detail {
// Pixel storage starts on a cache line. Tiles are 64 pixels wide, so a tile's row is 256 bytes of
// colour (RGBA8) or depth (D32) and, from an aligned start and for a width that is a multiple of 16
// pixels (every benchmark's), whole cache lines: two threads that render neighbouring tiles then
// never write the same line. (malloc's 16-byte alignment put every tile edge in a line shared with
// the neighbour; docs/PERFORMANCE.md has the measurement.)
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    static constexpr std::align_val_t kAlignment{64};
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) {}
    T* allocate(size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlignment)); }
    void deallocate(T* p, size_t n) { ::operator delete(p, n * sizeof(T), kAlignment); }
    bool operator==(const CacheLineAllocator&) const = default;
};
template <class T>
using PixelVector = std::vector<T, CacheLineAllocator<T>>;
}  // namespace detail

class RenderTarget {
public:
    RenderTarget() = default;
    // Throws Error(InvalidArgument) for a zero or too large size (each side at most kMaxSize)
    // or a format that is not a colour render-target format, Error(OutOfMemory) if the machine
    // cannot hold it.
    RenderTarget(uint32_t width, uint32_t height, Format format = Format::R8G8B8A8_UNORM);

    static constexpr uint32_t kMaxSize = 16384;  // D3D11_REQ_RENDER_TO_BUFFER_WINDOW_WIDTH

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    Format format() const { return format_; }
    bool empty() const { return width_ == 0; }

    // Every pixel set to `color`, converted by the format's rule (UNORM clamps and rounds).
    void clear(const glm::vec4& color) { clearRows(color, 0, height_); }
    // Rows [firstRow, firstRow + rowCount) only (clipped to the target), as clear() sets them;
    // Context::clearRenderTarget clears bands of rows on its threads with it.
    void clearRows(const glm::vec4& color, uint32_t firstRow, uint32_t rowCount);
    // One pixel as the shader would read it (UNORM -> n/255). Throws Error(OutOfRange) unless
    // x < width and y < height.
    glm::vec4 load(uint32_t x, uint32_t y) const;
    // One pixel written with the format's conversion; the same range check.
    void store(uint32_t x, uint32_t y, const glm::vec4& color);

    // Raw storage, row-major, row 0 on top: 4 bytes a pixel (UNORM) or 4 floats a pixel (FLOAT).
    uint8_t* rgba8() { return bytes_.data(); }
    const uint8_t* rgba8() const { return bytes_.data(); }
    float* rgba32f() { return floats_.data(); }
    const float* rgba32f() const { return floats_.data(); }

    // The picture as 8-bit RGBA (FLOAT targets converted by the UNORM rule).
    std::vector<uint8_t> toRgba8() const;
    // Writes a PNG (8-bit RGBA). Throws Error(BadFile) naming the path if it cannot be written.
    void savePng(const std::string& path) const;

    bool operator==(const RenderTarget& other) const = default;

private:
    uint32_t width_ = 0, height_ = 0;
    Format format_ = Format::Unknown;
    detail::PixelVector<uint8_t> bytes_;
    detail::PixelVector<float> floats_;
};

class DepthTarget {
public:
    DepthTarget() = default;
    // Throws Error(InvalidArgument) for a zero or too large size.
    DepthTarget(uint32_t width, uint32_t height);

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    bool empty() const { return width_ == 0; }

    void clear(float depth) { clearRows(depth, 0, height_); }
    void clearRows(float depth, uint32_t firstRow, uint32_t rowCount);  // as RenderTarget::clearRows
    // One depth value; throws Error(OutOfRange) unless x < width and y < height.
    float load(uint32_t x, uint32_t y) const;
    void store(uint32_t x, uint32_t y, float depth);
    float* data() { return depth_.data(); }
    const float* data() const { return depth_.data(); }

    // Writes depth as a grey PNG (0 black, 1 white) for viewing.
    void savePng(const std::string& path) const;

    bool operator==(const DepthTarget& other) const = default;

private:
    uint32_t width_ = 0, height_ = 0;
    detail::PixelVector<float> depth_;
};

}  // namespace raster
