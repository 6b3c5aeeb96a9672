// raster bench fog-accuracy: see bench_fog_accuracy.hpp and docs/ACCURACY.md, "Participating media".
//
// Each case of the grid is evaluated in float by every form and in long double by
// media/reference.hpp. Its error is |v − ref| in ulps of float at ref, less an absolute floor that no
// float result can be blamed for (2⁻¹²⁶, below which the fast exp flushes to 0, and for the height
// fog's radiance 2⁻¹²⁶·(1 + q), what a τ flushed to 0 loses of q·τ; media_test.cpp's tolerance has
// the same floor). The ulp of float at a reference below FLT_MIN is FLT_MIN's, 2⁻¹⁴⁹. A NaN, an ∞
// where the exact value is a float, and a finite value where it is ∞ are counted apart, not as ulps.
// κ, the reference's relative condition number (reference::relativeCondition: how many ulps of the
// result one ulp of rounding in each input moves it), scales the error for the column a stable form
// is judged by: max ulps/(1 + κ), and the share within 8·(1 + κ) ulps (the tests' bound).
#include "bench_fog_accuracy.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "fog_forms.hpp"
#include "raster/check.hpp"
#include "raster/media/exprel.hpp"
#include "raster/media/height_fog.hpp"
#include "raster/media/homogeneous.hpp"
#include "raster/media/reference.hpp"
#include "raster/shader_context.hpp"
#include "raster/simd.hpp"

namespace raster::tools {
namespace {

using media::reference::Real;
using Grid = media::reference::AdversarialGrid;

constexpr double kWrong = 1e30;  // the recorded error of a NaN or of an ∞ on the wrong side of FLT_MAX
constexpr double kUlps = 8;      // the tests' bound: 8 ulps·(1 + κ)
constexpr Real kFlushFloor = 0x1p-126L;

// max(|v − ref| − floor, 0) in ulps of float at ref (header), kWrong for a NaN or a misplaced ∞.
double ulpsOff(float v, Real ref, Real floor) {
    if (std::isnan(v) || std::isnan(ref)) return kWrong;
    const float rounded = float(ref);  // ±∞ where ref is past float's range
    if (std::isinf(v)) return v == rounded ? 0 : kWrong;
    if (std::isinf(ref)) return kWrong;
    int e = 0;
    std::frexp(std::max(std::fabs(ref), Real(FLT_MIN)), &e);
    return double(std::max(std::fabs(Real(v) - ref) - floor, 0.0L) / std::ldexp(1.0L, e - 24));
}

struct Tally {
    std::vector<double> finite;  // ulps of each case without a NaN or a misplaced ∞
    int cases = 0, nan = 0, infinite = 0, within = 0;
    int wrongAtInfinity = 0;  // of nan + infinite, those at s = ∞ (the sky)
    double worstScaled = 0;  // max ulps/(1 + κ)

