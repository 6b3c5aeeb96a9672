// The arithmetic the media headers are written in, for float, Float8 (simd.hpp) and double, so that
// one function template reads the same for all three: select, min, max, abs, sqrt, exp, fma.
//
// float and Float8 take raster's own (simd.hpp: the same IEEE operation lane by lane, the fast exp
// and expm1 with their scalar reference-mode twins); double takes the C library's. Scalar<T> is the
// type of a constant in T's arithmetic: float for float and Float8, double for double.
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "raster/simd.hpp"

namespace raster::media::detail {

using raster::abs;
using raster::exp;
using raster::expm1;
using raster::fma;
using raster::max;
using raster::min;
using raster::select;
using raster::sqrt;

inline double select(bool m, double a, double b) {
    return m ? a : b;
}
inline int32_t select(bool m, int32_t a, int32_t b) {
    return m ? a : b;
}
inline double min(double a, double b) {
    return a < b ? a : b;
}
inline double max(double a, double b) {
    return a > b ? a : b;
}
inline double abs(double a) {
    return std::fabs(a);
}
inline double sqrt(double a) {
    return std::sqrt(a);
}
inline double exp(double a) {
    return std::exp(a);
}
inline double expm1(double a) {
    return std::expm1(a);
}
inline double fma(double a, double b, double c) {
    return std::fma(a, b, c);
}

template <class T>
using Scalar = std::conditional_t<std::is_same_v<T, double>, double, float>;

}  // namespace raster::media::detail
