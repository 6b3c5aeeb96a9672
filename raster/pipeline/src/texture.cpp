#include "raster/texture.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <limits>

#include "raster/image_io.hpp"

namespace raster {

namespace {

std::string floatText(float f) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(f));
    return text;
}

std::string sizeText(uint32_t width, uint32_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

void requireTextureSize(const std::string& what, uint32_t width, uint32_t height) {
    RASTER_REQUIRE(width > 0 && height > 0 && width <= Texture2D::kMaxSize && height <= Texture2D::kMaxSize,
                   InvalidArgument,
                   what + ": texture size " + sizeText(width, height) + " is not within 1x1 .. " +
                       sizeText(Texture2D::kMaxSize, Texture2D::kMaxSize));
}

// The source texels one destination texel of a box-filtered mip level covers along one axis, and
// the fraction of its footprint each contributes.
struct BoxTaps {
    int count = 0;
    std::array<int, 3> index{};
    std::array<float, 3> weight{};
};

// Destination texel i of m covers source texels [i·n/m, (i+1)·n/m) of n. Measured in units of 1/m
// texel the ends are the integers i·n and (i+1)·n, so the overlaps, and the weights, are exact ratios.
std::vector<BoxTaps> boxTaps(int n, int m) {
    std::vector<BoxTaps> taps(size_t(m), BoxTaps{});
    for (int i = 0; i < m; ++i) {
        const long lo = long(i) * n, hi = long(i + 1) * n;
        for (long k = lo / m; k * m < hi; ++k) {
            const long overlap = std::min(hi, (k + 1) * m) - std::max(lo, k * m);
            if (overlap <= 0) continue;
            BoxTaps& t = taps[size_t(i)];
            // A footprint spans at most n/m ≤ 3 texels and never starts more than 1 − 1/m into one.
            RASTER_CHECK(t.count < 3);
            t.index[size_t(t.count)] = int(k);
            t.weight[size_t(t.count)] = float(double(overlap) / double(n));
            ++t.count;
        }
    }
    return taps;
}

}  // namespace

void validate(const SamplerState& s) {
    const auto filterOk = [](Filter f) { return f == Filter::Point || f == Filter::Linear; };
    const auto addressOk = [](AddressMode a) { return uint8_t(a) <= uint8_t(AddressMode::MirrorOnce); };
    RASTER_REQUIRE(filterOk(s.minFilter), InvalidState,
                   "sampler minFilter " + std::to_string(int(s.minFilter)) + " is not a Filter");
    RASTER_REQUIRE(filterOk(s.magFilter), InvalidState,
                   "sampler magFilter " + std::to_string(int(s.magFilter)) + " is not a Filter");
    RASTER_REQUIRE(filterOk(s.mipFilter), InvalidState,
                   "sampler mipFilter " + std::to_string(int(s.mipFilter)) + " is not a Filter");
    RASTER_REQUIRE(addressOk(s.addressU), InvalidState,
                   "sampler addressU " + std::to_string(int(s.addressU)) + " is not an AddressMode");
    RASTER_REQUIRE(addressOk(s.addressV), InvalidState,
                   "sampler addressV " + std::to_string(int(s.addressV)) + " is not an AddressMode");
    RASTER_REQUIRE(std::isfinite(s.mipLodBias), InvalidState,
                   "sampler mipLodBias " + floatText(s.mipLodBias) + " is not finite");
    RASTER_REQUIRE(!std::isnan(s.minLod), InvalidState, "sampler minLod is NaN");
    RASTER_REQUIRE(!std::isnan(s.maxLod), InvalidState, "sampler maxLod is NaN");
    RASTER_REQUIRE(s.minLod <= s.maxLod, InvalidState,
                   "sampler minLod " + floatText(s.minLod) + " > maxLod " + floatText(s.maxLod));
}

namespace {
// Runs make() and reports a std::bad_alloc as Error(OutOfMemory) naming the texture and its texel
// array (the largest of its allocations; mip levels and sampling tables come on top).
template <class Make>
Texture2D allocateTexture(uint32_t width, uint32_t height, Make&& make) {
    return allocateOrThrow("a " + sizeText(width, height) + " texture's texels (its mip levels and tables besides)",
                           byteCount(uint64_t(width) * height, sizeof(glm::vec4)), make);
}
}  // namespace