    // Returns the case's error in ulps (kWrong for a NaN or a misplaced ∞).
    double add(float v, Real ref, Real kappa, Real floor, bool atInfinity) {
        ++cases;
        const double ulps = ulpsOff(v, ref, floor);
        if (ulps >= kWrong) {
            ++(std::isnan(v) ? nan : infinite);
            wrongAtInfinity += atInfinity;
            return ulps;
        }
        finite.push_back(ulps);
        const double scaled = ulps / (1 + double(kappa));
        worstScaled = std::max(worstScaled, scaled);
        within += scaled <= kUlps;
        return ulps;
    }
    double worst() const { return finite.empty() ? 0 : *std::max_element(finite.begin(), finite.end()); }
    double median() {
        if (finite.empty()) return 0;
        std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
        return finite[finite.size() / 2];
    }
};

struct Row {
    std::string quantity, form;
    Tally tally;
};

// One point of the plot: the worst error over the grid's other axes at one value of the x axis.
struct Point {
    std::string panel, form;
    double x, ulps;
};

template <size_t N>
struct Form {
    const char* name;
    std::function<float(const std::array<float, N>&)> evaluate;
};

template <size_t N>
struct Quantity {
    const char* name;
    const char* panel;  // the plot's panel, by the grid's axis xAxis; nullptr: not plotted
    size_t xAxis;
    std::function<Real(const std::array<Real, N>&)> reference;
    std::function<Real(const std::array<float, N>&)> floor;
    std::vector<Form<N>> forms;
};

// Every combination of one value from each axis.
template <size_t N>
std::vector<std::array<float, N>> combinations(const std::array<std::vector<float>, N>& axes) {
    std::vector<std::array<float, N>> out(1);
    for (size_t a = 0; a < N; ++a) {
        std::vector<std::array<float, N>> next;
        for (const auto& partial : out)
            for (const float v : axes[a]) {
                next.push_back(partial);
                next.back()[a] = v;
            }
        out = std::move(next);
    }
    return out;
}

template <size_t N>
void measure(const Quantity<N>& q, const std::array<std::vector<float>, N>& axes, std::vector<Row>& rows,
             std::vector<Point>& points) {
    const size_t first = rows.size();
    std::vector<std::map<float, double>> worst_at(q.forms.size());
    for (const Form<N>& form : q.forms) rows.push_back({q.name, form.name, {}});
    for (const std::array<float, N>& in : combinations(axes)) {
        std::array<Real, N> exact_in;
        for (size_t i = 0; i < N; ++i) exact_in[i] = in[i];
        const Real ref = q.reference(exact_in);
        const Real kappa = media::reference::relativeCondition(q.reference, exact_in);
        const Real floor = q.floor(in);
        for (size_t f = 0; f < q.forms.size(); ++f) {
            const double ulps = rows[first + f].tally.add(q.forms[f].evaluate(in), ref, kappa, floor,
                                                              std::isinf(in[N - 1]));
            double& w = worst_at[f][in[q.xAxis]];
            w = std::max(w, ulps);
        }
    }
    if (!q.panel) return;
    for (size_t f = 0; f < q.forms.size(); ++f)
        for (const auto& [x, ulps] : worst_at[f]) points.push_back({q.panel, q.forms[f].name, x, ulps});
}

std::vector<float> axis(const auto& values, bool quick) {
    std::vector<float> out;
    const size_t n = std::size(values);
    for (size_t i = 0; i < n; ++i)
        if (!quick || i % 2 == 0 || i + 1 == n) out.push_back(values[i]);
    return out;
}

Real noFloor(const auto&) {
    return kFlushFloor;
}

Quantity<4> homogeneousRadiance() {
    Quantity<4> q{"homogeneous L", "homogeneous", 1,
                  [](const std::array<Real, 4>& x) { return media::reference::radiance(x[0], x[1], x[2], x[3]); },
                  noFloor<std::array<float, 4>>,
                  {}};
    q.forms = {{"raster", [](const auto& x) { return media::radiance(x[0], x[1], x[2], x[3]); }},
               {"lecture", [](const auto& x) { return fog_forms::lectureRadiance(x[0], x[1], x[2], x[3]); }},
               {"floor", [](const auto& x) { return fog_forms::flooredRadiance(x[0], x[1], x[2], x[3]); }}};
    return q;
}

Quantity<4> heightFogOpticalDepth() {
    Quantity<4> q{"height-fog tau", nullptr, 0,
                  [](const std::array<Real, 4>& x) {
                      return media::reference::heightFogOpticalDepth(x[0], x[1], x[2], x[3]);
                  },
                  noFloor<std::array<float, 4>>,
                  {}};
    q.forms = {
        {"raster", [](const auto& x) { return media::heightFogOpticalDepth(x[0], x[1], x[2], x[3]); }},
        {"unreal", [](const auto& x) { return fog_forms::unrealOpticalDepth(x[0], x[1], x[2], x[3]); }},
        {"lecture", [](const auto& x) { return fog_forms::lectureOpticalDepth(x[0], x[1], x[2], x[3]); }}};
    return q;
}

// Inputs L0, σ0, q, b, y0, dy, s. Unreal's τ and the floor are each combined with what the other
// form has of raster's, so that each row shows the one scheme's effect.
Quantity<7> heightFogRadiance() {
    Quantity<7> q{"height-fog L", "height-fog", 1,
                  [](const std::array<Real, 7>& x) {
                      return media::reference::heightFogRadiance(x[0], x[1], x[2], x[3], x[4], x[5], x[6]);
                  },
                  [](const std::array<float, 7>& x) { return kFlushFloor * (1 + Real(x[2])); },
                  {}};
    auto tau = [](const auto& x) { return media::heightFogOpticalDepth(x[3], x[4], x[5], x[6]); };
    q.forms = {{"raster", [tau](const auto& x) { return media::radiance(x[0], x[1], x[2], tau(x)); }},
               {"unreal",
                [](const auto& x) {
                    return media::radiance(x[0], x[1], x[2], fog_forms::unrealOpticalDepth(x[3], x[4], x[5], x[6]));
                }},
               {"floor", [tau](const auto& x) { return fog_forms::flooredRadiance(x[0], x[1], x[2], tau(x)); }},
               {"lecture",
                [](const auto& x) {
                    return fog_forms::lectureHeightRadiance(x[0], x[1], x[2], x[3], x[4], x[5], x[6]);
                }},
               {"slide",
                [](const auto& x) {
                    return fog_forms::slideHeightRadiance(x[0], x[1], x[2], x[3], x[4], x[5], x[6]);
                }}};
    return q;
}

// τ along rays straight up and straight down through unit falloff (b = 1, y0 = 0, dy = ±1) over
// 400 distances s from 1e-8 to 80 m, log-spaced: φ(±s)·s, where Unreal's Taylor switch (|F| = 0.01
// in base 2: s = 0.0069) and the direct form's cancellation show. The worse of the two directions.
void sweepOpticalDepth(std::vector<Point>& points) {
    constexpr int kSteps = 400;
    std::map<std::string, std::vector<Point>> by_form;  // each form's line in one block of rows
    for (int i = 0; i <= kSteps; ++i) {
        const float s = float(std::pow(10.0, -8.0 + 9.90309 * i / kSteps));  // to 80 = 10^1.90309
        std::map<std::string, double> worst;
        for (const float dy : {1.0f, -1.0f}) {
            const Real ref = media::reference::heightFogOpticalDepth(1, 0, dy, s);
            auto err = [&](const char* name, float v) {
                worst[name] = std::max(worst[name], ulpsOff(v, ref, kFlushFloor));
            };
            err("raster", media::heightFogOpticalDepth(1.0f, 0.0f, dy, s));
            err("unreal", fog_forms::unrealOpticalDepth(1.0f, 0.0f, dy, s));
            err("lecture", fog_forms::lectureOpticalDepth(1.0f, 0.0f, dy, s));
        }
        for (const auto& [form, ulps] : worst) by_form[form].push_back({"tau-sweep", form, double(s), ulps});
    }
    for (const auto& [form, line] : by_form) points.insert(points.end(), line.begin(), line.end());
}

// ---- Every float: ψ ---------------------------------------------------------------------------

// ψ's error at every finite float x of both signs: raster's float and Float8 (the same bits, checked),
// and the reference pipeline's (the C library's expm1), against reference::psi. φ(z) = ψ(−z) is
// the same evaluation (exprel.hpp), so this covers φ too.
struct PsiSweep {
    static constexpr int kBins = 2048;  // 1/256 ulp each, up to 8 ulps
    double worst[2] = {0, 0};           // fast, reference pipeline
    float worstAt[2] = {0, 0};
    uint64_t count = 0, nan = 0, laneMismatches = 0;
    std::vector<uint64_t> histogram[2] = {std::vector<uint64_t>(kBins + 1), std::vector<uint64_t>(kBins + 1)};

