// marbles-cli bench: run time against error (the work-precision diagram), and --scale.

#include "app/clicommon.h"
#include "app/pngplot.h"
#include "core/diagnostics.h"
#include "core/presets.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

namespace marbles::cli {

namespace {

// One model with one setting, as the bench rows name them.
struct Variant {
    ModelKind model;
    int substeps = 1;

    std::string setting() const
    {
        return model == ModelKind::Impulse ? "substeps=" + std::to_string(substeps) : "-";
    }
};

std::vector<Variant> precisionVariants()
{
    std::vector<Variant> v{{ModelKind::Book}};
    for (int n = 1; n <= 64; n *= 2)
        v.push_back({ModelKind::Impulse, n});
    v.push_back({ModelKind::Exact});
    return v;
}

// A bench scene: its world, how long it runs, and, where the physics has one, the closed-form
// positions at the last frame. Without one, the exact model's run is the reference.
struct BenchScene {
    std::string name;
    std::string about;
    World world;
    int frames = 100;
    std::function<std::vector<Vec2>(int frame)> closedForm; // empty: use "exact" as reference
    bool chaotic = false; // many bodies: report conserved quantities and overlap only
};

World openStage(double friction)
{
    World w;
    w.stage = {100000, 100000, false};
    w.params.friction = friction;
    w.params.zeroThreshold = 0.0;
    return w;
}

// s(t) = (1 - e^{-lambda t}) / lambda, lambda = -ln(1 - k): the distance factor of linear drag
// (s(t) = t without drag). p(t) = p0 + v0 s(t).
double dragDistance(double k, double t)
{
    if (k == 0.0)
        return t;
    const double lambda = -std::log1p(-k);
    return -std::expm1(-lambda * t) / lambda;
}

std::vector<BenchScene> precisionScenes(int crowdSize)
{
    std::vector<BenchScene> scenes;

    {
        // One marble gliding under air friction, no collisions: the book's Euler steps against
        // the exact exponential decay.
        BenchScene s{"glide", "one marble slowing under drag k = 0.05", openStage(0.05), 120, {}};
        const Vec2 p0{500, 500}, v0{6, 2.5};
        s.world.addMarble(p0, 10, v0);
        s.closedForm = [p0, v0](int f) {
            const double d = dragDistance(0.05, f);
            return std::vector<Vec2>{{p0.x + v0.x * d, p0.y + v0.y * d}};
        };
        scenes.push_back(std::move(s));
    }
    {
        // Gravity with drag: dv/dt = -lambda v + g  =>  p(t) = p0 + g t / lambda + (v0 - g / lambda) s(t).
        BenchScene s{"fall", "one marble thrown up under gravity 0.25 and drag k = 0.02", openStage(0.02), 120, {}};
        const Vec2 p0{500, 500}, v0{3, -4}, g{0, 0.25};
        s.world.params.gravity = g;
        s.world.addMarble(p0, 10, v0);
        s.closedForm = [p0, v0, g](int f) {
            const double lambda = -std::log1p(-0.02);
            const double d = dragDistance(0.02, f);
            return std::vector<Vec2>{{p0.x + g.x * f / lambda + (v0.x - g.x / lambda) * d,
                                      p0.y + g.y * f / lambda + (v0.y - g.y / lambda) * d}};
        };
        scenes.push_back(std::move(s));
    }
    {
        // Head-on elastic collision of unequal masses (1-D formulas), no friction.
        BenchScene s{"head-on", "masses 1 and 3 meet head-on, e = 1", openStage(0.0), 100, {}};
        const double x1 = 400, x2 = 520, r1 = 10, r2 = 20, v1 = 4, v2 = -2, m1 = 1, m2 = 3;
        s.world.addMarble({x1, 500}, r1, {v1, 0}, m1);
        s.world.addMarble({x2, 500}, r2, {v2, 0}, m2);
        s.closedForm = [=](int f) {
            const double tc = (x2 - x1 - (r1 + r2)) / (v1 - v2);
            if (f <= tc)
                return std::vector<Vec2>{{x1 + v1 * f, 500}, {x2 + v2 * f, 500}};
            const double u1 = ((m1 - m2) * v1 + 2 * m2 * v2) / (m1 + m2);
            const double u2 = ((m2 - m1) * v2 + 2 * m1 * v1) / (m1 + m2);
            return std::vector<Vec2>{{x1 + v1 * tc + u1 * (f - tc), 500}, {x2 + v2 * tc + u2 * (f - tc), 500}};
        };
        scenes.push_back(std::move(s));
    }
    {
        // A marble glancing off a pin at impact parameter b: a mirror reflection about the
        // contact normal, at the exact time of contact.
        BenchScene s{"pin", "a marble glances off a pin at impact parameter b = 6", openStage(0.0), 80, {}};
        const double r = 10, b = 6, v = 5, x0 = 300, y0 = 500, qx = 420;
        s.world.addMarble({x0, y0}, r, {v, 0});
        s.world.addPin({qx, y0 + b});
        s.closedForm = [=](int f) {
            const double tc = (qx - x0 - std::sqrt(r * r - b * b)) / v;
            if (f <= tc)
                return std::vector<Vec2>{{x0 + v * f, y0}};
            const Vec2 pc{x0 + v * tc, y0};
            const Vec2 n{(pc.x - qx) / r, (pc.y - (y0 + b)) / r};
            const double vn = v * n.x;
            const Vec2 out{v - 2 * vn * n.x, -2 * vn * n.y};
            return std::vector<Vec2>{{pc.x + out.x * (f - tc), pc.y + out.y * (f - tc)}};
        };
        scenes.push_back(std::move(s));
    }
    {
        // Newton's cradle: equal elastic marbles in a touching row; the striker's momentum
        // passes down the row and the last marble leaves with the striker's speed.
        BenchScene s{"cradle", "a striker hits a row of five touching equal marbles", openStage(0.0), 60, {}};
        World preset;
        makePreset("newtons-cradle", preset);
        for (int i = 0; i < preset.marbleCount(); ++i)
            s.world.addMarble(preset.position[i], preset.radius[i], preset.velocity[i]);
        const World start = s.world;
        s.closedForm = [start](int f) {
            std::vector<Vec2> p = start.position;
            const int striker = start.marbleCount() - 1;
            const double v = start.velocity[striker].x;
            const double tc = (p[0].x - 2 * start.radius[0] - p[striker].x) / v;
            if (f <= tc) {
                p[striker].x += v * f;
            } else {
                p[striker].x += v * tc;
                p[striker - 1].x += v * (f - tc);
            }
            return p;
        };
        scenes.push_back(std::move(s));
    }
    {
        // The Pachinko board: gravity, drag, pins and marbles, e = 0.8. The exact model is the
        // reference (validated against closed forms by the test suite).
        BenchScene s{"pachinko", "marbles falling through pins (reference: exact)", World{}, 80, {}};
        makePreset("pachinko", s.world);
        scenes.push_back(std::move(s));
    }
    if (crowdSize > 0) {
        BenchScene s{"crowd-" + std::to_string(crowdSize), "elastic crowd in a box: energy and overlap only",
                     makeCrowd(crowdSize, 1), 200, {}};
        s.chaotic = true;
        scenes.push_back(std::move(s));
    }
    return scenes;
}

World withVariant(const World &base, const Variant &v)
{
    World w = base;
    w.params.model = v.model;
    w.params.substeps = v.substeps;
    return w;
}

using Clock = std::chrono::steady_clock;

// Mean wall-clock time per frame, ms, of frames 2..F of an F-frame run from `base` (median over
// the repeats, each starting from `base` again). The first frame is stepped but not timed: it
// sizes the model's buffers (page faults, at 100k marbles a few milliseconds), a cost paid once
// per run, not per frame.
double msPerFrame(const World &base, int frames, int repeats)
{
    std::vector<double> samples;
    const int untimed = frames > 1 ? 1 : 0;
    for (int r = 0; r < repeats; ++r) {
        World w = base;
        for (int f = 0; f < untimed; ++f)
            w.step();
        const auto t0 = Clock::now();
        for (int f = untimed; f < frames; ++f)
            w.step();
        const std::chrono::duration<double, std::milli> dt = Clock::now() - t0;
        samples.push_back(dt.count() / std::max(frames - untimed, 1));
    }
    std::nth_element(samples.begin(), samples.begin() + samples.size() / 2, samples.end());
    return samples[samples.size() / 2];
}

struct Measured {
    World end;
    double maxOverlapPx = 0.0;
    double movingShare = 0.0; // marbles with a non-zero velocity after a frame, mean over the frames
    bool finite = true;
};

double shareMoving(const World &w)
{
    const auto moving = std::count_if(w.velocity.begin(), w.velocity.end(),
                                      [](Vec2 v) { return v.x != 0.0 || v.y != 0.0; });
    return w.marbleCount() > 0 ? static_cast<double>(moving) / w.marbleCount() : 0.0;
}

Measured measure(const World &base, int frames)
{
    Measured m{base};
    m.maxOverlapPx = maxOverlap(m.end);
    int stepped = 0;
    for (int f = 0; f < frames; ++f) {
        if (!m.end.step().finite) {
            m.finite = false;
            break;
        }
        ++stepped;
        m.maxOverlapPx = std::max(m.maxOverlapPx, maxOverlap(m.end));
        m.movingShare += shareMoving(m.end);
    }
    m.movingShare = stepped > 0 ? m.movingShare / stepped : shareMoving(m.end);
    return m;
}

struct Row {
    std::string scene, model, setting;
    double ms = 0, positionError = NAN, energyError = NAN, momentumError = NAN, overlap = 0;
    int escapes = 0;
    double movingShare = NAN; // scale rows: mean share of the marbles moving over the run
};

void printTable(const std::vector<Row> &rows, bool scale)
{
    int sceneWidth = 16; // as wide as the longest scene name
    for (const Row &r : rows)
        sceneWidth = std::max(sceneWidth, static_cast<int>(r.scene.size()));
    std::printf("%-*s %-8s %-12s %12s %12s %12s %12s %12s%s\n", sceneWidth, "scene", "model", "setting", "ms/frame",
                "pos err px", "energy err", "momentum err", "overlap px", scale ? "      escapes     moving %" : "");
    for (const Row &r : rows) {
        std::printf("%-*s %-8s %-12s %12s %12s %12s %12s %12s", sceneWidth, r.scene.c_str(), r.model.c_str(), r.setting.c_str(),
                    formatNumber(r.ms, "%.4g").c_str(), formatNumber(r.positionError).c_str(), formatNumber(r.energyError).c_str(),
                    formatNumber(r.momentumError).c_str(), formatNumber(r.overlap).c_str());
        if (scale)
            std::printf(" %12d %12s", r.escapes, formatNumber(100.0 * r.movingShare, "%.1f").c_str());
        std::printf("\n");
    }
    std::fflush(stdout);
}

std::string rowsToCsv(const std::vector<Row> &rows)
{
    std::string csv = "scene,model,setting,ms_per_frame,position_error_px,energy_error,momentum_error,max_overlap_px,escapes,"
                      "moving_share\n";
    // Six significant digits; a figure that does not apply is an empty field.
    const auto cell = [](double x) { return formatNumber(x, "%.6g", ""); };
    for (const Row &r : rows) {
        csv += r.scene + "," + r.model + "," + r.setting + "," + cell(r.ms) + "," + cell(r.positionError) + ","
               + cell(r.energyError) + "," + cell(r.momentumError) + "," + cell(r.overlap) + ","
               + std::to_string(r.escapes) + "," + cell(r.movingShare) + "\n";
    }
    return csv;
}

double relative(double value, double reference, double scale)
{
    return std::abs(value - reference) / std::max(scale, 1e-300);
}

std::vector<Row> precisionBench(int repeats, int crowdSize)
{
    std::vector<Row> rows;
    for (BenchScene &scene : precisionScenes(crowdSize)) {
        const int frames = scene.frames;
        // The reference end state: closed form where there is one, else the exact model.
        std::optional<Measured> exactRun;
        auto exactReference = [&]() -> const Measured & {
            if (!exactRun)
                exactRun = measure(withVariant(scene.world, {ModelKind::Exact}), frames);
            return *exactRun;
        };
        const World &reference = exactReference().end;
        const std::vector<Vec2> closed = scene.closedForm ? scene.closedForm(frames) : std::vector<Vec2>{};
        const double e0 = scene.world.kineticEnergy();
        const double pScale = std::max(momentumScale(scene.world), momentumScale(reference));

        for (const Variant &v : precisionVariants()) {
            const World start = withVariant(scene.world, v);
            Row row{scene.name, std::string(modelName(v.model)), v.setting()};
            const Measured m = v.model == ModelKind::Exact ? exactReference() : measure(start, frames);
            row.ms = msPerFrame(start, frames, repeats);
            row.overlap = m.maxOverlapPx;
            row.escapes = escapedMarbles(m.end);
            if (!m.finite) {
                row.positionError = row.energyError = row.momentumError = INFINITY;
                rows.push_back(row);
                continue;
            }
            if (scene.chaotic) {
                // Elastic, frictionless box: energy is conserved; walls change momentum.
                row.energyError = relative(m.end.kineticEnergy(), e0, e0);
            } else {
                double worst = 0.0;
                for (int i = 0; i < m.end.marbleCount(); ++i) {
                    const Vec2 want = closed.empty() ? reference.position[i] : closed[i];
                    worst = std::max(worst, distance(m.end.position[i], want));
                }
                row.positionError = worst;
                row.energyError = relative(m.end.kineticEnergy(), reference.kineticEnergy(),
                                           std::max(reference.kineticEnergy(), e0));
                const Vec2 pm = m.end.momentum(), pr = reference.momentum();
                row.momentumError = std::hypot(pm.x - pr.x, pm.y - pr.y) / std::max(pScale, 1e-300);
            }
            rows.push_back(row);
        }
    }
    return rows;
}

// The work-precision diagram: for each model, the largest position error over the closed-form
// scenes against the summed time per frame over them; impulse is one line over its substeps.
plot::Chart precisionChart(const std::vector<Row> &rows)
{
    plot::Chart chart;
    chart.title = "Run time against error (marbles-cli bench)";
    chart.xLabel = "ms per frame, summed over the closed-form scenes";
    chart.yLabel = "largest position error at the end, px";
    const std::vector<std::string> closedScenes{"glide", "fall", "head-on", "pin", "cradle"};
    struct Point {
        double ms = 0, error = 0;
    };
    std::vector<std::pair<std::string, Point>> points; // key: model + setting
    for (const Row &r : rows) {
        if (std::find(closedScenes.begin(), closedScenes.end(), r.scene) == closedScenes.end())
            continue;
        const std::string key = r.model + " " + r.setting;
        auto it = std::find_if(points.begin(), points.end(), [&](const auto &p) { return p.first == key; });
        if (it == points.end()) {
            points.push_back({key, {}});
            it = points.end() - 1;
        }
        it->second.ms += r.ms;
        it->second.error = std::max(it->second.error, r.positionError);
    }
    const std::vector<std::pair<std::string, std::uint32_t>> models{
        {"book", 0x1f5fbf}, {"impulse", 0xd9822b}, {"exact", 0x2a9d4b}};
    for (const auto &[model, colour] : models) {
        plot::Series s;
        s.label = model == "impulse" ? "impulse, substeps 1 to 64" : model;
        s.rgb = colour;
        for (const auto &[key, p] : points) {
            if (key.rfind(model + " ", 0) == 0) {
                s.x.push_back(p.ms);
                s.y.push_back(p.error);
            }
        }
        chart.series.push_back(std::move(s));
    }
    return chart;
}

struct ScaleCase {
    std::string name;
    int n;
    double moving;
    int giants = 0; // marbles of radius kGiantRadius among the crowd (makeCrowdWithGiants)
};

// The giants' radius: about ten times the crowd's largest, so that the grids leave them out.
constexpr double kGiantRadius = 100.0;
constexpr int kGiants = 4;

constexpr int kScaleSizes[] = {1000, 10000, 100000};

// The largest crowd size of the scale run (--max-n is at least 1000).
int largestCrowd(int maxN)
{
    int largest = kScaleSizes[0];
    for (int n : kScaleSizes) {
        if (n <= maxN)
            largest = n;
    }
    return largest;
}

std::string crowdName(int n)
{
    return "crowd-" + std::to_string(n);
}

std::vector<Row> scaleBench(int frames, int repeats, int maxN)
{
    std::vector<ScaleCase> cases;
    const int largest = largestCrowd(maxN);
    for (int n : kScaleSizes) {
        if (n <= largest)
            cases.push_back({crowdName(n), n, 1.0});
    }
    // The largest crowd again with 1 % of its marbles moving, and with all of them at rest (what
    // a frame costs when every marble sleeps).
    cases.push_back({crowdName(largest) + "-1%", largest, 0.01});
    cases.push_back({crowdName(largest) + "-rest", largest, 0.0});
    // A crowd of up to 10k with four marbles of radius 100 among it (the marbles they would
    // overlap taken out): what one large marble costs where the grids are sized from the rest.
    const int giantCrowd = std::min(largest, 10000);
    cases.push_back({crowdName(giantCrowd) + "-giants", giantCrowd, 1.0, kGiants});

    std::vector<Row> rows;
    for (const ScaleCase &c : cases) {
        const World base = c.giants > 0 ? makeCrowdWithGiants(c.n, 1, c.giants, kGiantRadius, c.moving)
                                         : makeCrowd(c.n, 1, c.moving);
        for (const Variant &v : {Variant{ModelKind::Book}, Variant{ModelKind::Impulse, 1}, Variant{ModelKind::Exact}}) {
            const World start = withVariant(base, v);
            Row row{c.name, std::string(modelName(v.model)), v.setting()};
            row.ms = msPerFrame(start, frames, c.n >= 100000 ? 1 : repeats);
            const Measured m = measure(start, frames);
            const double e0 = start.kineticEnergy();
            row.energyError = m.finite ? relative(m.end.kineticEnergy(), e0, e0) : INFINITY;
            row.overlap = m.maxOverlapPx;
            row.escapes = escapedMarbles(m.end);
            row.movingShare = m.movingShare;
            rows.push_back(row);
            std::fprintf(stderr, "  %s %s: %.3f ms/frame\n", c.name.c_str(), row.model.c_str(), row.ms);
        }
    }
    return rows;
}

const Row *findRow(const std::vector<Row> &rows, const std::string &scene, const std::string &model)
{
    for (const Row &r : rows) {
        if (r.scene == scene && r.model == model)
            return &r;
    }
    return nullptr;
}

void printScaleSummary(const std::vector<Row> &rows, int maxN)
{
    // The 1%-moving crowd does not stay at 1 %: a marble that is hit starts to move, and without
    // friction nothing stops again. Its mean moving share tells how far below the all-moving
    // cost a run can go when cost follows the moving marbles.
    const int largestN = largestCrowd(maxN);
    const std::string largest = crowdName(largestN);
    const std::string size = std::to_string(largestN / 1000) + "k";
    std::printf("\n%-8s %16s %28s %30s\n", "model", (size + " / 1k cost").c_str(),
                (size + " all / " + size + " 1% moving").c_str(), "moving in the 1% run, mean");
    for (const char *model : {"book", "impulse", "exact"}) {
        const Row *small = findRow(rows, "crowd-1000", model);
        const Row *large = findRow(rows, largest, model);
        const Row *sparse = findRow(rows, largest + "-1%", model);
        std::printf("%-8s %16s %28s %30s\n", model,
                    small && large && small != large ? formatNumber(large->ms / small->ms, "%.1f").c_str() : "n/a",
                    large && sparse ? formatNumber(large->ms / sparse->ms, "%.1f").c_str() : "n/a",
                    sparse ? (formatNumber(100.0 * sparse->movingShare, "%.1f") + " %").c_str() : "n/a");
    }
}

// Issue 5's targets for the crowd at 100k marbles, each with the figure this run measured and
// whether it meets it ("n/a" when the run has no such row). The bench only reports: its exit code
// does not depend on the verdicts.
void printScaleTargets(const std::vector<Row> &rows, int frames, int maxN)
{
    constexpr int targetN = 100000;
    constexpr int targetFrames = 220;
    if (largestCrowd(maxN) < targetN) {
        std::printf("\nissue 5's targets are for %d marbles: this run stops at %d (--max-n)\n", targetN,
                    largestCrowd(maxN));
        return;
    }
    std::printf("\nissue 5's targets at %d marbles (one core, %d frames%s):\n", targetN, targetFrames,
                frames == targetFrames ? "" : ("; this run: " + std::to_string(frames)).c_str());
    std::printf("%-46s %14s  %s\n", "target", "measured", "verdict");
    const std::string all = crowdName(targetN);
    auto line = [](const std::string &what, const Row *row, double value, const std::string &text, bool met) {
        std::printf("%-46s %14s  %s\n", what.c_str(), row && !std::isnan(value) ? text.c_str() : "n/a",
                    !row || std::isnan(value) ? "n/a" : met ? "met" : "NOT MET");
    };
    auto msTarget = [&](const std::string &label, const char *model, double limitMs) {
        const Row *r = findRow(rows, all, model);
        const double ms = r ? r->ms : NAN;
        line(label + ": <= " + formatNumber(limitMs, "%g") + " ms per frame", r, ms, formatNumber(ms, "%.4g") + " ms",
             ms <= limitMs);
    };
    msTarget("exact", "exact", 10.0);
    const Row *exact = findRow(rows, all, "exact");
    line("exact: energy drift <= 1e-12", exact, exact ? exact->energyError : NAN,
         exact ? formatNumber(exact->energyError) : "", exact && exact->energyError <= 1e-12);
    line("exact: overlap <= 1e-9 px", exact, exact ? exact->overlap : NAN, exact ? formatNumber(exact->overlap) + " px" : "",
         exact && exact->overlap <= 1e-9);
    line("exact: no escapes", exact, exact ? exact->escapes : NAN, exact ? std::to_string(exact->escapes) : "",
         exact && exact->escapes == 0);
    msTarget("book", "book", 5.0);
    msTarget("impulse, 1 substep", "impulse", 5.0);
    for (const char *model : {"book", "impulse", "exact"}) {
        const Row *large = findRow(rows, all, model);
        const Row *sparse = findRow(rows, all + "-1%", model);
        const double ratio = large && sparse ? large->ms / sparse->ms : NAN;
        line(std::string(model) + ": 1 % moving >= 30 times cheaper", sparse, ratio, formatNumber(ratio, "%.1f") + " times",
             ratio >= 30.0);
    }
    for (const char *model : {"book", "impulse", "exact"}) {
        const Row *small = findRow(rows, crowdName(1000), model);
        const Row *large = findRow(rows, all, model);
        const double growth = small && large ? large->ms / small->ms : NAN;
        line(std::string(model) + ": 100k costs <= 120 times 1k", large, growth, formatNumber(growth, "%.1f") + " times",
             growth <= 120.0);
    }
}

} // namespace

int benchCommand(const std::vector<std::string> &given)
{
    const Options o = parseOptions(given, {"--csv", "--plot", "--repeat", "--frames", "--crowd", "--max-n"}, {"--scale"});
    if (!o.positional.empty())
        throw InvalidInput{"bench: unexpected argument '" + o.positional.front() + "'"};
    // An option the chosen bench has no use for is refused, not silently dropped, and before its
    // value is judged ("--max-n 10" said "must be >= 1000" without --scale).
    const bool scale = o.has("--scale");
    int repeats = 5;
    int frames = 220;
    int crowd = 1000;
    int maxN = 100000;
    for (const auto &[a, value] : o.named) {
        if (!scale && (a == "--frames" || a == "--max-n"))
            throw InvalidInput{a + ": only with --scale"};
        if (scale && a == "--crowd")
            throw InvalidInput{"--crowd: not with --scale (its crowds have 1k, 10k and 100k marbles; --max-n stops earlier)"};
        if (scale && a == "--plot")
            throw InvalidInput{"--plot: draws the work-precision diagram, not --scale"};
        if (a == "--repeat")
            repeats = static_cast<int>(parseInteger("--repeat", value, 1, 1000));
        else if (a == "--frames")
            frames = static_cast<int>(parseInteger("--frames", value, 1, 1'000'000));
        else if (a == "--crowd")
            crowd = static_cast<int>(parseInteger("--crowd", value, 0, kMaxCrowd));
        else if (a == "--max-n")
            maxN = static_cast<int>(parseInteger("--max-n", value, 1000, kMaxCrowd));
    }

    // The files are opened before the scenes run (a typo in a path failed after the two minutes
    // of --scale), and written, then both committed, before anything is printed: one that cannot
    // be written ends the command with its message on stderr, nothing on stdout and neither file
    // changed (exit code 2 for a path that cannot be written, 1 for a write that failed; progress
    // goes to stderr while the scenes run).
    std::optional<OutputFile> csvFile;
    std::optional<OutputFile> plotFile;
    if (const std::string *path = o.last("--csv"))
        csvFile.emplace("--csv", *path);
    if (const std::string *path = o.last("--plot"))
        plotFile.emplace("--plot", *path);
    if (csvFile && plotFile && namesSameFile(*o.last("--csv"), *o.last("--plot")))
        throw InvalidInput{"--csv and --plot name the same file, " + *o.last("--plot")};
    const std::vector<Row> rows = scale ? scaleBench(frames, repeats, maxN) : precisionBench(repeats, crowd);
    if (csvFile)
        csvFile->write(rowsToCsv(rows));
    if (plotFile) {
        const std::vector<std::uint8_t> png = plot::encodePng(plot::render(precisionChart(rows)));
        plotFile->write(std::string_view(reinterpret_cast<const char *>(png.data()), png.size()));
    }
    if (csvFile)
        csvFile->commit();
    if (plotFile)
        plotFile->commit();
    if (scale) {
        std::printf("marbles-cli bench --scale: crowd scene, %d frames, one core\n", frames);
        printTable(rows, true);
        printScaleSummary(rows, maxN);
        printScaleTargets(rows, frames, maxN);
    } else {
        std::printf("marbles-cli bench: run time against error (median of %d run%s; errors against the closed form, "
                    "else against exact)\n",
                    repeats, repeats == 1 ? "" : "s");
        printTable(rows, false);
    }
    return ExitOk;
}

} // namespace marbles::cli