Texture2D Texture2D::fromRgba8(uint32_t width, uint32_t height, std::span<const uint8_t> rgba, bool mipmaps) {
    requireTextureSize("Texture2D::fromRgba8", width, height);
    const size_t expected = size_t(width) * height * 4;
    RASTER_REQUIRE(rgba.size() == expected, InvalidArgument,
                   "Texture2D::fromRgba8: " + std::to_string(rgba.size()) + " bytes for a " +
                       sizeText(width, height) + " RGBA8 texture, expected " + std::to_string(expected));
    return allocateTexture(width, height, [&] {
        std::vector<glm::vec4> texels(size_t(width) * height);
        for (size_t k = 0; k < texels.size(); ++k)
            texels[k] = glm::vec4(unorm8ToFloat(rgba[4 * k]), unorm8ToFloat(rgba[4 * k + 1]),
                                  unorm8ToFloat(rgba[4 * k + 2]), unorm8ToFloat(rgba[4 * k + 3]));
        return build(width, height, Format::R8G8B8A8_UNORM, std::move(texels),
                     std::vector<uint8_t>(rgba.begin(), rgba.end()), mipmaps);
    });
}

Texture2D Texture2D::fromRgba32f(uint32_t width, uint32_t height, std::span<const float> rgba, bool mipmaps) {
    requireTextureSize("Texture2D::fromRgba32f", width, height);
    const size_t expected = size_t(width) * height * 4;
    RASTER_REQUIRE(rgba.size() == expected, InvalidArgument,
                   "Texture2D::fromRgba32f: " + std::to_string(rgba.size()) + " floats for a " +
                       sizeText(width, height) + " RGBA32F texture, expected " + std::to_string(expected));
    return allocateTexture(width, height, [&] {
        std::vector<glm::vec4> texels(size_t(width) * height);
        for (size_t k = 0; k < texels.size(); ++k)
            texels[k] = glm::vec4(rgba[4 * k], rgba[4 * k + 1], rgba[4 * k + 2], rgba[4 * k + 3]);
        return build(width, height, Format::R32G32B32A32_FLOAT, std::move(texels), {}, mipmaps);
    });
}

Texture2D Texture2D::fromPng(const std::string& path, Format format, bool mipmaps) {
    RASTER_REQUIRE(format == Format::R8G8B8A8_UNORM || format == Format::R32G32B32A32_FLOAT, InvalidArgument,
                   "Texture2D::fromPng('" + path + "'): " + std::string(formatName(format)) +
                       " is not a texture format");
    const ImageRgba8 image = readImageRgba8(path);
    requireTextureSize("Texture2D::fromPng('" + path + "')", image.width, image.height);
    if (format == Format::R8G8B8A8_UNORM) return fromRgba8(image.width, image.height, image.pixels, mipmaps);
    std::vector<float> rgba(image.pixels.size());
    for (size_t k = 0; k < rgba.size(); ++k) rgba[k] = unorm8ToFloat(image.pixels[k]);
    return fromRgba32f(image.width, image.height, rgba, mipmaps);
}

Texture2D Texture2D::build(uint32_t width, uint32_t height, Format format, std::vector<glm::vec4> texels,
                           std::vector<uint8_t> bytes, bool mipmaps) {
    Texture2D t;
    t.format_ = format;
    t.texels_ = std::move(texels);
    t.bytes_ = std::move(bytes);
    t.levels_.push_back({int(width), int(height), 0});
    if (!mipmaps) {
        t.buildFootprints();
        t.buildAlphaSpans();
        return t;
    }

    const bool unorm = format == Format::R8G8B8A8_UNORM;
    while (t.levels_.back().width > 1 || t.levels_.back().height > 1) {
        const Level src = t.levels_.back();
        const Level dst{std::max(1, src.width >> 1), std::max(1, src.height >> 1), t.texels_.size()};
        const std::vector<BoxTaps> tapsX = boxTaps(src.width, dst.width);
        const std::vector<BoxTaps> tapsY = boxTaps(src.height, dst.height);
        t.texels_.resize(dst.offset + size_t(dst.width) * dst.height);
        if (unorm) t.bytes_.resize(4 * t.texels_.size());
        for (int y = 0; y < dst.height; ++y) {
            const BoxTaps& ty = tapsY[size_t(y)];
            for (int x = 0; x < dst.width; ++x) {
                const BoxTaps& tx = tapsX[size_t(x)];
                glm::vec4 sum(0.0f);
                for (int b = 0; b < ty.count; ++b) {
                    glm::vec4 row(0.0f);
                    for (int a = 0; a < tx.count; ++a)
                        row += t.texel<float>(src, tx.index[size_t(a)], ty.index[size_t(b)]) *
                               tx.weight[size_t(a)];
                    sum += row * ty.weight[size_t(b)];
                }
                const size_t k = dst.offset + size_t(y) * size_t(dst.width) + size_t(x);
                if (unorm) {
                    for (int c = 0; c < 4; ++c) {
                        const uint8_t n = floatToUnorm8(sum[c]);
                        t.bytes_[4 * k + size_t(c)] = n;
                        sum[c] = unorm8ToFloat(n);
                    }
                }
                t.texels_[k] = sum;
            }
        }
        t.levels_.push_back(dst);
    }
    return t;
}

