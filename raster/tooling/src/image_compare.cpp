#include "raster/image_compare.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "raster/check.hpp"

namespace raster {
namespace {

std::string sizeText(uint32_t width, uint32_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

void requireSameSize(const Rgba8View& a, const Rgba8View& b) {
    RASTER_REQUIRE(a.width() == b.width() && a.height() == b.height(), InvalidArgument,
                   "comparing images of different sizes: " + sizeText(a.width(), a.height()) + " and " +
                       sizeText(b.width(), b.height()));
}

void requireChannels(CompareChannels channels) {
    RASTER_REQUIRE(channels == CompareChannels::Rgb || channels == CompareChannels::Rgba, InvalidArgument,
                   "comparing " + std::to_string(int(channels)) + " channels (3: RGB, 4: RGBA)");
}

}  // namespace

Rgba8View::Rgba8View(std::span<const uint8_t> pixels, uint32_t width, uint32_t height)
    : pixels_(pixels), width_(width), height_(height) {
    RASTER_REQUIRE(pixels.size() == byteCount(byteCount(width, height), 4), InvalidArgument,
                   "an RGBA8 image of " + sizeText(width, height) + " needs " +
                       std::to_string(byteCount(byteCount(width, height), 4)) + " bytes, not " +
                       std::to_string(pixels.size()));
}

int largestChannelDifference(const uint8_t* a, const uint8_t* b, CompareChannels channels) {
    int m = 0;
    for (int c = 0; c < int(channels); ++c) m = std::max(m, std::abs(int(a[c]) - int(b[c])));
    return m;
}

ImageDifference compareImages(Rgba8View a, Rgba8View b, CompareChannels channels) {
    requireSameSize(a, b);
    requireChannels(channels);
    ImageDifference d;
    d.width = a.width(), d.height = a.height();
    d.pixels = size_t(d.width) * d.height;
    uint64_t sum = 0;  // of every channel's |a − b|: at most 255 · 4 · 16384² fits
    for (size_t i = 0; i < d.pixels; ++i) {
        const uint8_t *p = a.pixel(i), *q = b.pixel(i);
        for (int c = 0; c < int(channels); ++c) sum += uint64_t(std::abs(int(p[c]) - int(q[c])));
        const int m = largestChannelDifference(p, q, channels);
        d.differing += m > 0;
        d.within1 += m <= 1;
        d.within3 += m <= 3;
        if (m > d.max) d.max = m, d.maxX = uint32_t(i % d.width), d.maxY = uint32_t(i / d.width);
    }
    d.meanAbs = d.pixels > 0 ? double(sum) / (double(int(channels)) * double(d.pixels)) : 0.0;
    return d;
}

DifferenceMap differenceMap(Rgba8View a, Rgba8View b, CompareChannels channels) {
    requireSameSize(a, b);
    requireChannels(channels);
    DifferenceMap map;
    map.width = a.width(), map.height = a.height();
    map.largest.resize(size_t(map.width) * map.height);
    for (size_t i = 0; i < map.largest.size(); ++i) {
        map.largest[i] = uint8_t(largestChannelDifference(a.pixel(i), b.pixel(i), channels));
        map.max = std::max(map.max, int(map.largest[i]));
    }
    return map;
}

// ---- Grading: the result, the integer methods and the region finder ----

namespace {

ComparisonResult startResult(CompareMethod method, const Rgba8View& reference, const Rgba8View& result) {
    requireSameSize(reference, result);
    ComparisonResult r;
    r.method = method;
    r.width = reference.width(), r.height = reference.height();
    r.error.assign(size_t(r.width) * r.height, 0.0f);
    return r;
}

// Fills in the worst pixel and the failing count from r.error and r.failLevel; the integer methods'
// figure is that count. Then passed = figure ≤ limit.
void finishResult(ComparisonResult& r, bool figure_is_failing) {
    for (size_t i = 0; i < r.error.size(); ++i) {
        const float e = r.error[i];
        r.failing += e > r.failLevel;
        if (e > r.worstError)
            r.worstError = e, r.worstX = uint32_t(i % r.width), r.worstY = uint32_t(i / r.width);
    }
    if (figure_is_failing) r.figure = double(r.failing);
    r.passed = r.figure <= r.limit;
}

// How many steps the largest channel difference of two pixels is past its allowance, 0 when every
// channel is within its allowance (dEQP's boolAll(lessThanEqual(diff, threshold))).
int stepsOver(const uint8_t* p, const uint8_t* q, const Rgba8Threshold& threshold) {
    int over = 0;
    for (int c = 0; c < 4; ++c) over = std::max(over, std::abs(int(p[c]) - int(q[c])) - int(threshold[c]));
    return over;
}

ComparisonResult thresholdResult(CompareMethod method, const Rgba8View& reference, const Rgba8View& result,
                                 const Rgba8Threshold& threshold) {
    ComparisonResult r = startResult(method, reference, result);
    for (size_t i = 0; i < r.error.size(); ++i)
        r.error[i] = float(stepsOver(reference.pixel(i), result.pixel(i), threshold)) / 255.0f;
    finishResult(r, true);
    return r;
}

// The fewest steps over the allowance of any pixel of `image` in the window [x0, x1] × [y0, y1] against
// `pixel`; stops at the first match (0).
int bestMatch(const uint8_t* pixel, const Rgba8View& image, uint32_t x0, uint32_t x1, uint32_t y0,
              uint32_t y1, const Rgba8Threshold& threshold) {
    int best = std::numeric_limits<int>::max();
    for (uint32_t y = y0; y <= y1; ++y)
        for (uint32_t x = x0; x <= x1; ++x) {
            best = std::min(best, stepsOver(pixel, image.pixel(size_t(y) * image.width() + x), threshold));
            if (best == 0) return 0;
        }
    return best;
}

void validatePosition(const PositionTolerance& t) {
    RASTER_REQUIRE(
        t.deviationX <= PositionTolerance::kMaxDeviation && t.deviationY <= PositionTolerance::kMaxDeviation,
        InvalidArgument,
        "position \"deviation\" must be 0.." + std::to_string(PositionTolerance::kMaxDeviation) +
            " pixels, not " + std::to_string(t.deviationX) + ", " + std::to_string(t.deviationY));
    RASTER_REQUIRE(
        t.check == PositionCheck::Both || t.check == PositionCheck::ResultInReference, InvalidArgument,
        "position check " + std::to_string(int(t.check)) + " (0: both ways, 1: result in reference)");
}

}  // namespace

const char* compareMethodName(CompareMethod method) {
    switch (method) {
        case CompareMethod::Exact:
            return "exact";
        case CompareMethod::Threshold:
            return "threshold";
        case CompareMethod::Position:
            return "position";
        case CompareMethod::Flip:
            return "flip";
    }
    return "?";
}

ComparisonResult compareExact(Rgba8View reference, Rgba8View result) {
    return thresholdResult(CompareMethod::Exact, reference, result, {0, 0, 0, 0});
}

ComparisonResult compareThreshold(Rgba8View reference, Rgba8View result, Rgba8Threshold threshold) {
    return thresholdResult(CompareMethod::Threshold, reference, result, threshold);
}

ComparisonResult comparePosition(Rgba8View reference, Rgba8View result, const PositionTolerance& tolerance) {
    ComparisonResult r = startResult(CompareMethod::Position, reference, result);
    validatePosition(tolerance);
    const uint32_t w = r.width, h = r.height, dx = tolerance.deviationX, dy = tolerance.deviationY;
    const Rgba8Threshold& t = tolerance.threshold;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            // dEQP's acceptOutOfBoundsAsAnyValue: the band whose window leaves the image is not checked.
            if (tolerance.acceptOutOfBounds && (x < dx || x + dx >= w || y < dy || y + dy >= h)) continue;
            const size_t i = size_t(y) * w + x;
            if (stepsOver(reference.pixel(i), result.pixel(i), t) == 0) continue;
            // The window, cut to the image.
            const uint32_t x0 = x - std::min(x, dx), x1 = std::min(w - 1, x + dx);
            const uint32_t y0 = y - std::min(y, dy), y1 = std::min(h - 1, y + dy);
            int over = bestMatch(result.pixel(i), reference, x0, x1, y0, y1, t);
            if (tolerance.check == PositionCheck::Both)
                over = std::max(over, bestMatch(reference.pixel(i), result, x0, x1, y0, y1, t));
            r.error[i] = float(over) / 255.0f;
        }
    finishResult(r, true);
    return r;
}

PixelRegion largestFailingRegion(const ComparisonResult& result) {
    const size_t n = size_t(result.width) * result.height;
    RASTER_REQUIRE(result.error.size() == n, InvalidArgument,
                   "a comparison result of " + sizeText(result.width, result.height) + " with " +
                       std::to_string(result.error.size()) + " error values");
    const uint32_t w = result.width, h = result.height;
    auto failing = [&](size_t i) { return result.error[i] > result.failLevel; };
    std::vector<uint8_t> seen(n, 0);
    std::vector<size_t> stack;
    PixelRegion best;
    for (size_t start = 0; start < n; ++start) {
        if (seen[start] || !failing(start)) continue;
        // Flood fill from the region's first pixel (row by row), 8-connected.
        PixelRegion region;
        region.left = region.right = uint32_t(start % w), region.top = region.bottom = uint32_t(start / w);
        size_t representative = start;
        seen[start] = 1;
        stack.assign(1, start);
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            const uint32_t x = uint32_t(i % w), y = uint32_t(i / w);
            ++region.pixels;
            region.left = std::min(region.left, x), region.right = std::max(region.right, x);
            region.top = std::min(region.top, y), region.bottom = std::max(region.bottom, y);
            const float e = result.error[i], best_e = result.error[representative];
            if (e > best_e || (e == best_e && i < representative)) representative = i;
            for (uint32_t ny = y - std::min(y, 1u); ny <= std::min(h - 1, y + 1); ++ny)
                for (uint32_t nx = x - std::min(x, 1u); nx <= std::min(w - 1, x + 1); ++nx) {
                    const size_t j = size_t(ny) * w + nx;
                    if (!seen[j] && failing(j)) seen[j] = 1, stack.push_back(j);
                }
        }
        region.x = uint32_t(representative % w), region.y = uint32_t(representative / w);
        region.error = result.error[representative];
        if (region.pixels > best.pixels) best = region;  // strictly larger: the earlier wins ties
    }
    return best;
}

