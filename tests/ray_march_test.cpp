// Ray marching (raster/media/march.hpp, majorant_grid.hpp, ratio_tracking.hpp, metaballs.hpp): the step
// rules' convergence orders from log-log fits against a float64 quadrature, Euler's instability, the
// exponential step's exactness, ratio tracking's mean against the analytic transmittance, the grid walk
// against a brute-force test of every cell, and empty-space skipping changing no bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "raster/check.hpp"
#include "raster/media/majorant_grid.hpp"
#include "raster/media/march.hpp"
#include "raster/media/metaballs.hpp"
#include "raster/media/ratio_tracking.hpp"

using namespace raster;
using namespace raster::media;

namespace {

// A smooth heterogeneous medium along a ray: μ(s) = a + b·sin(c·s), q(s) = e + f·cos(s) (both > 0).
struct SineMedium {
    double a = 1.5, b = 1.0, c = 3.0, e = 0.6, f = 0.4;
    double mu(double s) const { return a + b * std::sin(c * s); }
    double q(double s) const { return e + f * std::cos(s); }
    // ∫_x^y μ ds, in closed form.
    double opticalDepth(double x, double y) const {
        return a * (y - x) - b / c * (std::cos(c * y) - std::cos(c * x));
    }
};

// The radiance at t0: L_bg·e^{−τ(t0, t1)} + ∫ q(s)·e^{−τ(t0, s)} ds, the integral by composite
// 5-point Gauss–Legendre over 4000 panels (error far below 1e-13 for this smooth integrand).
double referenceRadiance(const SineMedium& m, double t0, double t1, double L_bg) {
    static const double kX[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
    static const double kW[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                 0.2369268850561891};
    const int panels = 4000;
    const double h = (t1 - t0) / panels;
    double sum = 0.0;
    for (int p = 0; p < panels; ++p) {
        const double mid = t0 + (p + 0.5) * h;
        for (int k = 0; k < 5; ++k) {
            const double s = mid + 0.5 * h * kX[k];
            sum += 0.5 * h * kW[k] * m.q(s) * std::exp(-m.opticalDepth(t0, s));
        }
    }
    return L_bg * std::exp(-m.opticalDepth(t0, t1)) + sum;
}

// The slope of log(error) against log(Δs), least squares.
double convergenceOrder(StepRule rule) {
    const SineMedium m;
    const double t0 = 0.0, t1 = 2.0, L_bg = 0.3;
    const double exact = referenceRadiance(m, t0, t1, L_bg);
    std::vector<double> xs, ys;
    for (uint32_t n = 32; n <= 1024; n *= 2) {
        const double error = std::fabs(marchBackToFront(m, t0, t1, n, rule, L_bg) - exact);
        xs.push_back(std::log((t1 - t0) / n));
        ys.push_back(std::log(error));
    }
    double mx = 0, my = 0;
    for (size_t i = 0; i < xs.size(); ++i) mx += xs[i] / xs.size(), my += ys[i] / ys.size();
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < xs.size(); ++i) sxy += (xs[i] - mx) * (ys[i] - my), sxx += (xs[i] - mx) * (xs[i] - mx);
    return sxy / sxx;
}

}  // namespace

TEST(StepRules, EulerAndLeftEndExponentialAreFirstOrder) {
    EXPECT_NEAR(convergenceOrder(StepRule::euler), 1.0, 0.1);
    EXPECT_NEAR(convergenceOrder(StepRule::exponential), 1.0, 0.1);
}

TEST(StepRules, MidpointExponentialIsSecondOrder) {
    EXPECT_NEAR(convergenceOrder(StepRule::midpointExponential), 2.0, 0.1);
}

