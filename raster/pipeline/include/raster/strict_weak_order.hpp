// Whether a comparator is a strict weak ordering on given elements, checked before std::sort or
// std::stable_sort sees it: with any other comparator those are undefined behaviour (they may read
// past the range and crash). The blending lab checks its student's back-to-front comparator with it
// and refuses to sort, naming the elements that break the rule, instead of crashing.
//
// A strict weak ordering `less` is irreflexive (never less(a, a)), asymmetric (not both less(a, b)
// and less(b, a)), transitive (less(a, b) and less(b, c) give less(a, c)), and its incomparability
// ("tied": neither less(a, b) nor less(b, a)) is transitive too. The lecture's slide comparator
//     a·ahead > b·ahead + 0.01
// breaks the last: depths 0, 0.008 and 0.016 are tied pairwise in a row, yet the third is before the
// first.
//
// The check is complete and takes O(n²) calls of `less` on n elements: with rank(x) the number of
// elements before x, `less` is a strict weak ordering on the elements exactly when
// less(a, b) == (rank(a) < rank(b)) for every pair (then it is the order of ranks, and a strict weak
// ordering has that form). When a pair disagrees, one of the four rules fails on that pair or on a
// triple with a third element, which findStrictWeakOrderViolation finds in O(n) more calls and returns.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace raster {

enum class OrderRule { Irreflexivity, Asymmetry, Transitivity, TransitiveTies };

// Elements (indices into the checked span) breaking `rule`, in the order the rule's text names them:
//   Irreflexivity:   less(a, a)
//   Asymmetry:       less(a, b) and less(b, a)
//   Transitivity:    less(a, b) and less(b, c), but not less(a, c)
//   TransitiveTies:  a and b tied, b and c tied, but less(a, c)
struct OrderViolation {
    OrderRule rule = OrderRule::Irreflexivity;
    size_t a = 0, b = 0, c = 0;
};

namespace detail {

// The first rule the three elements (i, j, k) break, in any of their orders, or none.
template <class T, class Less>
std::optional<OrderViolation> tripleViolation(std::span<const T> x, Less& less, size_t i, size_t j,
                                              size_t k) {
    const size_t p[3] = {i, j, k};
    const auto before = [&](size_t a, size_t b) { return bool(less(x[a], x[b])); };
    const auto tied = [&](size_t a, size_t b) { return !before(a, b) && !before(b, a); };
    for (size_t first = 0; first < 3; ++first)
        for (size_t second = 0; second < 3; ++second) {
            if (second == first) continue;
            const size_t a = p[first], b = p[second], c = p[3 - first - second];
            if (before(a, b) && before(b, c) && !before(a, c))
                return OrderViolation{OrderRule::Transitivity, a, b, c};
            if (tied(a, b) && tied(b, c) && before(a, c))
                return OrderViolation{OrderRule::TransitiveTies, a, b, c};
        }
    return std::nullopt;
}

}  // namespace detail

// The first rule `less` breaks on `items`, or none when it is a strict weak ordering on them.
template <class T, class Less>
std::optional<OrderViolation> findStrictWeakOrderViolation(std::span<const T> items, Less less) {
    const size_t n = items.size();
    for (size_t i = 0; i < n; ++i)
        if (less(items[i], items[i])) return OrderViolation{OrderRule::Irreflexivity, i, i, i};
    // rank[j]: how many items come before item j. An array, not a std::vector: GCC 12 at -O3 warns
    // falsely (-Wfree-nonheap-object) about the vector's delete once this loop is inlined into a lab.
    const std::unique_ptr<size_t[]> rank(new size_t[n]());
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j) rank[j] += bool(less(items[i], items[j]));
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j) {
            if (bool(less(items[i], items[j])) == (rank[i] < rank[j])) continue;
            if (less(items[i], items[j]) && less(items[j], items[i]))
                return OrderViolation{OrderRule::Asymmetry, i, j, j};
            for (size_t k = 0; k < n; ++k)
                if (k != i && k != j)
                    if (auto v = detail::tripleViolation(items, less, i, j, k)) return v;
        }
    return std::nullopt;
}

// The violation as a sentence, each element named by `name(index)` (e.g. "particle 17 (depth
// 2.314)") and the comparator by `comparator`.
inline std::string orderViolationText(const OrderViolation& v, const std::string& comparator,
                                      const std::function<std::string(size_t)>& name) {
    const std::string a = name(v.a), b = name(v.b), c = name(v.c);
    const std::string call = comparator + "(";
    switch (v.rule) {
        case OrderRule::Irreflexivity:
            return call + a + ", itself) is true: nothing may be before itself (irreflexivity)";
        case OrderRule::Asymmetry:
            return call + a + ", " + b + ") and " + call + b + ", " + a +
                   ") are both true: two elements cannot each be before the other (asymmetry)";
        case OrderRule::Transitivity:
            return a + " is before " + b + " and " + b + " before " + c + ", but " + a + " is not before " +
                   c + " (transitivity)";
        case OrderRule::TransitiveTies:
            return a + " and " + b + " are tied (neither is before the other), so are " + b + " and " + c +
                   ", yet " + a + " is before " + c + ": ties must be transitive";
    }
    return {};
}

}  // namespace raster
