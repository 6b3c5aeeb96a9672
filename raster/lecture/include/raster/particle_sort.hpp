// Sorting particles back to front for order-dependent blending ("over"): the lecture's last blend
// figure. Additive blending is order-independent and needs no sort at all.
//
// The lecture's slide sorts with
//     bool operator<(a, b) { return a.pos·ahead > b.pos·ahead + 0.01; }
// which is not a strict weak ordering: "neither is before the other" (depths within 0.01) is not
// transitive. Depths 0, 0.008 and 0.016: the first two are tied, so are the last two, yet the third
// is before the first. std::sort with such a comparator is undefined behaviour (it may read past
// the range or crash), which tests/particles_test.cpp exhibits on that triple without calling it.
// Sorting by the plain key fixes it: depth is a number, and ">" on numbers (NaN set apart, below)
// is a strict weak ordering.
//
// The order, exactly: depth descending (the farthest first); equal depths, −0 and +0 included, keep
// their index order (the sort is stable); NaN depths come last, after the nearest, in index order
// (a particle with a NaN position is dropped by the clipper anyway, so where it is drawn does not
// matter, only that the order stays well defined). backToFrontBefore() is that ordering as a
// comparator, and every method below gives the same permutation as
// std::stable_sort(indices, backToFrontBefore on depths), bit for bit.
//
// How: each depth becomes a 32-bit key whose unsigned order is that order (depthSortKey), packed with
// its index into 64 bits; then an LSD radix sort (three passes of 11 bits, or four of 8 from 600 000
// keys, where fewer buckets scatter with fewer cache and TLB misses; a pass skipped when all keys
// share its digit) or, for short arrays, std::sort on the packed words. The radix sort pays from
// kRadixSortMinCount elements (measured, see the constant).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "raster/particles.hpp"

namespace raster {

// The back-to-front strict weak ordering on depths: true when a is drawn before b.
inline bool backToFrontBefore(float a, float b) {
    if (b != b) return a == a;  // every number is before a NaN; NaNs are tied
    return a > b;               // false when a is NaN
}

// A key whose unsigned order is the back-to-front order: larger depth → smaller key, −0 and +0 the
// same key, every NaN 0xFFFFFFFF (the largest, and no number's key).
uint32_t depthSortKey(float depth);

// Below this many elements, Automatic uses std::sort on the packed (key, index) words; from it on,
// the radix sort. Measured with -O3 on the 2-core AMD EPYC build machine (busy with other builds):
// the radix sort has a fixed cost of about 6 µs (three histograms of 2048 counters to clear, scan
// and prefix-sum), so std::sort wins below ~900 elements; both take 10 µs at 1024, the radix sort
// is 1.8× faster at 4096 and 7× at 10⁶ (10–13 ms against 77–89 ms; 16–18× against std::sort of
// indices with a comparator that reads the depths, 171–232 ms). tests/particles_bench.cpp.
constexpr size_t kRadixSortMinCount = 1024;

enum class SortMethod : uint8_t {
    Automatic,   // radix from kRadixSortMinCount elements, std::sort below
    Radix,       // always the LSD radix sort
    Comparison,  // always std::sort on the packed (key, index) words
};

// Reused buffers, so that sorting every frame does not allocate every frame.
struct SortScratch {
    std::vector<uint64_t> packed, spare;  // (key << 32) | index
};

// Fills `order` (order.size() must equal depths.size(), < 2³²) with the indices 0..n−1 of `depths`
// in back-to-front order, as above. Error(InvalidArgument) if the sizes differ.
void sortBackToFront(std::span<const float> depths, std::span<uint32_t> order,
                     SortMethod method = SortMethod::Automatic, SortScratch* scratch = nullptr);

// The same with depth_i = (position_i − eye)·ahead, `ahead` the camera's forward direction (any
// nonzero finite length: the order of depths does not depend on it beyond rounding). The indices
// are into `particles`, e.g. for an index buffer over the uploaded vertices.
void sortBackToFront(std::span<const Particle> particles, glm::vec3 eye, glm::vec3 ahead, std::span<uint32_t> order,
                     SortMethod method = SortMethod::Automatic, SortScratch* scratch = nullptr);

}  // namespace raster