// Constant μ and q: both exponential rules give the closed form at any step count; Euler does not.
TEST(StepRules, ExponentialStepIsExactInAHomogeneousMedium) {
    struct Constant {
        double mu(double) const { return 2.5; }
        double q(double) const { return 0.7; }
    } m;
    const double closed = radiance(5.0, 2.5, 0.7, 0.5);
    for (uint32_t n : {1u, 2u, 7u, 64u}) {
        EXPECT_NEAR(marchBackToFront(m, 0.0, 0.5, n, StepRule::exponential, 5.0), closed, 1e-14 * n) << n;
        EXPECT_NEAR(marchBackToFront(m, 0.0, 0.5, n, StepRule::midpointExponential, 5.0), closed, 1e-14 * n) << n;
    }
    // Euler: (1 − μΔs)^4 = 0.223 where e^{−μs} = 0.287, times L_bg − q/μ = 4.72.
    EXPECT_GT(std::fabs(marchBackToFront(m, 0.0, 0.5, 4, StepRule::euler, 5.0) - closed), 0.1);
}

// μΔs > 2: Euler's factor 1 − μΔs is below −1, so the error grows geometrically and alternates in sign;
// the exponential step stays between 0 and the background for q = 0.
TEST(StepRules, EulerDivergesAboveMuDsOfTwo) {
    struct Absorbing {
        double mu(double) const { return 30.0; }
        double q(double) const { return 0.0; }
    } m;
    const double euler = marchBackToFront(m, 0.0, 1.0, 10, StepRule::euler, 1.0);  // μΔs = 3
    EXPECT_NEAR(euler, std::pow(-2.0, 10), 1e-9);
    const double stable = marchBackToFront(m, 0.0, 1.0, 20, StepRule::euler, 1.0);  // μΔs = 1.5
    EXPECT_LT(std::fabs(stable), 1e-6);
    const double exponential = marchBackToFront(m, 0.0, 1.0, 10, StepRule::exponential, 1.0);
    EXPECT_GE(exponential, 0.0);
    EXPECT_NEAR(exponential, std::exp(-30.0), 1e-20);
}

// A front-to-back march (the pixel shader's order, T carried along) gives the back-to-front
// exponential recurrence's value.
TEST(MarchState, FrontToBackEqualsBackToFront) {
    const SineMedium m;
    const uint32_t n = 50;
    const double t0 = 0.5, t1 = 2.5, ds = (t1 - t0) / n, L_bg = 0.25;
    MarchState<double> state;
    for (uint32_t i = 0; i < n; ++i) {
        const double s = t0 + (i + 0.5) * ds;
        state.addStep(m.mu(s), m.q(s), ds);
    }
    const double back = marchBackToFront(m, t0, t1, n, StepRule::midpointExponential, L_bg);
    EXPECT_NEAR(state.finish(L_bg), back, 1e-13);
    EXPECT_NEAR(state.transmittance, std::exp(-m.opticalDepth(t0, t1)), 1e-4);
}

// Stopping where T < ε drops at most ε·max(L_bg, sup q/μ) (march.hpp): checked at ε = 1e-2, 1e-3.
TEST(MarchState, EarlyTerminationStaysUnderItsBound) {
    const SineMedium m;  // q/μ ≤ (0.6 + 0.4)/(1.5 − 1) = 2
    const uint32_t n = 400;
    const double t0 = 0.0, t1 = 8.0, ds = (t1 - t0) / n, L_bg = 0.9, bound_ratio = 2.0;
    for (double epsilon : {1e-2, 1e-3}) {
        MarchState<double> full, cut;
        for (uint32_t i = 0; i < n; ++i) {
            const double s = t0 + (i + 0.5) * ds;
            full.addStep(m.mu(s), m.q(s), ds);
            if (cut.transmittance >= epsilon) cut.addStep(m.mu(s), m.q(s), ds);
        }
        const double dropped = full.finish(L_bg) - cut.radiance;  // the cut march adds no background
        EXPECT_GE(dropped, 0.0);
        EXPECT_LE(dropped, epsilon * std::max(L_bg, bound_ratio)) << epsilon;
        EXPECT_LT(cut.transmittance, epsilon);
    }
}

