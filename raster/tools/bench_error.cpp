// raster bench error [--out-dir D] [--rays N] [--seed S]: each media integrator and step count, and the
// other accuracy knobs, timed and measured on a seeded set of rays against a float64 reference.
//
// Media (one value per ray: the green channel, so that errors read in display units, 0.5/255 and up):
//   metaball     rays from the `media` scene's eye to random points of its six balls, with its light:
//                μ = 4·ρ(x), q = μ·albedo·(p(cos θ)·e^{−τ_l}·E + A), τ_l by a 32-step midpoint shadow
//                ray in double (part of the medium's definition here: only the view ray is swept).
//   smooth       μ(s) = μ0·(1 + 0.8·sin(2πs/λ + φ)), q = μ·(1 + 0.5·cos s) over 4 m, random μ0, λ, φ.
//   homogeneous  constant μ ∈ [0.5, 3]/m and q = μ over 1..4 m: the closed form is the answer.
// L_bg = 0.10 behind each ray. Reference: the midpoint exponential march with 2^16 steps in double
// (second order: its error is below 1e-9 here); the closed form for homogeneous.
// Rows: euler, exponential (left end), midpoint at 4..1024 steps; analytic; ratio tracking's
// transmittance (quantity T, against e^{−∫μ} from the reference march) at 1..256 samples; and for
// metaball the knobs of the float march the scene uses: majorant grid 4³..64³ (error the same bits
// as no skipping), early termination 1e-1..1e-4, raster::exp against std::exp.
// Time: median over repeats of the whole ray set, per ray (steady_clock). Pareto: a row no other row
// of its medium and quantity beats in both time and max error.
#include "bench_error.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <numbers>
#include <vector>

#include "raster/check.hpp"
#include "raster/media/march.hpp"
#include "raster/media/metaball_march.hpp"
#include "raster/media/ratio_tracking.hpp"

namespace raster::tools {
namespace {

using media::StepRule;

// A ray through the metaball medium, in double, counting its density evaluations.
struct MetaballRay {
    const media::MetaballVolume* volume = nullptr;
    glm::dvec3 o{0.0}, d{0.0}, toLight{0.0};
    double phase = 0.0, sun = 0.0, ambient = 0.0, albedo = 0.0;
    mutable uint64_t evaluations = 0;
    static constexpr int kShadowSteps = 32;