    void add(int which, float x, double ulps) {
        if (ulps > worst[which]) worst[which] = ulps, worstAt[which] = x;
        ++histogram[which][std::min<size_t>(size_t(ulps * 256), kBins)];
    }
    void merge(const PsiSweep& o) {
        for (int w = 0; w < 2; ++w) {
            if (o.worst[w] > worst[w]) worst[w] = o.worst[w], worstAt[w] = o.worstAt[w];
            for (int b = 0; b <= kBins; ++b) histogram[w][b] += o.histogram[w][b];
        }
        count += o.count, nan += o.nan, laneMismatches += o.laneMismatches;
    }
    double median(int which) const {
        uint64_t seen = 0;
        for (int b = 0; b <= kBins; ++b)
            if ((seen += histogram[which][b]) * 2 >= count) return (b + 0.5) / 256;
        return INFINITY;
    }
};

// The floats with bit patterns [lo, hi), each with both signs.
void sweepPsi(uint32_t lo, uint32_t hi, PsiSweep& out) {
    for (uint32_t base = lo; base < hi; base += 4) {
        Float8 x8;
        for (int j = 0; j < 8; ++j)
            x8.set(j, (j < 4 ? 1.0f : -1.0f) * std::bit_cast<float>(std::min(base + uint32_t(j % 4), hi - 1)));
        const Float8 fast8 = media::psi(x8);
        for (int j = 0; j < 8; ++j) {
            if (base + uint32_t(j % 4) >= hi) continue;
            const float x = x8[j];
            detail::tReferenceMode = false;
            const float fast = media::psi(x);
            detail::tReferenceMode = true;
            const float library = media::psi(x);
            detail::tReferenceMode = false;
            out.laneMismatches += std::bit_cast<uint32_t>(fast) != std::bit_cast<uint32_t>(fast8[j]);
            ++out.count;
            out.nan += std::isnan(fast) || std::isnan(library);
            const Real ref = media::reference::psi(x);
            out.add(0, x, ulpsOff(fast, ref, 0));
            out.add(1, x, ulpsOff(library, ref, 0));
        }
    }
}

PsiSweep sweepEveryFloat(unsigned threads) {
    constexpr uint32_t kEnd = 0x7F800000u, kChunk = 1u << 20;  // every finite float's bits
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<uint32_t> next{0};
    std::vector<PsiSweep> parts(threads);
    std::vector<std::thread> workers;
    for (unsigned t = 0; t < threads; ++t)
        workers.emplace_back([&, t] {
            for (uint32_t lo; (lo = next.fetch_add(kChunk)) < kEnd;) sweepPsi(lo, std::min(kEnd, lo + kChunk), parts[t]);
        });
    PsiSweep total;
    for (unsigned t = 0; t < threads; ++t) {
        workers[t].join();
        total.merge(parts[t]);
    }
    return total;
}

void reportPsiSweep(const FogAccuracyOptions& options, std::FILE* csv) {
    const auto t0 = std::chrono::steady_clock::now();
    const PsiSweep sweep = sweepEveryFloat(options.threads);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const char* names[2] = {"raster (float, Float8)", "raster (reference pipeline)"};
    std::printf("\npsi at every finite float, both signs: %llu arguments, %.0f s; Float8 lanes differing from "
                "float: %llu; NaN: %llu\n",
                (unsigned long long)sweep.count, seconds, (unsigned long long)sweep.laneMismatches,
                (unsigned long long)sweep.nan);
    for (int w = 0; w < 2; ++w) {
        std::printf("  %-28s max %.3f ulp (at %.9g), median %.3f ulp\n", names[w], sweep.worst[w],
                    double(sweep.worstAt[w]), sweep.median(w));
        if (csv)
            std::fprintf(csv, "psi every float,%s,%llu,%llu,0,0,%.4g,%.4g,%.4g,%.6f\n", names[w],
                         (unsigned long long)sweep.count, (unsigned long long)sweep.nan, sweep.worst[w],
                         sweep.median(w), sweep.worst[w], sweep.worst[w] <= kUlps ? 1.0 : 0.0);
    }
}

// ---- Output -------------------------------------------------------------------------------------

std::string ulpText(double ulps) {
    char text[32];
    std::snprintf(text, sizeof text, ulps < 1e4 ? "%.2f" : "%.2g", ulps);
    return text;
}

void printRows(std::vector<Row>& rows, std::FILE* csv) {
    std::printf("| quantity | form | cases | NaN | ∞ misplaced | of these at s = ∞ | max ulp | median ulp | "
                "max ulp/(1 + κ) | within 8·(1 + κ) ulp |\n|---|---|---|---|---|---|---|---|---|---|\n");
    if (csv)
        std::fprintf(csv, "quantity,form,cases,nan,infinite,wrong_at_infinity,max_ulp,median_ulp,"
                          "max_ulp_per_condition,share_within_8_ulp_condition\n");
    for (Row& r : rows) {
        Tally& t = r.tally;
        const double worst = t.worst(), median = t.median(), share = double(t.within) / t.cases;
        std::printf("| %s | %s | %d | %d | %d | %d | %s | %s | %s | %.2f %% |\n", r.quantity.c_str(),
                    r.form.c_str(), t.cases, t.nan, t.infinite, t.wrongAtInfinity, ulpText(worst).c_str(),
                    ulpText(median).c_str(), ulpText(t.worstScaled).c_str(), 100 * share);
        if (csv)
            std::fprintf(csv, "%s,%s,%d,%d,%d,%d,%.4g,%.4g,%.4g,%.6f\n", r.quantity.c_str(), r.form.c_str(),
                         t.cases, t.nan, t.infinite, t.wrongAtInfinity, worst, median, t.worstScaled, share);
    }
}

// The plot: three panels, the error in ulps (a NaN or misplaced ∞ drawn at the top line) against the
// homogeneous medium's μ, the distance of the τ sweep, and the height fog's σ0.
constexpr const char* kPlotScript = R"gp(# Drawn by raster bench fog-accuracy from fog-accuracy-points.csv: gnuplot fog-accuracy.gp
set terminal pngcairo size 1500,460 font "DejaVu Sans,10"
set output "fog-accuracy.png"
set datafile separator ","
set multiplot layout 1,3
set logscale xy
set grid
set yrange [0.5:3e13]
set ytics ("0" 1, "10" 11, "10^3" 1001, "10^6" 1e6, "10^9" 1e9, "NaN, ∞" 1e13)
set ylabel "worst error in float ulps, 1 + ulps"
set key top right
y(e) = e >= 1e29 ? 1e13 : (e > 1e12 ? 1e12 : 1 + e)
pick(p, f) = (strcol(1) eq p && strcol(2) eq f)
# μ = 0 and σ0 = 0 are drawn at 1e-35.
x0(x) = x == 0 ? 1e-35 : x
set xrange [3e-36:3e31]
set format x "10^{%L}"
set xlabel "extinction μ, 1/m (0 at the left edge)"
set title "Homogeneous L, worst over q, L0, s"
plot for [f in "raster lecture floor"] "fog-accuracy-points.csv" using (pick("homogeneous", f) ? x0($3) : NaN):(y($4)) with linespoints pt 7 title f
set xrange [1e-8:100]
set format x "10^{%L}"
set xlabel "distance s, m (b = 1, y0 = 0, dy = ±1)"
set title "Height fog τ along a ray, worse of up and down"
plot for [f in "raster unreal lecture"] "fog-accuracy-points.csv" using (pick("tau-sweep", f) ? $3 : NaN):(y($4)) with lines lw 2 title f
set xrange [3e-36:3e31]
set key center right
set xlabel "extinction σ0, 1/m (0 at the left edge)"
set title "Height-fog L, worst over q, L0, b, y0, dy, s"
plot for [f in "raster unreal floor lecture slide"] "fog-accuracy-points.csv" using (pick("height-fog", f) ? x0($3) : NaN):(y($4)) with linespoints pt 7 title f
unset multiplot
)gp";

// Runs gnuplot on the script in `dir`; false where it is not installed or fails.
bool drawPlot(const std::string& dir) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
    char program[] = "gnuplot", script[] = "fog-accuracy.gp";
    char* argv[] = {program, script, nullptr};
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, program, &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    int status = 0;
    return spawned == 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void writePlot(const std::string& dir, const std::vector<Point>& points) {
    std::FILE* f = std::fopen((dir + "/fog-accuracy-points.csv").c_str(), "w");
    RASTER_REQUIRE(f, BadFile, "cannot write " + dir + "/fog-accuracy-points.csv");
    std::fprintf(f, "panel,form,x,error_ulp\n");
    for (const Point& p : points)
        std::fprintf(f, "%s,%s,%.9g,%.6g\n", p.panel.c_str(), p.form.c_str(), p.x, p.ulps);
    std::fclose(f);
    std::ofstream(dir + "/fog-accuracy.gp") << kPlotScript;
    if (drawPlot(dir))
        std::printf("\nwrote %s/fog-accuracy.png\n", dir.c_str());
    else
        std::printf("\ngnuplot is not installed or failed: the plot's script is %s/fog-accuracy.gp\n", dir.c_str());
}

}  // namespace