uint32_t Texture2D::width(uint32_t level) const {
    if (levels_.empty() && level == 0) return 0;
    RASTER_REQUIRE(level < levels_.size(), InvalidArgument,
                   "Texture2D::width: level " + std::to_string(level) + " of a texture with " +
                       std::to_string(levels_.size()) + " mip levels");
    return uint32_t(levels_[level].width);
}

uint32_t Texture2D::height(uint32_t level) const {
    if (levels_.empty() && level == 0) return 0;
    RASTER_REQUIRE(level < levels_.size(), InvalidArgument,
                   "Texture2D::height: level " + std::to_string(level) + " of a texture with " +
                       std::to_string(levels_.size()) + " mip levels");
    return uint32_t(levels_[level].height);
}

glm::vec4 Texture2D::load(int x, int y, int level) const {
    if (level < 0 || size_t(level) >= levels_.size()) return glm::vec4(0.0f);
    const Level& l = levels_[size_t(level)];
    if (x < 0 || x >= l.width || y < 0 || y >= l.height) return glm::vec4(0.0f);
    return texel<float>(l, x, y);
}

template <class T>
T Texture2D::lodFromGradients(glm::vec2 ddx, glm::vec2 ddy) const {
    const T w = T(levels_[0].width), h = T(levels_[0].height);
    const T xu = T(ddx.x) * w, xv = T(ddx.y) * h, yu = T(ddy.x) * w, yv = T(ddy.y) * h;
    T rho_x = std::sqrt(xu * xu + xv * xv), rho_y = std::sqrt(yu * yu + yv * yv);
    if (!(rho_x > 0)) rho_x = 0;  // also NaN
    if (!(rho_y > 0)) rho_y = 0;
    const T rho = std::max(rho_x, rho_y);
    // Spelled out rather than trusting log2(0) = −∞ to every libm and to the compiler's flags.
    return rho > 0 ? std::log2(rho) : -std::numeric_limits<T>::infinity();
}

template <class T>
glm::vec4 Texture2D::sampleAtLod(const SamplerState& s, glm::vec2 uv, T lambda) const {
    using Vec = glm::vec<4, T>;
    const T u = T(uv.x), v = T(uv.y);
    lambda += T(s.mipLodBias);
    if (!(lambda >= T(s.minLod))) lambda = T(s.minLod);  // also NaN, and −∞ from zero derivatives
    if (lambda > T(s.maxLod)) lambda = T(s.maxLod);
    // The min/mag choice is made after the sampler's clamp, as in D3D11: minLod > 0 always minifies.
    if (!(lambda > 0)) return glm::vec4(filterLevel<T>(s, s.magFilter, levels_[0], u, v));

    const size_t last = levels_.size() - 1;
    if (lambda > T(last)) lambda = T(last);
    if (s.mipFilter == Filter::Point) {
        const size_t l = std::min(last, size_t(std::floor(lambda + T(0.5))));
        return glm::vec4(filterLevel<T>(s, s.minFilter, levels_[l], u, v));
    }
    const T base = std::floor(lambda);
    const size_t l0 = size_t(base);
    const T f = lambda - base;
    const Vec c0 = filterLevel<T>(s, s.minFilter, levels_[l0], u, v);
    if (f == 0 || l0 >= last) return glm::vec4(c0);
    const Vec c1 = filterLevel<T>(s, s.minFilter, levels_[l0 + 1], u, v);
    return glm::vec4(c0 + (c1 - c0) * f);
}

glm::vec4 Texture2D::sampleImplicitLod(const SamplerState& s, glm::vec2 uv) const {
    if (levels_.empty()) return glm::vec4(0.0f);
    const bool reference = inReferenceMode();
    if (levels_.size() == 1 && s.minFilter == s.magFilter) {
        if (reference) return glm::vec4(filterLevel<double>(s, s.magFilter, levels_[0], uv.x, uv.y));
        return filterLevel<float>(s, s.magFilter, levels_[0], uv.x, uv.y);
    }
    const Gradient<glm::vec2> g = quadGradient(uv);
    if (reference) return sampleAtLod<double>(s, uv, lodFromGradients<double>(g.ddx, g.ddy));
    return sampleAtLod<float>(s, uv, lodFromGradients<float>(g.ddx, g.ddy));
}

glm::vec4 Texture2D::SampleLevel(const SamplerState& s, glm::vec2 uv, float lod) const {
    if (levels_.empty()) return glm::vec4(0.0f);
    if (inReferenceMode()) return sampleAtLod<double>(s, uv, double(lod));
    return sampleAtLod<float>(s, uv, lod);
}