// ---- LDR-FLIP ----

namespace {
namespace flip {

constexpr double kPi = 3.14159265358979323846;

// Linear sRGB to XYZ (D65), the reference code's fractions; its rows' sums are the white point
// (Xn, Yn, Zn) = XYZ of linear (1, 1, 1), so Yn = 1.
constexpr double kRgbToXyz[3][3] = {{10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794},
                                    {2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897},
                                    {1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382}};

using Matrix = std::array<std::array<double, 3>, 3>;

// XYZ relative to white, (X/Xn, Y/Yn, Z/Zn), from linear RGB.
Matrix rgbToRelativeXyz() {
    Matrix m{};
    for (int i = 0; i < 3; ++i) {
        const double white = kRgbToXyz[i][0] + kRgbToXyz[i][1] + kRgbToXyz[i][2];
        for (int j = 0; j < 3; ++j) m[i][j] = kRgbToXyz[i][j] / white;
    }
    return m;
}

// The opponent channels (y, cx, cz) = (Y/Yn, X/Xn − Y/Yn, Y/Yn − Z/Zn) from linear RGB. YCxCz is
// (116 y − 16, 500 cx, 200 cz); the filters are linear with weights summing to 1, so filtering
// y, cx, cz is filtering Y, Cx, Cz, without the scale and offset's rounding.
Matrix rgbToOpponent() {
    const Matrix t = rgbToRelativeXyz();
    Matrix m{};
    for (int j = 0; j < 3; ++j) m[0][j] = t[1][j], m[1][j] = t[0][j] - t[1][j], m[2][j] = t[1][j] - t[2][j];
    return m;
}

Matrix inverse(const Matrix& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    Matrix r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
            r[i][j] = (m[a][c] * m[b][d] - m[a][d] * m[b][c]) / det;  // cofactor, transposed
        }
    return r;
}

// The same in float, for the per-pixel work.
struct FloatMatrix {
    float m[3][3];
    float times(int row, const float (&v)[3]) const {
        return m[row][0] * v[0] + m[row][1] * v[1] + m[row][2] * v[2];
    }
};
FloatMatrix toFloat(const Matrix& d) {
    FloatMatrix f{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f.m[i][j] = float(d[size_t(i)][size_t(j)]);
    return f;
}

// The cube root of t > 0 for floats: a first guess from the bits (a third of the exponent, within
// 3.5%), then two Halley steps in double (the error cubed each time: 3.5% → 4e-5 → 1e-13), rounded to
// float. Correctly rounded on [0.0088, 1.2], L*a*b*'s domain here (every float in it checked against
// double cbrt; glibc's cbrtf is 1 ulp off for a tenth of them). Arithmetic only, so the bits are the
// same on every machine; and 5 times faster than cbrtf, which took 40% of FLIP's time.
float cubeRoot(float t) {
    const float guess = std::bit_cast<float>(std::bit_cast<uint32_t>(t) / 3 + 709921077u);
    const double x = t;
    double y = guess;
    for (int i = 0; i < 2; ++i) {
        const double y3 = y * y * y;
        y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
    }
    return float(y);
}
double cubeRoot(double t) {
    return std::cbrt(t);
}

// CIE L*a*b*'s f: the cube root above (6/29)³, a line below it.
template <class T>
T labF(T t) {
    constexpr T kDelta = T(6.0 / 29.0);
    return t > kDelta * kDelta * kDelta ? cubeRoot(t) : t / (T(3) * kDelta * kDelta) + T(4.0 / 29.0);
}

// Hunt-adjusted L*a*b* from XYZ relative to white: (L*, 0.01 L* a*, 0.01 L* b*).
template <class T>
std::array<T, 3> huntLab(T x, T y, T z) {
    const T fx = labF(x), fy = labF(y), fz = labF(z);
    const T l = T(116) * fy - T(16);
    return {l, T(0.01) * l * (T(500) * (fx - fy)), T(0.01) * l * (T(200) * (fy - fz))};
}

template <class T>
T hyab(const std::array<T, 3>& p, const std::array<T, 3>& q) {
    const T da = p[1] - q[1], db = p[2] - q[2];
    return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

constexpr double kColorExponent = 0.7;       // q_c
constexpr double kCompressAt = 0.4;          // p_c: errors up to p_c · cmax map linearly...
constexpr double kCompressedTo = 0.95;       // p_t: ...onto [0, p_t]
constexpr double kEdgeWidthDegrees = 0.082;  // w: peak to trough of the edge detector, 2σ

// cmax: the HyAB distance of Hunt-adjusted green and blue, the largest in the RGB cube, to the q_c.
double maxColorError() {
    const Matrix t = rgbToRelativeXyz();
    const auto green = huntLab(t[0][1], t[1][1], t[2][1]), blue = huntLab(t[0][2], t[1][2], t[2][2]);
    return std::pow(hyab(green, blue), kColorExponent);
}

// sRGB byte to linear, the sRGB transfer function.
const std::array<float, 256>& srgbToLinear() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}

// ---- Filters: separable, clamp-to-edge, deterministic ----

// A symmetric (or antisymmetric) 1D kernel by its half: w[k] is the weight at offsets ±k, k = 0..r,
// applied as a correlation out(x) = Σ kernel(k) · in(x + k):
//   Even     w[0] in(x) + Σ w[k] (in(x − k) + in(x + k))             (Gaussians: weights sum to 1)
//   Odd      Σ w[k] (in(x − k) − in(x + k))                          (first derivative: sums to 0)
//   ZeroSum  Σ w[k] (in(x − k) + in(x + k) − 2 in(x))                (second derivative, w[0] =
//            −2 Σ w[k] by the normalisation: sums to 0)
// The odd and zero-sum forms give exactly 0 on a constant input, whatever the weights' rounding.
enum class Parity : uint8_t { Even, Odd, ZeroSum };
struct Taps {
    Parity parity = Parity::Even;
    std::vector<float> w;
    int radius() const { return int(w.size()) - 1; }
};

// out[x] for x in [0, n), from the centre samples and those k before and after (minus[k], plus[k]).
// The sum's order is fixed per x (k = 1, 2, ...), so vectorising over x does not change the bits.
void applyTaps(const Taps& t, const float* centre, const float* const* minus, const float* const* plus,
               float* out, size_t n) {
    const float w0 = t.parity == Parity::Even ? t.w[0] : 0.0f;
    for (size_t x = 0; x < n; ++x) out[x] = w0 * centre[x];
    for (int k = 1; k <= t.radius(); ++k) {
        const float wk = t.w[size_t(k)], *a = minus[k], *b = plus[k];
        switch (t.parity) {
            case Parity::Even:
                for (size_t x = 0; x < n; ++x) out[x] += wk * (a[x] + b[x]);
                break;
            case Parity::Odd:
                for (size_t x = 0; x < n; ++x) out[x] += wk * (a[x] - b[x]);
                break;
            case Parity::ZeroSum:
                for (size_t x = 0; x < n; ++x) out[x] += wk * ((a[x] + b[x]) - (centre[x] + centre[x]));
                break;
        }
    }
}

struct Plane {
    uint32_t width = 0, height = 0;
    std::vector<float> v;
    float* row(uint32_t y) { return v.data() + size_t(y) * width; }
    const float* row(uint32_t y) const { return v.data() + size_t(y) * width; }
};

// Filters every row of `in` into `out` (same size), reading past the ends as the end pixel.
void filterRows(const Plane& in, Plane& out, const Taps& t) {
    const int r = t.radius();
    std::vector<float> padded(in.width + 2 * size_t(r));
    std::vector<const float*> minus(size_t(r) + 1), plus(size_t(r) + 1);
    const float* centre = padded.data() + r;
    for (int k = 1; k <= r; ++k) minus[size_t(k)] = centre - k, plus[size_t(k)] = centre + k;
    for (uint32_t y = 0; y < in.height; ++y) {
        const float* src = in.row(y);
        for (size_t i = 0; i < padded.size(); ++i)
            padded[i] = src[std::clamp<ptrdiff_t>(ptrdiff_t(i) - r, 0, ptrdiff_t(in.width) - 1)];
        applyTaps(t, centre, minus.data(), plus.data(), out.row(y), in.width);
    }
}

// Row y of `in` filtered down its columns, into out (in.width values), reading past the top and bottom
// as the edge row.
void filterColumnsAt(const Plane& in, uint32_t y, const Taps& t, float* out) {
    const int r = t.radius(), last = int(in.height) - 1;
    std::vector<const float*> minus(size_t(r) + 1), plus(size_t(r) + 1);
    for (int k = 1; k <= r; ++k) {
        minus[size_t(k)] = in.row(uint32_t(std::clamp(int(y) - k, 0, last)));
        plus[size_t(k)] = in.row(uint32_t(std::clamp(int(y) + k, 0, last)));
    }
    applyTaps(t, in.row(y), minus.data(), plus.data(), out, in.width);
}

// ---- The kernels ----

// Half of a Gaussian exp(−k² / (2σ²)) or, for the CSFs, exp(−π² (k/ppd)² / b), k = 0..r, in double.
std::vector<double> halfGaussian(int r, double scale) {  // weight exp(−scale · k²)
    std::vector<double> g(size_t(r) + 1);
    for (int k = 0; k <= r; ++k) g[size_t(k)] = std::exp(-scale * double(k) * double(k));
    return g;
}

// g scaled so that the whole kernel (both halves) sums to 1; also returns that sum before.
Taps evenTaps(const std::vector<double>& g, double* sum = nullptr) {
    double s = g[0];
    for (size_t k = 1; k < g.size(); ++k) s += 2 * g[k];
    Taps t{Parity::Even, {}};
    for (double v : g) t.w.push_back(float(v / s));
    if (sum) *sum = s;
    return t;
}

struct Kernels {
    // Contrast sensitivity, per opponent channel: achromatic, red–green, and blue–yellow as
    // byWeight[0] · by[0] ⊗ by[0] + byWeight[1] · by[1] ⊗ by[1] (a sum of two Gaussians).
    Taps achromatic, redGreen, by[2];
    float byWeight[2] = {0, 0};
    // Features: the Gaussian across, its first (edge) and second (point) derivative along.
    Taps gaussian, edge, point;
};

// The CSFs' Gaussians a · √(π/b) · exp(−π² d² / b), d in degrees, with the paper's (a, b): achromatic
// (1, 0.0047), red–green (1, 0.0053), blue–yellow (34.1, 0.04) + (13.5, 0.025). All on one radius,
// ⌈3 √(b_max / (2π²)) · ppd⌉ with b_max = 0.04, as the reference code.
void makeContrastKernels(double ppd, Kernels& k) {
    const int r = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * ppd));
    auto gaussian = [&](double b) { return halfGaussian(r, kPi * kPi / (b * ppd * ppd)); };
    k.achromatic = evenTaps(gaussian(0.0047));
    k.redGreen = evenTaps(gaussian(0.0053));
    // 2D, a · √(π/b) · G(x) G(y) sums to a · √(π/b) · S², S the 1D sum: each term's share of the total.
    const double a[2] = {34.1, 13.5}, b[2] = {0.04, 0.025};
    double mass[2];
    for (int i = 0; i < 2; ++i) {
        double s = 0;
        k.by[i] = evenTaps(gaussian(b[i]), &s);
        mass[i] = a[i] * std::sqrt(kPi / b[i]) * s * s;
    }
    for (int i = 0; i < 2; ++i) k.byWeight[i] = float(mass[i] / (mass[0] + mass[1]));
}