int runFogAccuracyBench(const FogAccuracyOptions& options) {
    const bool quick = options.quick;
    std::vector<Row> rows;
    std::vector<Point> points;
    measure(homogeneousRadiance(),
            {axis(Grid::kSurface, quick), axis(Grid::kExtinction, quick), axis(Grid::kSource, quick),
             axis(Grid::kDistance, quick)},
            rows, points);
    const std::array<std::vector<float>, 4> ray = {axis(Grid::kFalloff, quick), axis(Grid::kHeight, quick),
                                                   axis(Grid::kDirectionY, quick), axis(Grid::kDistance, quick)};
    measure(heightFogOpticalDepth(), ray, rows, points);
    measure(heightFogRadiance(),
            {axis(Grid::kSurface, quick), axis(Grid::kExtinction, quick), axis(Grid::kSource, quick), ray[0],
             ray[1], ray[2], ray[3]},
            rows, points);
    sweepOpticalDepth(points);

    std::FILE* csv = nullptr;
    if (!options.outDir.empty()) {
        std::filesystem::create_directories(options.outDir);
        csv = std::fopen((options.outDir + "/fog-accuracy.csv").c_str(), "w");
        RASTER_REQUIRE(csv, BadFile, "cannot write " + options.outDir + "/fog-accuracy.csv");
    }
    std::printf("Adversarial grid%s (media/reference.hpp), float against long double:\n\n", quick ? ", every other value" : "");
    printRows(rows, csv);
    if (options.exhaustive) reportPsiSweep(options, csv);
    if (csv) std::fclose(csv);
    if (!options.outDir.empty()) writePlot(options.outDir, points);
    return 0;
}

}  // namespace raster::tools
