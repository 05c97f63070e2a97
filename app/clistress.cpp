// marbles-cli stress: numerical stability. Long runs and extreme parameters in every model; each
// row states what it expects, and the command exits 0 only when every row meets it.

#include "app/clicommon.h"
#include "core/diagnostics.h"
#include "core/presets.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>

namespace marbles::cli {

namespace {

constexpr double unbounded = std::numeric_limits<double>::infinity();

// What a row must show to pass.
struct Expect {
    bool blowsUp = false;            // the book's k > 2: must leave finite numbers, and be caught
    bool noEscapes = true;           // with walls on, every centre stays on the stage
    double maxOverlapPx = unbounded; // largest penetration seen (sampled), px
    double maxEnergyDrift = unbounded;   // |E_end - E_0| / E_0
    double maxMomentumDrift = unbounded; // |P_end - P_0| / sum m|v|
};

struct StressRow {
    std::string name;
    ModelKind model;
    std::function<World()> build;
    long long frames;
    Expect expect;
};

struct Outcome {
    long long framesRun = 0;
    long long blewUpAt = -1;
    int badMarble = -1;
    int escapes = 0;
    double overlap = 0;
    double energyDrift = NAN;
    double momentumDrift = NAN;
    double framesPerSecond = 0;
    std::string verdict;
};

World withModel(World w, ModelKind model)
{
    w.params.model = model;
    return w;
}

// A hexagonal packing of equal marbles at area fraction `packing` (at most 0.9069), slowly
// jiggling, elastic, no friction.
World densePacking(double packing, int columns, int rows, std::uint64_t seed)
{
    const double r = 6.0;
    // Hexagonal cell area per disc: (sqrt(3)/2) d^2, so packing = pi r^2 / ((sqrt(3)/2) d^2).
    const double d = std::sqrt(std::numbers::pi * r * r / (packing * std::sqrt(3.0) / 2.0));
    const double rowHeight = d * std::sqrt(3.0) / 2.0;
    World w;
    w.stage = {columns * d + d / 2 + 2 * r, rows * rowHeight + 2 * r, true};
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    SplitMix64 rng(seed);
    for (int y = 0; y < rows; ++y) {
        for (int x = 0; x < columns; ++x) {
            const double angle = rng.uniform(0, 2 * std::numbers::pi);
            w.addMarble({r + d / 2 + x * d + (y % 2) * d / 2, r + rowHeight / 2 + y * rowHeight}, r,
                        {0.5 * std::cos(angle), 0.5 * std::sin(angle)});
        }
    }
    return w;
}

// Marbles of radii 0.5 to 500 together: three giants and a swarm of tiny ones.
World radiusRange(std::uint64_t seed)
{
    World w;
    w.stage = {4000, 3000, true};
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    w.addMarble({700, 700}, 500, {3, 1});
    w.addMarble({2600, 1500}, 400, {-2, 2});
    w.addMarble({1500, 2300}, 300, {1, -3});
    SplitMix64 rng(seed);
    for (int k = 0; k < 400; ++k) {
        const double r = rng.uniform(0.5, 3.0);
        const Vec2 p{rng.uniform(3400, 3990), rng.uniform(10, 2990)};
        w.addMarble(p, r, {rng.uniform(-20, 20), rng.uniform(-20, 20)});
    }
    return w;
}

// A few marbles thrown at up to 1e6 px/frame among pins on a small stage.
World extremeSpeeds()
{
    World w;
    w.stage = {800, 600, true};
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    w.addMarble({100, 100}, 10, {1e6, 3.3e5});
    w.addMarble({700, 500}, 15, {-7.7e5, -1e6});
    w.addMarble({400, 300}, 20, {2.5e5, -6e5});
    w.addMarble({200, 450}, 8, {0, 0});
    for (int k = 0; k < 12; ++k)
        w.addPin({150.0 + 50 * k, 300.0 + 40 * std::sin(k)});
    return w;
}

// Marbles spawned overlapping each other and pins.
World spawnedOverlapping()
{
    World w;
    w.stage = {800, 600, true};
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    w.addMarble({300, 300}, 30, {2, 0});
    w.addMarble({320, 305}, 25, {-2, 1});   // deep overlap, approaching
    w.addMarble({300, 300}, 10, {0, 0});    // concentric with the first
    w.addMarble({500, 300}, 20, {0, 0});
    w.addPin({505, 300});                   // a pin inside a resting marble
    w.addMarble({600, 200}, 20, {-1, 1});
    w.addPin({610, 200});                   // a pin inside a moving marble
    w.addMarble({15, 300}, 20, {-3, 0});    // overlapping the left wall, moving out
    return w;
}

World crowd(int n, double friction = 0.0, double zero = 0.0)
{
    World w = makeCrowd(n, 1);
    w.params.friction = friction;
    w.params.zeroThreshold = zero;
    return w;
}

// The four marbles of the default scene, all moving, without friction: they bounce for ever.
World smallScene()
{
    World w = defaultScene();
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    w.pushes.clear();
    const Vec2 speeds[] = {{3.1, 1.7}, {-2.3, 2.9}, {1.3, -3.7}, {-4.1, -0.6}};
    for (int i = 0; i < w.marbleCount(); ++i)
        w.velocity[i] = speeds[i % 4];
    return w;
}

std::vector<StressRow> stressRows(bool quick)
{
    const int big = quick ? 10000 : 100000;
    const long long longFrames = quick ? 100000 : 1000000;
    const std::string bigName = quick ? "10k" : "100k";
    const long long crowdFrames = quick ? 200 : 1000;
    std::vector<StressRow> rows;
    const ModelKind models[] = {ModelKind::Book, ModelKind::Impulse, ModelKind::Exact};

    // What each model promises. Exact: no overlap beyond rounding, energy and momentum kept.
    // Impulse: marbles sink into each other within a sub-step (that is its error), but no
    // centre reaches another disc's far side (overlap below the largest diameter), and
    // pairwise elastic impulses keep the energy. Book: stays finite and on the stage.
    auto expectFor = [](ModelKind m, bool conservative, double overlapBound, double largestRadius) {
        Expect e;
        if (m == ModelKind::Exact) {
            e.maxOverlapPx = std::max(1e-9, overlapBound);
            if (conservative)
                e.maxEnergyDrift = 1e-9;
        } else if (m == ModelKind::Impulse) {
            e.maxOverlapPx = std::max(2 * largestRadius, overlapBound);
            if (conservative)
                e.maxEnergyDrift = 1e-9;
        }
        return e;
    };

    for (ModelKind m : models) {
        // (a) Long runs.
        rows.push_back({"long: four marbles, no friction, " + std::to_string(longFrames) + " frames", m,
                        [m] { return withModel(smallScene(), m); }, longFrames, expectFor(m, true, 0, 55)});
        // Named with the frames it runs (--quick's said 1000 and ran 200).
        rows.push_back({"long: crowd " + bigName + ", " + std::to_string(crowdFrames) + " frames", m,
                        [m, big] { return withModel(crowd(big), m); }, crowdFrames, expectFor(m, true, 0, 12)});
        // (b) Extremes.
        rows.push_back({"friction 0", m, [m] { return withModel(crowd(2000), m); }, 500, expectFor(m, true, 0, 12)});
        rows.push_back({"friction 0.999", m, [m] { return withModel(crowd(2000, 0.999), m); }, 300, expectFor(m, false, 0, 12)});
        rows.push_back({"threshold 0", m, [m] { return withModel(crowd(2000, 0.05, 0.0), m); }, 500, expectFor(m, false, 0, 12)});
        rows.push_back({"threshold 100", m, [m] { return withModel(crowd(2000, 0.05, 100.0), m); }, 200,
                        expectFor(m, false, 0, 12)});
        rows.push_back({"massScale 1e-6", m,
                        [m] {
                            World w = withModel(defaultScene(), m);
                            w.setMassScale(1e-6);
                            return w;
                        },
                        2000, expectFor(m, false, 0, 55)});
        rows.push_back({"massScale 1e6", m,
                        [m] {
                            World w = withModel(defaultScene(), m);
                            w.setMassScale(1e6);
                            return w;
                        },
                        2000, expectFor(m, false, 0, 55)});
        rows.push_back({"radii 0.5 to 500", m, [m] { return withModel(radiusRange(5), m); }, 2000,
                        expectFor(m, true, 0, 500)});
        rows.push_back({"speeds up to 1e6 px/frame", m, [m] { return withModel(extremeSpeeds(), m); }, 500,
                        expectFor(m, true, 0, 20)});
        rows.push_back({"sparse gas, up to 60 px/frame", m, [m] { return withModel(makeSparseGas(), m); }, 500,
                        expectFor(m, true, 0, 3)});
        {
            const World spawned = spawnedOverlapping();
            // Overlaps present at the start may persist (separating pairs are left alone); none may grow.
            rows.push_back({"spawned overlapping marbles and pins", m, [m] { return withModel(spawnedOverlapping(), m); },
                            1000, expectFor(m, false, maxOverlap(spawned) + 1e-9, 30)});
        }
        // Gravity far beyond a classroom's 0.5 px/frame^2: up to 1e13 every promise holds. At
        // 1e34 a falling marble's bounces come closer together than a double's time tells apart:
        // marbles resting on each other sink in (the exact model's overlap reaches pixels from
        // about 1e30), so there only finite numbers and the stage are expected (the exact model
        // let marbles through the floor from about 1e33).
        auto withGravity = [](ModelKind m, double g) {
            World w = withModel(smallScene(), m);
            w.params.gravity = {0.0, g};
            return w;
        };
        rows.push_back({"gravity 1e13 px/frame^2", m, [m, withGravity] { return withGravity(m, 1e13); }, 200,
                        expectFor(m, false, 0, 55)});
        {
            // Each model's own expectation but the exact model's overlap, which that gravity
            // cannot keep.
            Expect e = expectFor(m, false, 0, 55);
            if (m == ModelKind::Exact)
                e.maxOverlapPx = unbounded;
            rows.push_back({"gravity 1e34 (finite, on the stage)", m, [m, withGravity] { return withGravity(m, 1e34); },
                            200, e});
        }
        rows.push_back({"dense packing 0.85", m, [m] { return withModel(densePacking(0.85, 40, 40, 3), m); }, 300,
                        expectFor(m, true, 0, 6)});
        {
            // No walls: nothing outside acts on the marbles, so the total momentum must stay.
            Expect e = expectFor(m, true, 0, 12);
            if (m != ModelKind::Book)
                e.maxMomentumDrift = 1e-12;
            rows.push_back({"no walls: momentum", m,
                            [m] {
                                World w = withModel(crowd(2000), m);
                                w.stage.walls = false;
                                return w;
                            },
                            300, e});
        }
    }
    // The book's own instability and its neighbour: friction 1.5 flips the velocity every frame
    // and decays; friction 2.5 grows without bound and must be caught, not crash.
    rows.push_back({"book friction 1.5 (flips sign)", ModelKind::Book,
                    [] { return withModel(crowd(2000, 1.5, 0.01), ModelKind::Book); }, 2000, Expect{}});
    {
        Expect e;
        e.blowsUp = true;
        rows.push_back({"book friction 2.5 (unstable)", ModelKind::Book,
                        [] {
                            // Without collisions to rescale them, speeds grow by 1.5 every frame.
                            World w = defaultScene();
                            w.params.friction = 2.5;
                            return w;
                        },
                        5000, e});
    }
    return rows;
}

Outcome runRow(const StressRow &row)
{
    Outcome o;
    World w = row.build();
    const double e0 = w.kineticEnergy();
    const Vec2 p0 = w.momentum();
    const double pScale = momentumScale(w);
    // Overlap is sampled about 50 times per row (it costs a broad-phase pass) and at the end;
    // escapes are checked at the same samples.
    const long long sampleEvery = std::max<long long>(1, row.frames / 50);
    o.overlap = maxOverlap(w);
    double stepSeconds = 0.0;
    for (long long f = 1; f <= row.frames; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        const StepResult r = w.step();
        stepSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        o.framesRun = f;
        if (!r.finite) {
            o.blewUpAt = w.frame;
            o.badMarble = r.badMarble;
            break;
        }
        if (f % sampleEvery == 0 || f == row.frames) {
            o.overlap = std::max(o.overlap, maxOverlap(w));
            o.escapes = std::max(o.escapes, escapedMarbles(w));
        }
    }
    o.framesPerSecond = stepSeconds > 0 ? o.framesRun / stepSeconds : 0;
    if (o.blewUpAt < 0) {
        o.energyDrift = e0 > 0 ? std::abs(w.kineticEnergy() - e0) / e0 : NAN;
        const Vec2 p = w.momentum();
        o.momentumDrift = pScale > 0 ? std::hypot(p.x - p0.x, p.y - p0.y) / pScale : NAN;
    }

    const Expect &e = row.expect;
    std::string why;
    auto fail = [&why](const std::string &reason) { why += (why.empty() ? "" : "; ") + reason; };
    char buf[160];
    if (e.blowsUp && o.blewUpAt < 0)
        fail("expected the update to leave finite numbers");
    if (!e.blowsUp && o.blewUpAt >= 0) {
        std::snprintf(buf, sizeof buf, "left finite numbers at frame %lld, marble %d", o.blewUpAt, o.badMarble);
        fail(buf);
    }
    if (e.noEscapes && o.escapes > 0)
        fail(std::to_string(o.escapes) + " escaped");
    if (!(o.overlap <= e.maxOverlapPx)) {
        std::snprintf(buf, sizeof buf, "overlap %.3g > %.3g px", o.overlap, e.maxOverlapPx);
        fail(buf);
    }
    if (std::isfinite(e.maxEnergyDrift) && !(o.energyDrift <= e.maxEnergyDrift)) {
        std::snprintf(buf, sizeof buf, "energy drift %.3g > %.3g", o.energyDrift, e.maxEnergyDrift);
        fail(buf);
    }
    if (std::isfinite(e.maxMomentumDrift) && !(o.momentumDrift <= e.maxMomentumDrift)) {
        std::snprintf(buf, sizeof buf, "momentum drift %.3g > %.3g", o.momentumDrift, e.maxMomentumDrift);
        fail(buf);
    }
    if (why.empty()) {
        if (o.blewUpAt >= 0) {
            std::snprintf(buf, sizeof buf, "ok (exit 3 case: non-finite at frame %lld, marble %d)", o.blewUpAt,
                          o.badMarble);
            o.verdict = buf;
        } else {
            o.verdict = "ok";
        }
    } else {
        o.verdict = "FAIL: " + why;
    }
    return o;
}

} // namespace

int stressCommand(const std::vector<std::string> &given)
{
    const Options o = parseOptions(given, {"--csv", "--only"}, {"--quick"});
    if (!o.positional.empty())
        throw InvalidInput{"stress: unexpected argument '" + o.positional.front() + "'"};
    const bool quick = o.has("--quick");
    const std::string only = o.last("--only") ? *o.last("--only") : std::string();
    if (o.has("--only") && only.empty())
        throw InvalidInput{"--only: an empty text matches every row; leave --only out to run them all"};

    std::vector<StressRow> rows = stressRows(quick);
    if (!only.empty()) {
        const std::string example = rows.front().name;
        std::erase_if(rows, [&only](const StressRow &row) { return row.name.find(only) == std::string::npos; });
        if (rows.empty())
            throw InvalidInput{"stress: --only '" + only + "' matches no row's name (e.g. '" + example + "')"};
    }

    // Opened before the rows run and print: a path that cannot be written fails at once, with
    // nothing on stdout (it failed after the whole table).
    std::optional<OutputFile> csvFile;
    if (const std::string *path = o.last("--csv"))
        csvFile.emplace("--csv", *path);

    std::printf("marbles-cli stress%s: each row states its expectation; exit 0 only if all are met\n",
                quick ? " --quick" : "");
    // The name column as wide as the longest name ("long: four marbles, no friction, 1000000 frames").
    int nameWidth = 3;
    for (const StressRow &row : rows)
        nameWidth = std::max(nameWidth, static_cast<int>(row.name.size()));
    std::printf("%-*s %-8s %9s %8s %10s %12s %12s %12s  %s\n", nameWidth, "row", "model", "frames", "escapes",
                "overlap px", "energy drift", "mom. drift", "frames/s", "verdict");
    std::string csv = "row,model,frames,blew_up_at,escapes,max_overlap_px,energy_drift,momentum_drift,frames_per_second,verdict\n";
    int failures = 0;
    int ran = 0;
    for (const StressRow &row : rows) {
        const Outcome o = runRow(row);
        ++ran;
        failures += o.verdict.rfind("FAIL", 0) == 0;
        const std::string model(modelName(row.model));
        std::printf("%-*s %-8s %9lld %8d %10s %12s %12s %12s  %s\n", nameWidth, row.name.c_str(), model.c_str(), o.framesRun,
                    o.escapes, formatNumber(o.overlap).c_str(), formatNumber(o.energyDrift).c_str(), formatNumber(o.momentumDrift).c_str(),
                    formatNumber(o.framesPerSecond).c_str(), o.verdict.c_str());
        std::fflush(stdout);
        csv += "\"" + row.name + "\"," + model + "," + std::to_string(o.framesRun) + "," + std::to_string(o.blewUpAt)
               + "," + std::to_string(o.escapes) + "," + formatNumber(o.overlap) + "," + formatNumber(o.energyDrift) + ","
               + formatNumber(o.momentumDrift) + "," + formatNumber(o.framesPerSecond) + ",\"" + o.verdict + "\"\n";
    }
    if (csvFile) {
        csvFile->write(csv);
        csvFile->commit();
    }
    std::printf("stress: %d of %d %s their expectation\n", ran - failures, ran, ran == 1 ? "row met" : "rows met");
    return failures == 0 ? ExitOk : ExitInternal;
}

} // namespace marbles::cli