// The reference code's 2D feature kernels, −x · g(x, y) (edges) and (x²/σ² − 1) · g(x, y) (points),
// with g the Gaussian of σ = 0.5 · w · ppd, radius ⌈3σ⌉, positive weights scaled to sum 1 and negative
// ones to −1, are separable: that 1D kernel along x, times the 1D Gaussian normalised to 1 along y.
void makeFeatureKernels(double ppd, Kernels& k) {
    const double sigma = 0.5 * kEdgeWidthDegrees * ppd;
    const int r = int(std::ceil(3.0 * sigma));
    const std::vector<double> g = halfGaussian(r, 1.0 / (2.0 * sigma * sigma));
    k.gaussian = evenTaps(g);
    // Edges: weight k · g(k) at −k, −k · g(k) at +k; the positive side sums to 1.
    double positive = 0;
    for (int i = 1; i <= r; ++i) positive += i * g[size_t(i)];
    k.edge = {Parity::Odd, std::vector<float>(size_t(r) + 1, 0.0f)};
    for (int i = 1; i <= r && positive > 0; ++i) k.edge.w[size_t(i)] = float(i * g[size_t(i)] / positive);
    // Points: (k²/σ² − 1) g(k), negative within σ of the centre; each sign scaled to sum ±1 over both
    // sides. (When the ppd is so small that the Gaussian vanishes at ±1, no feature can be seen: 0.)
    double pos = 0, neg = 0;
    std::vector<double> h(size_t(r) + 1);
    for (int i = 0; i <= r; ++i) {
        h[size_t(i)] = (double(i) * i / (sigma * sigma) - 1.0) * g[size_t(i)];
        (h[size_t(i)] > 0 ? pos : neg) += (i == 0 ? 1 : 2) * h[size_t(i)];
    }
    k.point = {Parity::ZeroSum, std::vector<float>(size_t(r) + 1, 0.0f)};
    for (int i = 1; i <= r && pos > 0 && neg < 0; ++i)
        k.point.w[size_t(i)] = float(h[size_t(i)] > 0 ? h[size_t(i)] / pos : h[size_t(i)] / -neg);
}