// Ratio tracking is unbiased: the mean of 20 000 estimates lies within 3 standard errors of e^{−τ}, for
// a tight and a loose majorant; the same seed gives the same bits.
TEST(RatioTracking, MeanIsWithinThreeStandardErrorsOfTheTransmittance) {
    const SineMedium m;
    const double t0 = 0.0, t1 = 1.5, exact = std::exp(-m.opticalDepth(t0, t1));
    auto mu = [&](double s) { return m.mu(s); };
    for (double mu_bar : {2.5, 6.0}) {
        SplitMix64 rng(12345);
        const int count = 20000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < count; ++i) {
            const double t = ratioTrackingTransmittance(mu, t0, t1, mu_bar, rng);
            EXPECT_TRUE(t >= 0.0 && t <= 1.0);
            sum += t, sum2 += t * t;
        }
        const double mean = sum / count, se = std::sqrt((sum2 / count - mean * mean) / count);
        EXPECT_LT(std::fabs(mean - exact), 3 * se) << "majorant " << mu_bar << " mean " << mean << " exact " << exact;
        EXPECT_GT(se, 0.0);
    }
    SplitMix64 a(7), b(7);
    EXPECT_EQ(ratioTrackingTransmittance(mu, t0, t1, 2.5, a), ratioTrackingTransmittance(mu, t0, t1, 2.5, b));
}

// On a homogeneous medium the march, the closed form and ratio tracking agree: the march exactly,
// ratio tracking (which then has no variance: every ratio is 1 − μ/μ̄ = 0 or the estimate is 1 − …) to
// its standard error.
TEST(RatioTracking, AgreesWithTheClosedFormInAHomogeneousMedium) {
    const double mu = 1.3, length = 0.8;
    SplitMix64 rng(99);
    double sum = 0, sum2 = 0;
    const int count = 20000;
    for (int i = 0; i < count; ++i) {
        const double t = ratioTrackingTransmittance([&](double) { return mu; }, 0.0, length, 2.0, rng);
        sum += t, sum2 += t * t;
    }
    const double mean = sum / count, se = std::sqrt((sum2 / count - mean * mean) / count);
    EXPECT_LT(std::fabs(mean - transmittance(mu, length)), 3 * se);
    MarchState<double> state;
    for (int i = 0; i < 8; ++i) state.addStep(mu, 0.0, length / 8);
    EXPECT_NEAR(state.transmittance, transmittance(mu, length), 1e-15);
}

namespace {

// The cells the ray crosses with positive length, by testing every cell in double: cells half-open,
// the last closed (majorant_grid.hpp). Cells whose stretch is shorter than `ambiguous` are returned in
// `unsure` instead (float rounding may count them either way).
void bruteForceCells(const GridFrame& g, glm::dvec3 o, glm::dvec3 d, double t0, double t1, double ambiguous,
                     std::set<std::tuple<int, int, int>>& sure, std::set<std::tuple<int, int, int>>& unsure) {
    for (int z = 0; z < g.dims.z; ++z)
        for (int y = 0; y < g.dims.y; ++y)
            for (int x = 0; x < g.dims.x; ++x) {
                const Box b = g.cellBox({x, y, z});
                double lo = t0, hi = t1;
                const int c[3] = {x, y, z};
                for (int a = 0; a < 3 && lo < hi; ++a) {
                    if (d[a] == 0.0) {
                        const bool inside = o[a] >= g.box.lo[a] && o[a] <= g.box.hi[a];
                        if (!inside || g.cellOf(a, float(o[a])) != c[a]) hi = lo;
                        continue;
                    }
                    double ta = (double(b.lo[a]) - o[a]) / d[a], tb = (double(b.hi[a]) - o[a]) / d[a];
                    if (ta > tb) std::swap(ta, tb);
                    lo = std::max(lo, ta), hi = std::min(hi, tb);
                }
                if (hi - lo > ambiguous) sure.insert({x, y, z});
                else if (hi - lo > -ambiguous) unsure.insert({x, y, z});
            }
}

std::vector<std::tuple<int, int, int>> walkCells(const GridFrame& g, glm::vec3 o, glm::vec3 d, float t0, float t1) {
    std::vector<std::tuple<int, int, int>> cells;
    float last_exit = -INFINITY;
    walkGrid(g, o, d, t0, t1, [&](const glm::ivec3& c, float enter, float exit) {
        EXPECT_LT(enter, exit);
        if (last_exit != -INFINITY) {
            EXPECT_EQ(enter, last_exit);  // contiguous, in order
        }
        last_exit = exit;
        cells.push_back({c.x, c.y, c.z});
        return true;
    });
    return cells;
}

}  // namespace