    double muAt(const glm::dvec3& x) const {
        ++evaluations;
        double rho = 0.0;
        for (const media::Metaball& b : volume->balls) {
            const glm::dvec3 v = x - glm::dvec3(b.centre);
            const double u = glm::dot(v, v) / (double(b.radius) * b.radius);
            if (u < 1.0) rho += (1.0 - u) * (1.0 - u);
        }
        return volume->extinctionScale * rho;
    }
    double mu(double s) const { return muAt(o + d * s); }
    double q(double s) const {
        const glm::dvec3 x = o + d * s;
        const double m = muAt(x);
        if (m == 0.0) return 0.0;
        const auto [lo, hi] = media::slabInterval(volume->box, glm::vec3(x), glm::vec3(toLight));
        const double dl = std::max(double(hi), 0.0) / kShadowSteps;
        double tau = 0.0;
        for (int j = 0; j < kShadowSteps; ++j) tau += muAt(x + toLight * ((j + 0.5) * dl)) * dl;
        return m * albedo * (phase * std::exp(-tau) * sun + ambient);
    }
};

struct SmoothRay {
    double mu0 = 1.0, lambda = 1.0, phi = 0.0;
    mutable uint64_t evaluations = 0;
    double mu(double s) const {
        ++evaluations;
        return mu0 * (1.0 + 0.8 * std::sin(2.0 * std::numbers::pi * s / lambda + phi));
    }
    double q(double s) const { return mu(s) * (1.0 + 0.5 * std::cos(s)); }
};

struct HomogeneousRay {
    double m = 1.0;
    mutable uint64_t evaluations = 0;
    double mu(double) const { return ++evaluations, m; }
    double q(double) const { return ++evaluations, m; }
};

constexpr double kBackground = 0.10;
constexpr double kReferenceSteps = 65536;

template <class Ray>
struct RaySet {
    std::vector<Ray> rays;
    std::vector<double> t0, t1, referenceL, referenceT, majorant;
};

struct Row {
    std::string medium, quantity, integrator, knob;
    uint32_t steps = 0;
    double timeUs = 0, evaluations = 0, maxErr = 0, rmsErr = 0;
    bool pareto = false;
};

// Median over `repeats` of the time for all rays, per ray (µs); `value(k)` returns ray k's estimate.
// Fills the row's errors against `reference` and the evaluations per ray (`counter` summed).
void measure(Row& row, size_t n, uint32_t repeats, const std::vector<double>& reference,
             const std::function<double(size_t)>& value, const std::function<uint64_t()>& counter) {
    std::vector<double> times, values(n);
    uint64_t evals = 0;
    for (uint32_t r = 0; r < repeats; ++r) {
        const uint64_t before = counter();
        const auto start = std::chrono::steady_clock::now();
        for (size_t k = 0; k < n; ++k) values[k] = value(k);
        times.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
        evals = counter() - before;
    }
    std::sort(times.begin(), times.end());
    row.timeUs = times[times.size() / 2] / double(n);
    row.evaluations = double(evals) / double(n);
    double sum2 = 0;
    for (size_t k = 0; k < n; ++k) {
        const double e = std::abs(values[k] - reference[k]);
        row.maxErr = std::max(row.maxErr, std::isfinite(e) ? e : INFINITY);
        sum2 += e * e;
    }
    row.rmsErr = std::sqrt(sum2 / double(n));
}

template <class Ray>
uint64_t totalEvaluations(const RaySet<Ray>& set) {
    uint64_t n = 0;
    for (const Ray& r : set.rays) n += r.evaluations;
    return n;
}

template <class Ray>
void fillReference(RaySet<Ray>& set) {
    for (size_t k = 0; k < set.rays.size(); ++k) {
        const Ray& r = set.rays[k];
        set.referenceL.push_back(media::marchBackToFront(r, set.t0[k], set.t1[k], uint32_t(kReferenceSteps),
                                                         StepRule::midpointExponential, kBackground));
        const double ds = (set.t1[k] - set.t0[k]) / kReferenceSteps;
        double tau = 0.0;
        for (uint32_t i = 0; i < uint32_t(kReferenceSteps); ++i) tau += r.mu(set.t0[k] + (i + 0.5) * ds) * ds;
        set.referenceT.push_back(std::exp(-tau));
    }
}

// The marching integrators at 4..1024 steps and ratio tracking at 1..256 samples.
template <class Ray>
void sweepIntegrators(const char* medium, RaySet<Ray>& set, const ErrorBenchArgs& args, std::vector<Row>& rows) {
    const size_t n = set.rays.size();
    auto counter = [&] { return totalEvaluations(set); };
    for (StepRule rule : {StepRule::euler, StepRule::exponential, StepRule::midpointExponential})
        for (uint32_t steps = 4; steps <= 1024; steps *= 2) {
            Row row{medium, "L", media::stepRuleName(rule), "-", steps};
            measure(row, n, args.repeats, set.referenceL, [&](size_t k) {
                return media::marchBackToFront(set.rays[k], set.t0[k], set.t1[k], steps, rule, kBackground);
            }, counter);
            rows.push_back(row);
        }
    for (uint32_t samples = 1; samples <= 256; samples *= 4) {
        Row row{medium, "T", "ratio-tracking", "-", samples};
        media::SplitMix64 rng(args.seed * 7919 + samples);
        measure(row, n, args.repeats, set.referenceT, [&](size_t k) {
            double sum = 0;
            auto mu = [&](double s) { return set.rays[k].mu(s); };
            for (uint32_t j = 0; j < samples; ++j)
                sum += media::ratioTrackingTransmittance(mu, set.t0[k], set.t1[k], set.majorant[k], rng);
            return sum / samples;
        }, counter);
        rows.push_back(row);
    }
}

// The float march of the `media` scene (metaball_march.hpp) over the metaball rays, its value L + T·L_bg.
double sceneMarch(const media::MetaballVolume& v, const media::VolumeLight& light, const media::MarchSettings& s,
                  const MetaballRay& r, uint64_t& evaluations) {
    const media::MarchResult m = media::marchMetaballs(v, light, s, glm::vec3(r.o), glm::vec3(r.d));
    evaluations += m.densityEvaluations;
    return double(m.radiance.y) + double(m.transmittance) * kBackground;
}

// The float march's knobs on the metaball rays: majorant grid size (bits against no skipping), the C
// library's exp in place of raster::exp; and early termination of the double midpoint march.
void sweepKnobs(RaySet<MetaballRay>& set, const ErrorBenchArgs& args, std::vector<Row>& rows) {
    const size_t n = set.rays.size();
    const media::VolumeLight light = media::mediaSceneLight();
    uint64_t evals = 0;
    auto counter = [&] { return evals; };
    media::MarchSettings settings{256, MetaballRay::kShadowSteps, media::SkipMethod::none};
    std::vector<double> none(n);
    for (size_t k = 0; k < n; ++k) none[k] = sceneMarch(*set.rays[k].volume, light, settings, set.rays[k], evals);
    settings.skip = media::SkipMethod::grid;
    for (int cells = 4; cells <= 64; cells *= 2) {
        const media::MetaballVolume v = media::makeMetaballVolume(set.rays[0].volume->balls, set.rays[0].volume->box,
                                                                  set.rays[0].volume->extinctionScale, cells);
        Row row{"metaball", "L", "scene-march", "grid=" + std::to_string(cells), settings.steps};
        measure(row, n, args.repeats, set.referenceL,
                [&](size_t k) { return sceneMarch(v, light, settings, set.rays[k], evals); }, counter);
        bool same = true;
        for (size_t k = 0; k < n; ++k) same = same && sceneMarch(v, light, settings, set.rays[k], evals) == none[k];
        row.knob += same ? ";same-bits-as-none" : ";DIFFERS-from-none";
        rows.push_back(row);
    }
    settings.skip = media::SkipMethod::balls;
    for (bool library_exp : {false, true}) {
        Row row{"metaball", "L", "scene-march", library_exp ? "exp=std" : "exp=raster", settings.steps};
        detail::tReferenceMode = library_exp;
        measure(row, n, args.repeats, set.referenceL,
                [&](size_t k) { return sceneMarch(*set.rays[k].volume, light, settings, set.rays[k], evals); },
                counter);
        detail::tReferenceMode = false;
        rows.push_back(row);
    }
    for (double threshold : {1e-1, 1e-2, 1e-3, 1e-4, 0.0}) {
        char knob[32];
        std::snprintf(knob, sizeof knob, "terminate<%g", threshold);
        Row row{"metaball", "L", "midpoint", knob, 256};
        measure(row, n, args.repeats, set.referenceL, [&](size_t k) {
            const MetaballRay& r = set.rays[k];
            const double ds = (set.t1[k] - set.t0[k]) / 256;
            media::MarchState<double> state;
            for (uint32_t i = 0; i < 256 && state.transmittance >= threshold; ++i) {
                const double s = set.t0[k] + (i + 0.5) * ds;
                state.addStep(r.mu(s), r.q(s), ds);
            }
            return state.finish(kBackground);
        }, [&] { return totalEvaluations(set); });
        rows.push_back(row);
    }
}

RaySet<MetaballRay> metaballRays(const media::MetaballVolume& v, const ErrorBenchArgs& args) {
    const media::VolumeLight light = media::mediaSceneLight();
    const glm::dvec3 eye{0.0, 0.4, 3.0};  // the `media` scene's camera
    media::SplitMix64 rng(args.seed);
    RaySet<MetaballRay> set;
    for (uint32_t k = 0; k < args.rays; ++k) {
        const media::Metaball& b = v.balls[rng.next() % v.balls.size()];
        const glm::dvec3 jitter{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5};
        MetaballRay r;
        r.volume = &v, r.o = eye, r.d = glm::normalize(glm::dvec3(b.centre) + jitter * double(b.radius) - eye);
        r.toLight = glm::dvec3(light.toLight), r.sun = light.sun.y, r.ambient = light.ambient.y;
        r.albedo = light.albedo;
        r.phase = media::henyeyGreenstein(double(light.g), glm::dot(r.d, r.toLight));
        const auto [t_near, t_far] = media::slabInterval(v.box, glm::vec3(r.o), glm::vec3(r.d));
        set.rays.push_back(r);
        set.t0.push_back(std::max(double(t_near), 0.0)), set.t1.push_back(double(t_far));
        set.majorant.push_back(v.extinctionScale * double(v.balls.size()));  // each ball's term is at most 1
    }
    return set;
}

RaySet<SmoothRay> smoothRays(const ErrorBenchArgs& args) {
    media::SplitMix64 rng(args.seed + 1);
    RaySet<SmoothRay> set;
    for (uint32_t k = 0; k < args.rays; ++k) {
        SmoothRay r{0.5 + 1.5 * rng.uniform(), 0.5 + 1.5 * rng.uniform(), 2.0 * std::numbers::pi * rng.uniform()};
        set.rays.push_back(r), set.t0.push_back(0.0), set.t1.push_back(4.0), set.majorant.push_back(1.8 * r.mu0);
    }
    return set;
}

RaySet<HomogeneousRay> homogeneousRays(const ErrorBenchArgs& args) {
    media::SplitMix64 rng(args.seed + 2);
    RaySet<HomogeneousRay> set;
    for (uint32_t k = 0; k < args.rays; ++k) {
        const HomogeneousRay r{0.5 + 2.5 * rng.uniform()};
        const double length = 1.0 + 3.0 * rng.uniform();
        set.rays.push_back(r), set.t0.push_back(0.0), set.t1.push_back(length), set.majorant.push_back(r.m);
        set.referenceL.push_back(media::radiance(kBackground, r.m, r.m, length));
        set.referenceT.push_back(std::exp(-r.m * length));
    }
    return set;
}

void markPareto(std::vector<Row>& rows) {
    for (Row& a : rows) {
        a.pareto = true;
        for (const Row& b : rows)
            if (&a != &b && a.medium == b.medium && a.quantity == b.quantity && b.timeUs <= a.timeUs &&
                b.maxErr <= a.maxErr && (b.timeUs < a.timeUs || b.maxErr < a.maxErr))
                a.pareto = false;
    }
}

// The time at which an integrator's curve (rows in step order) first reaches `target`, interpolated
// log-log between the rows around it; negative: not reached.
double timeToReach(const std::vector<Row>& rows, const std::string& medium, const std::string& integrator,
                   double target) {
    const Row* previous = nullptr;
    for (const Row& r : rows) {
        if (r.medium != medium || r.integrator != integrator || r.knob != "-") continue;
        if (r.maxErr <= target) {
            if (!previous || !(previous->maxErr > 0) || !std::isfinite(previous->maxErr) || !(r.maxErr > 0))
                return r.timeUs;
            const double f = std::log(previous->maxErr / target) / std::log(previous->maxErr / r.maxErr);
            return std::exp(std::log(previous->timeUs) + f * std::log(r.timeUs / previous->timeUs));
        }
        previous = &r;
    }
    return -1.0;
}

void writeCsv(const std::vector<Row>& rows, const std::filesystem::path& path) {
    FILE* f = std::fopen(path.c_str(), "w");
    RASTER_REQUIRE(f != nullptr, BadFile, "raster bench error: cannot write " + path.string());
    std::fprintf(f, "medium,quantity,integrator,knob,steps,time_us,density_evals,max_err,rms_err,pareto\n");
    // Time and max error round-trip (%.17g): the Pareto marks were decided on these values, and a
    // reader re-checking them must see the same ones, not two rows rounded to a tie.
    for (const Row& r : rows)
        std::fprintf(f, "%s,%s,%s,%s,%u,%.17g,%.6g,%.17g,%.6g,%d\n", r.medium.c_str(), r.quantity.c_str(),
                     r.integrator.c_str(), r.knob.c_str(), r.steps, r.timeUs, r.evaluations, r.maxErr, r.rmsErr,
                     int(r.pareto));
    std::fclose(f);
}

// error.png from error.csv: per medium a log-log panel of time against max error, one line per
// integrator, the Pareto rows circled (errors below 1e-16 drawn at 1e-16).
void plot(const std::filesystem::path& dir) {
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
        std::printf("gnuplot not found: wrote %s only, no error.png (apt-get install gnuplot-nox)\n",
                    (dir / "error.csv").c_str());
        return;
    }
    const std::filesystem::path script = dir / "error.gp";
    FILE* f = std::fopen(script.c_str(), "w");
    RASTER_REQUIRE(f != nullptr, BadFile, "raster bench error: cannot write " + script.string());
    std::fprintf(f,
                 "set terminal pngcairo size 1600,560\nset output '%s'\nset datafile separator ','\n"
                 "set logscale xy\nset format xy '10^{%%L}'\nset xlabel 'time per ray (us)'\nset ylabel 'max error'\n"
                 "set key top right font ',9'\ne(x) = x < 1e-16 ? 1e-16 : x\nset multiplot layout 1,3\n",
                 (dir / "error.png").c_str());
    for (const char* medium : {"metaball", "smooth", "homogeneous"}) {
        std::fprintf(f, "set title '%s'\nplot ", medium);
        const char* sep = "";
        for (const char* integ : {"euler", "exponential", "midpoint", "ratio-tracking", "analytic", "scene-march"}) {
            std::fprintf(f,
                         "%s'%s' using (strcol(1) eq '%s' && strcol(3) eq '%s' && strcol(4) eq '-' ? $6 : NaN):"
                         "(e($8)) with linespoints title '%s'",
                         sep, (dir / "error.csv").c_str(), medium, integ, integ);
            sep = ", ";
        }
        std::fprintf(f,
                     ", '%s' using (strcol(1) eq '%s' && strcol(4) ne '-' ? $6 : NaN):(e($8)) with points pt 2 "
                     "title 'knobs', '%s' using (strcol(1) eq '%s' && $10 == 1 ? $6 : NaN):(e($8)) with points "
                     "pt 6 ps 2.5 lc rgb 'black' title 'Pareto'\n",
                     (dir / "error.csv").c_str(), medium, (dir / "error.csv").c_str(), medium);
    }
    std::fprintf(f, "unset multiplot\n");
    std::fclose(f);
    const std::string command = "gnuplot '" + script.string() + "'";
    if (std::system(command.c_str()) != 0) std::printf("gnuplot failed: no error.png\n");
    else std::printf("wrote %s\n", (dir / "error.png").c_str());
}

void printHeadline(const std::vector<Row>& rows) {
    std::printf("\n# time per ray (us) to reach a max error of: (-: not reached)\n%-12s %-15s %10s %10s %10s\n",
                "medium", "integrator", "1e-2", "0.5/255", "1e-3");
    for (const char* medium : {"metaball", "smooth", "homogeneous"})
        for (const char* integ : {"euler", "exponential", "midpoint", "ratio-tracking", "analytic"}) {
            std::printf("%-12s %-15s", medium, integ);
            for (double target : {1e-2, 0.5 / 255, 1e-3}) {
                const double t = timeToReach(rows, medium, integ, target);
                if (t < 0) std::printf(" %10s", "-");
                else std::printf(" %10.3g", t);
            }
            std::printf("\n");
        }
}

}  // namespace