// ---- One image's planes ----

// What the error needs of one image: its filtered colour as Hunt-adjusted L*a*b*, and the size of its
// edge and point responses.
struct Prepared {
    Plane l, a, b, edge, point;
};

// Edge and point magnitudes of the luminance plane, using three scratch planes.
void detectFeatures(const Plane& luminance, const Kernels& k, Plane (&scratch)[3], Prepared& out) {
    Plane &across = scratch[0], &edgeAlong = scratch[1], &pointAlong = scratch[2];
    filterRows(luminance, across, k.gaussian);
    filterRows(luminance, edgeAlong, k.edge);
    filterRows(luminance, pointAlong, k.point);
    std::vector<float> gx(luminance.width), gy(luminance.width);
    for (uint32_t y = 0; y < luminance.height; ++y) {
        float *edge = out.edge.row(y), *point = out.point.row(y);
        filterColumnsAt(edgeAlong, y, k.gaussian, gx.data());  // ∂/∂x: derivative across, Gaussian down
        filterColumnsAt(across, y, k.edge, gy.data());         // ∂/∂y
        for (uint32_t x = 0; x < luminance.width; ++x) edge[x] = std::sqrt(gx[x] * gx[x] + gy[x] * gy[x]);
        filterColumnsAt(pointAlong, y, k.gaussian, gx.data());
        filterColumnsAt(across, y, k.point, gy.data());
        for (uint32_t x = 0; x < luminance.width; ++x) point[x] = std::sqrt(gx[x] * gx[x] + gy[x] * gy[x]);
    }
}