TEST(WalkGrid, VisitsExactlyTheCellsARandomRayCrosses) {
    const GridFrame g{{{-1.2f, -0.8f, -1.2f}, {1.2f, 1.2f, 1.2f}}, {16, 9, 13}};
    std::mt19937 rng(2026);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    for (int r = 0; r < 2000; ++r) {
        const glm::vec3 o{u(rng), u(rng), u(rng)};
        glm::vec3 d{u(rng), u(rng), u(rng)};
        if (r % 5 == 0) d[r % 3] = 0.0f;                       // parallel to a face
        if (r % 7 == 0) d = glm::vec3(0.0f), d[r % 3] = 1.0f;  // along an axis
        if (glm::length(d) == 0.0f) continue;
        const auto cells = walkCells(g, o, d, 0.0f, 10.0f);
        std::set<std::tuple<int, int, int>> sure, unsure;
        bruteForceCells(g, o, d, 0.0, 10.0, 1e-5, sure, unsure);
        std::set<std::tuple<int, int, int>> seen(cells.begin(), cells.end());
        EXPECT_EQ(seen.size(), cells.size()) << "a cell visited twice, ray " << r;
        for (const auto& c : sure) EXPECT_TRUE(seen.count(c)) << "missed a crossed cell, ray " << r;
        for (const auto& c : seen) EXPECT_TRUE(sure.count(c) || unsure.count(c)) << "visited a cell not crossed, ray " << r;
    }
}

// Unit cells on [0, 4]³: rays along faces and edges, and diagonals through cell corners, where the walk
// must take the half-open cell and step over the cells it only touches at a point.
TEST(WalkGrid, RaysAlongFacesAndThroughCorners) {
    const GridFrame g{{{0, 0, 0}, {4, 4, 4}}, {4, 4, 4}};
    using C = std::vector<std::tuple<int, int, int>>;
    EXPECT_EQ(walkCells(g, {-1, 1, 1.5f}, {1, 0, 0}, 0, 100), (C{{0, 1, 1}, {1, 1, 1}, {2, 1, 1}, {3, 1, 1}}));
    EXPECT_EQ(walkCells(g, {5, 1, 1.5f}, {-1, 0, 0}, 0, 100), (C{{3, 1, 1}, {2, 1, 1}, {1, 1, 1}, {0, 1, 1}}));
    EXPECT_EQ(walkCells(g, {-1, 2, 2}, {1, 0, 0}, 0, 100), (C{{0, 2, 2}, {1, 2, 2}, {2, 2, 2}, {3, 2, 2}}));
    EXPECT_EQ(walkCells(g, {-1, 4, 1.5f}, {1, 0, 0}, 0, 100), (C{{0, 3, 1}, {1, 3, 1}, {2, 3, 1}, {3, 3, 1}}));
    EXPECT_EQ(walkCells(g, {-1, -1, 0.5f}, {1, 1, 0}, 0, 100), (C{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 3, 0}}));
    EXPECT_EQ(walkCells(g, {5, 5, 0.5f}, {-1, -1, 0}, 0, 100), (C{{3, 3, 0}, {2, 2, 0}, {1, 1, 0}, {0, 0, 0}}));
    EXPECT_EQ(walkCells(g, {-1, -1, -1}, {1, 1, 1}, 0, 100), (C{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}));
    EXPECT_EQ(walkCells(g, {0.5f, 0.5f, 0.5f}, {1, 0, 0}, 0, 1.5f), (C{{0, 0, 0}, {1, 0, 0}}));  // starts inside, ends at t1
    EXPECT_TRUE(walkCells(g, {-1, 5, 1}, {1, 0, 0}, 0, 100).empty());                            // misses
    EXPECT_TRUE(walkCells(g, {1, 1, 1}, {0, 0, 0}, 0, 100).empty());                             // no direction
}