glm::vec4 Texture2D::SampleGrad(const SamplerState& s, glm::vec2 uv, glm::vec2 ddx, glm::vec2 ddy) const {
    if (levels_.empty()) return glm::vec4(0.0f);
    if (inReferenceMode()) return sampleAtLod<double>(s, uv, lodFromGradients<double>(ddx, ddy));
    return sampleAtLod<float>(s, uv, lodFromGradients<float>(ddx, ddy));
}

glm::vec<4, Float8> Texture2D::sampleLanes(SamplerState s, glm::vec<2, Float8> uv) const {
    glm::vec<4, Float8> out;
    const bool lod_matters = levels_.size() > 1 || s.minFilter != s.magFilter;
    for (int lane = 0; lane < 8; ++lane) {
        const glm::vec2 p(uv.x[lane], uv.y[lane]);
        glm::vec4 c;
        if (lod_matters) {
            // Fine derivatives within the lane's 2×2 quad: lanes (0,1,4,5) and (2,3,6,7).
            const int left = lane & ~1, top = lane & ~4;
            const glm::vec2 ddx(uv.x[left + 1] - uv.x[left], uv.y[left + 1] - uv.y[left]);
            const glm::vec2 ddy(uv.x[top + 4] - uv.x[top], uv.y[top + 4] - uv.y[top]);
            c = SampleGrad(s, p, ddx, ddy);
        } else {
            c = SampleLevel(s, p, 0.0f);
        }
        out.x.set(lane, c.x), out.y.set(lane, c.y), out.z.set(lane, c.z), out.w.set(lane, c.w);
    }
    return out;
}

void Texture2D::buildAlphaSpans() {
    const Level& level = levels_[0];
    alpha_spans_.assign(size_t(level.height), AlphaSpan{level.width, -1});
    for (int y = 0; y < level.height; ++y) {
        AlphaSpan& span = alpha_spans_[size_t(y)];
        for (int x = 0; x < level.width; ++x) {
            // `!(a == 0)`: NaN is not transparent.
            if (!(texel<float>(level, x, y).w == 0.0f)) {
                span.first = std::min(span.first, x);
                span.last = x;
            }
        }
    }
    // Level k, row r: the union of rows r .. r + 2^k − 1 (those that exist), from two of level k − 1.
    for (int k = 1; (1 << k) <= level.height; ++k) {
        const size_t h = size_t(level.height), previous = size_t(k - 1) * h, half = size_t(1) << (k - 1);
        alpha_spans_.resize(size_t(k + 1) * h);
        for (size_t r = 0; r < h; ++r) {
            const AlphaSpan a = alpha_spans_[previous + r];
            const AlphaSpan b = r + half < h ? alpha_spans_[previous + r + half] : a;
            alpha_spans_[previous + h + r] = a.unite(b);
        }
    }
}

void Texture2D::buildFootprints() {
    footprints_.clear();
    planes_.clear();
    grid_ = {};
    const Level& level = levels_[0];
    if (format_ != Format::R8G8B8A8_UNORM || levels_.size() != 1 || level.width > kMaxFootprintSide ||
        level.height > kMaxFootprintSide)
        return;
    const int w = level.width, h = level.height;
    footprints_.resize(size_t(w + 1) * size_t(h + 1) * 16);
    grid_ = {float(w), float(h), float(w - 1), float(h - 1), float(w + 1), float(w + 2), w - 1, h - 1, w + 1};
    // Channel-major, so that a load is already what the filter multiplies: bytes 4c..4c+3 are channel
    // c of texels (i, j) (i+1, j) (i, j+1) (i+1, j+1), clamped, each stored as texel − 128 in two's
    // complement (the filters read signed bytes).
    auto put = [&](int x, int y, uint8_t* f, size_t k) {
        x = std::clamp(x, 0, w - 1);
        y = std::clamp(y, 0, h - 1);
        for (size_t c = 0; c < 4; ++c) f[4 * c + k] = bytes_[4 * (size_t(y) * size_t(w) + size_t(x)) + c] ^ 0x80u;
    };
    for (int j = -1; j < h; ++j) {
        for (int i = -1; i < w; ++i) {
            uint8_t* f = &footprints_[16 * (size_t(j + 1) * size_t(w + 1) + size_t(i + 1))];
            put(i, j, f, 0);
            put(i + 1, j, f, 1);
            put(i, j + 1, f, 2);
            put(i + 1, j + 1, f, 3);
        }
    }
#if RASTER_AVX512
    const size_t count = size_t(w + 1) * size_t(h + 1), plane = count + kPlaneWindow - 1;
    planes_.assign(4 * plane, 0);
    for (size_t c = 0; c < 4; ++c)
        for (size_t k = 0; k < count; ++k)
            std::memcpy(&planes_[c * plane + k], &footprints_[16 * k + 4 * c], 4);
    grid_.planeStride = int32_t(plane);
#endif
}

}  // namespace raster