// The contrast sensitivity filters, in place on the three opponent planes.
void filterContrast(Plane (&opponent)[3], const Kernels& k, Plane (&scratch)[3]) {
    std::vector<float> second(opponent[0].width);
    for (int c = 0; c < 2; ++c) {
        const Taps& t = c == 0 ? k.achromatic : k.redGreen;
        filterRows(opponent[c], scratch[0], t);
        for (uint32_t y = 0; y < opponent[c].height; ++y)
            filterColumnsAt(scratch[0], y, t, opponent[c].row(y));
    }
    filterRows(opponent[2], scratch[0], k.by[0]);
    filterRows(opponent[2], scratch[1], k.by[1]);
    for (uint32_t y = 0; y < opponent[2].height; ++y) {
        float* out = opponent[2].row(y);
        filterColumnsAt(scratch[0], y, k.by[0], out);
        filterColumnsAt(scratch[1], y, k.by[1], second.data());
        for (uint32_t x = 0; x < opponent[2].width; ++x)
            out[x] = k.byWeight[0] * out[x] + k.byWeight[1] * second[x];
    }
}

Prepared prepare(const Rgba8View& image, const Kernels& k, Plane (&scratch)[3]) {
    const uint32_t w = image.width(), h = image.height();
    const size_t n = size_t(w) * h;
    auto plane = [&] { return Plane{w, h, std::vector<float>(n)}; };
    Plane opponent[3] = {plane(), plane(), plane()};
    const std::array<float, 256>& linear = srgbToLinear();
    static const FloatMatrix kToOpponent = toFloat(rgbToOpponent());
    for (size_t i = 0; i < n; ++i) {
        const uint8_t* p = image.pixel(i);
        const float rgb[3] = {linear[p[0]], linear[p[1]], linear[p[2]]};
        for (int c = 0; c < 3; ++c) opponent[c].v[i] = kToOpponent.times(c, rgb);
    }
    Prepared out{{}, {}, {}, plane(), plane()};
    detectFeatures(opponent[0], k, scratch, out);  // on y = Y/Yn, before the colour filters
    filterContrast(opponent, k, scratch);
    // Back to linear RGB, into the RGB cube, to Hunt-adjusted L*a*b*: in place.
    static const FloatMatrix kFromOpponent = toFloat(inverse(rgbToOpponent())),
                             kToXyz = toFloat(rgbToRelativeXyz());
    for (size_t i = 0; i < n; ++i) {
        const float yc[3] = {opponent[0].v[i], opponent[1].v[i], opponent[2].v[i]};
        float rgb[3];
        for (int c = 0; c < 3; ++c) rgb[c] = std::clamp(kFromOpponent.times(c, yc), 0.0f, 1.0f);
        const std::array<float, 3> lab =
            huntLab(kToXyz.times(0, rgb), kToXyz.times(1, rgb), kToXyz.times(2, rgb));
        for (int c = 0; c < 3; ++c) opponent[c].v[i] = lab[size_t(c)];
    }
    out.l = std::move(opponent[0]), out.a = std::move(opponent[1]), out.b = std::move(opponent[2]);
    return out;
}

}  // namespace flip