TEST(MajorantGrid, BoundsEverySampleAndIsZeroOnlyWhereTheFieldIs) {
    const auto balls = mediaSceneMetaballs();
    const MajorantGrid grid = makeMajorantGrid(mediaSceneBox(), {16, 16, 16},
                                               [&](const Box& b) { return metaballMajorant(balls, b); });
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    size_t empty = 0;
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const Box b = grid.frame.cellBox({x, y, z});
                const float bound = grid.at({x, y, z});
                empty += bound == 0.0f;
                for (int k = 0; k < 64; ++k) {
                    const glm::vec3 p = b.lo + (b.hi - b.lo) * glm::vec3(u(rng), u(rng), u(rng));
                    ASSERT_LE(metaballDensity(balls, p), bound) << x << "," << y << "," << z;
                }
            }
    // The scene's balls fill a part of the box: skipping has something to skip.
    EXPECT_GT(empty, 16u * 16 * 16 / 4);
    EXPECT_LT(empty, 16u * 16 * 16);
    EXPECT_THROW(makeMajorantGrid(mediaSceneBox(), {0, 4, 4}, [](const Box&) { return 1.0f; }), Error);
}

// The media scene's march (SCENES.md: 32 midpoint samples through the box, μ = 4ρ), with every sample
// and with the empty cells skipped, and with early termination in both: the same bits, ray by ray.
TEST(EmptySpaceSkipping, ChangesNoBit) {
    const auto balls = mediaSceneMetaballs();
    const Box box = mediaSceneBox();
    for (int cells : {4, 16, 64}) {
        const MajorantGrid grid = makeMajorantGrid(box, glm::ivec3(cells),
                                                   [&](const Box& b) { return 4.0f * metaballMajorant(balls, b); });
        size_t differing = 0, skipped_total = 0, rays = 0;
        const glm::vec3 eye{0.0f, 0.4f, 3.0f};
        for (int py = 0; py < 48; ++py)
            for (int px = 0; px < 64; ++px) {
                const glm::vec3 d = glm::normalize(glm::vec3((px - 31.5f) / 40.0f, (py - 23.5f) / 40.0f - 0.07f, -1.0f));
                const auto [t_near, t_far] = slabInterval(box, eye, d);
                const float t0 = std::fmax(t_near, 0.0f), t1 = t_far;
                if (!(t1 > t0)) continue;
                ++rays;
                const uint32_t n = 32;
                const float ds = (t1 - t0) / float(n);
                auto step = [&](MarchState<float>& state, uint32_t i) {
                    const glm::vec3 x = eye + d * (t0 + (float(i) + 0.5f) * ds);
                    const float mu = 4.0f * metaballDensity(balls, x);
                    state.addStep(mu, 0.9f * 0.6f * mu, ds);
                    return state.transmittance >= 1e-3f;
                };
                MarchState<float> every, skipping;
                for (uint32_t i = 0; i < n; ++i)
                    if (!step(every, i)) break;
                uint32_t visited = 0;
                forEachOccupiedSample(grid, eye, d, t0, ds, n, [&](uint32_t i, const glm::ivec3&) {
                    ++visited;
                    return step(skipping, i);
                });
                skipped_total += n - visited;
                differing += std::memcmp(&every, &skipping, sizeof every) != 0;
            }
        EXPECT_EQ(differing, 0u) << cells << "³ cells";
        EXPECT_GT(skipped_total, rays * 4) << cells << "³ cells skip little";  // most samples lie in empty space
    }
}