int runErrorBench(const ErrorBenchArgs& args) {
    const std::filesystem::path dir(args.outDir);
    std::filesystem::create_directories(dir);
    std::vector<Row> rows;
    const media::MetaballVolume volume =
        media::makeMetaballVolume(media::mediaSceneMetaballs(), media::mediaSceneBox(), 4.0f, 16);
    RaySet<MetaballRay> metaball = metaballRays(volume, args);
    fillReference(metaball);
    sweepIntegrators("metaball", metaball, args, rows);
    sweepKnobs(metaball, args, rows);
    RaySet<SmoothRay> smooth = smoothRays(args);
    fillReference(smooth);
    sweepIntegrators("smooth", smooth, args, rows);
    RaySet<HomogeneousRay> homogeneous = homogeneousRays(args);
    sweepIntegrators("homogeneous", homogeneous, args, rows);
    Row analytic{"homogeneous", "L", "analytic", "-", 1};
    measure(analytic, homogeneous.rays.size(), args.repeats, homogeneous.referenceL, [&](size_t k) {
        const double m = homogeneous.rays[k].mu(0.0);
        return media::radiance(kBackground, m, homogeneous.rays[k].q(0.0), homogeneous.t1[k]);
    }, [&] { return totalEvaluations(homogeneous); });
    rows.push_back(analytic);
    markPareto(rows);
    std::printf("# raster bench error: %u rays per medium, seed %llu, median of %u repeats; reference: midpoint "
                "exponential, 2^16 steps, double (homogeneous: the closed form)\n",
                args.rays, (unsigned long long)args.seed, args.repeats);
    std::printf("%-12s %-2s %-15s %-28s %6s %10s %10s %10s %10s %s\n", "medium", "q", "integrator", "knob",
                "steps", "us/ray", "evals/ray", "max_err", "rms_err", "pareto");
    for (const Row& r : rows)
        std::printf("%-12s %-2s %-15s %-28s %6u %10.3g %10.4g %10.3g %10.3g %s\n", r.medium.c_str(),
                    r.quantity.c_str(), r.integrator.c_str(), r.knob.c_str(), r.steps, r.timeUs, r.evaluations,
                    r.maxErr, r.rmsErr, r.pareto ? "*" : "");
    printHeadline(rows);
    writeCsv(rows, dir / "error.csv");
    plot(dir);
    return 0;
}

}  // namespace raster::tools