// What is wrong with the options, naming the JSON field; empty when nothing is. (NaN fails every range.)
std::string flipProblem(const FlipOptions& o) {
    if (!(o.ppd >= 1.0 && o.ppd <= 1000.0))
        return "FLIP \"ppd\" (pixels per degree) must be in [1, 1000], not " + std::to_string(o.ppd);
    if (!(o.meanLimit >= 0.0 && o.meanLimit <= 1.0))
        return "FLIP \"mean\" (the mean error's limit) must be in [0, 1], not " + std::to_string(o.meanLimit);
    if (!(o.pixelLimit >= 0.0 && o.pixelLimit <= 1.0))
        return "FLIP \"pixel\" (a failing pixel's error) must be in [0, 1], not " +
               std::to_string(o.pixelLimit);
    return "";
}

}  // namespace

ComparisonResult compareFlip(Rgba8View reference, Rgba8View result, const FlipOptions& options) {
    ComparisonResult r = startResult(CompareMethod::Flip, reference, result);
    const std::string problem = flipProblem(options);
    RASTER_REQUIRE(problem.empty(), InvalidArgument, problem);
    r.limit = options.meanLimit;
    r.failLevel = float(options.pixelLimit);
    const size_t n = r.error.size();
    if (n == 0) {
        finishResult(r, false);
        return r;
    }
    // 2 × 5 prepared planes, 3 opponent planes and 3 scratch planes at the peak, besides r.error.
    requireMemory(byteCount(n, 13 * sizeof(float)),
                  "FLIP of two " + sizeText(r.width, r.height) + " images' float planes");
    flip::Kernels kernels;
    flip::makeContrastKernels(options.ppd, kernels);
    flip::makeFeatureKernels(options.ppd, kernels);
    flip::Plane scratch[3];
    for (flip::Plane& p : scratch) p = {r.width, r.height, std::vector<float>(n)};
    const flip::Prepared a = flip::prepare(reference, kernels, scratch),
                         b = flip::prepare(result, kernels, scratch);

    static const double kCmax = flip::maxColorError();
    const float cmax = float(kCmax), knee = float(flip::kCompressAt * kCmax),
                top = float(flip::kCompressedTo);
    const float below = top / knee, above = (1.0f - top) / (cmax - knee);
    const float qc = float(flip::kColorExponent), inv_sqrt2 = float(1.0 / std::sqrt(2.0));
    double sum = 0;  // in row-major order: the same bits every run
    for (size_t i = 0; i < n; ++i) {
        const std::array<float, 3> p = {a.l.v[i], a.a.v[i], a.b.v[i]}, q = {b.l.v[i], b.a.v[i], b.b.v[i]};
        const float powered = std::pow(flip::hyab(p, q), qc);
        const float color = std::min(1.0f, powered < knee ? powered * below : top + (powered - knee) * above);
        const float feature_difference =
            std::max(std::abs(a.edge.v[i] - b.edge.v[i]), std::abs(a.point.v[i] - b.point.v[i]));
        const float feature = std::min(1.0f, std::sqrt(feature_difference * inv_sqrt2));  // ^q_f, q_f = 0.5
        r.error[i] = std::pow(color, 1.0f - feature);
        sum += double(r.error[i]);
    }
    r.figure = sum / double(n);
    finishResult(r, false);
    return r;
}

// ---- A comparison described by data ----

namespace {

using Json = nlohmann::json;

[[noreturn]] void badComparison(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, "comparison: " + message);
}

// A value as the JSON said it, cut short for a message.
std::string shown(const Json& v) {
    std::string text = v.dump();
    return text.size() > 60 ? text.substr(0, 57) + "..." : text;
}

void requireOnlyFields(const Json& j, std::initializer_list<const char*> fields, const std::string& method) {
    for (const auto& [key, value] : j.items()) {
        if (std::find_if(fields.begin(), fields.end(), [&](const char* f) { return key == f; }) !=
            fields.end())
            continue;
        std::string known;
        for (const char* f : fields) known += std::string(known.empty() ? "" : ", ") + "\"" + f + "\"";
        badComparison("unknown field \"" + key + "\" for method \"" + method + "\" (it takes " + known + ")");
    }
}

// An integer in [lo, hi].
int64_t readInteger(const Json& v, const std::string& field, int64_t lo, int64_t hi) {
    if (!v.is_number_integer() || v.get<int64_t>() < lo || v.get<int64_t>() > hi)
        badComparison("\"" + field + "\" must be an integer " + std::to_string(lo) + ".." +
                      std::to_string(hi) + ", not " + shown(v));
    return v.get<int64_t>();
}

Rgba8Threshold readRgba(const Json& v) {
    if (!v.is_array() || v.size() != 4)
        badComparison("\"rgba\" must be an array of 4 integers 0..255 (red, green, blue, alpha steps), not " +
                      shown(v));
    Rgba8Threshold t{};
    for (size_t c = 0; c < 4; ++c)
        t[c] = uint8_t(readInteger(v[c], "rgba[" + std::to_string(c) + "]", 0, 255));
    return t;
}

double readNumber(const Json& j, const char* field, double fallback) {
    if (!j.contains(field)) return fallback;
    if (!j[field].is_number())
        badComparison("\"" + std::string(field) + "\" must be a number, not " + shown(j[field]));
    return j[field].get<double>();
}

bool readBool(const Json& j, const char* field, bool fallback) {
    if (!j.contains(field)) return fallback;
    if (!j[field].is_boolean())
        badComparison("\"" + std::string(field) + "\" must be true or false, not " + shown(j[field]));
    return j[field].get<bool>();
}

void readPosition(const Json& j, PositionTolerance& p) {
    requireOnlyFields(j, {"method", "deviation", "rgba", "acceptOutOfBounds", "symmetric"}, "position");
    if (!j.contains("deviation"))
        badComparison("method \"position\" needs \"deviation\": N or [x, y] pixels");
    const Json& d = j["deviation"];
    const int64_t most = PositionTolerance::kMaxDeviation;
    if (d.is_array() && d.size() == 2) {
        p.deviationX = uint32_t(readInteger(d[0], "deviation[0]", 0, most));
        p.deviationY = uint32_t(readInteger(d[1], "deviation[1]", 0, most));
    } else if (d.is_array()) {
        badComparison("\"deviation\" must be N or [x, y], not " + shown(d));
    } else {
        p.deviationX = p.deviationY = uint32_t(readInteger(d, "deviation", 0, most));
    }
    if (j.contains("rgba")) p.threshold = readRgba(j["rgba"]);
    p.acceptOutOfBounds = readBool(j, "acceptOutOfBounds", false);
    p.check = readBool(j, "symmetric", true) ? PositionCheck::Both : PositionCheck::ResultInReference;
}

void readFlip(const Json& j, FlipOptions& f) {
    requireOnlyFields(j, {"method", "mean", "ppd", "pixel"}, "flip");
    f.meanLimit = readNumber(j, "mean", f.meanLimit);
    f.pixelLimit = readNumber(j, "pixel", f.meanLimit);
    f.ppd = readNumber(j, "ppd", f.ppd);
    if (const std::string problem = flipProblem(f); !problem.empty()) badComparison(problem);
}

// "4/255", or "any" for 255 (the channel is not compared).
std::string stepsText(uint8_t steps) {
    return steps == 255 ? "any" : std::to_string(steps) + "/255";
}

std::string thresholdText(const Rgba8Threshold& t) {
    if (t[0] == t[1] && t[1] == t[2] && t[2] == t[3]) return stepsText(t[0]) + " in every channel";
    return "red " + stepsText(t[0]) + ", green " + stepsText(t[1]) + ", blue " + stepsText(t[2]) +
           ", alpha " + stepsText(t[3]);
}

std::string numberText(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", v);
    return buffer;
}

}  // namespace

Comparison Comparison::parse(std::string_view text) {
    Json j;
    try {
        j = Json::parse(text);
    } catch (const Json::parse_error& e) {
        badComparison("not JSON (" + std::string(e.what()) + ")");
    }
    if (!j.is_object())
        badComparison("must be a JSON object such as {\"method\": \"exact\"}, not " + shown(j));
    if (!j.contains("method") || !j["method"].is_string())
        badComparison("needs \"method\": \"exact\", \"threshold\", \"position\" or \"flip\"");
    const std::string method = j["method"].get<std::string>();
    Comparison c;
    if (method == "exact") {
        c.method = CompareMethod::Exact;
        requireOnlyFields(j, {"method"}, method);
    } else if (method == "threshold") {
        c.method = CompareMethod::Threshold;
        requireOnlyFields(j, {"method", "rgba"}, method);
        if (!j.contains("rgba")) badComparison("method \"threshold\" needs \"rgba\": [r, g, b, a] steps");
        c.threshold = readRgba(j["rgba"]);
    } else if (method == "position") {
        c.method = CompareMethod::Position;
        readPosition(j, c.position);
    } else if (method == "flip") {
        c.method = CompareMethod::Flip;
        readFlip(j, c.flip);
    } else {
        badComparison("unknown \"method\" \"" + method + "\" (exact, threshold, position or flip)");
    }
    return c;
}

std::string Comparison::describe() const {
    switch (method) {
        case CompareMethod::Exact:
            return "exact: every channel (red, green, blue, alpha) of every pixel equal to the reference's";
        case CompareMethod::Threshold:
            return "threshold: every pixel within " + thresholdText(threshold) + " of the reference's";
        case CompareMethod::Position: {
            const PositionTolerance& p = position;
            const std::string window = p.deviationX == p.deviationY
                                           ? "±" + std::to_string(p.deviationX) + " pixels"
                                           : "±" + std::to_string(p.deviationX) + " pixels across and ±" +
                                                 std::to_string(p.deviationY) + " down";
            return "position: every result pixel matched within " + thresholdText(p.threshold) +
                   " by a reference pixel within " + window +
                   (p.check == PositionCheck::Both ? ", and every reference pixel by a result pixel" : "") +
                   (p.acceptOutOfBounds ? "; pixels whose window leaves the image pass"
                                        : "; at the border, only pixels inside the image count");
        }
        case CompareMethod::Flip:
            return "flip: mean LDR-FLIP error at most " + numberText(flip.meanLimit) + " at " +
                   numberText(flip.ppd) + " pixels per degree (pixels above " + numberText(flip.pixelLimit) +
                   " count as failing)";
    }
    return "?";
}

ComparisonResult compare(const Comparison& comparison, Rgba8View reference, Rgba8View result) {
    switch (comparison.method) {
        case CompareMethod::Exact:
            return compareExact(reference, result);
        case CompareMethod::Threshold:
            return compareThreshold(reference, result, comparison.threshold);
        case CompareMethod::Position:
            return comparePosition(reference, result, comparison.position);
        case CompareMethod::Flip:
            return compareFlip(reference, result, comparison.flip);
    }
    throw Error(ErrorCode::InvalidArgument, "comparison method " + std::to_string(int(comparison.method)));
}

}  // namespace raster
