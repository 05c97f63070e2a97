// libFuzzer target for the physics models. Every scene that loads (and is small enough to step
// quickly) is run for a few dozen frames in its model, with edits between frames such as the
// window makes (a marble moved, pushed, stopped, resized, added or removed; a pin added or
// removed; friction, zero threshold, gravity or the walls changed; a step back in time).
// Besides "never crashes, hangs or trips a sanitizer", it checks World.h's promise to every
// Stepper: a model's caches never change its results. Each frame is stepped twice from the same
// state, once by the world that has been stepping all along (its model keeps grids, sleepers and
// calendars from frame to frame and must notice the edits) and once by a fresh copy (a new model
// that builds everything from the World), and the two must agree bit for bit. It also checks
// that a step reports a marble that left finite numbers exactly when there is one, that the book
// model gives the bits of its plain all-pairs transcription, and that in the exact model the
// deepest overlap never grows.

#include "core/bookmodel.h"
#include "core/presets.h"
#include "core/sceneio.h"
#include "core/world.h"
#include "fuzz/samebits.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

using namespace marbles;
using namespace marbles::fuzzbits;

// Kept small so that each input runs in milliseconds: the bugs this looks for need a few
// marbles, not thousands.
// Enough marbles and pins for every model's grid (the book model's from 48 marbles and 24 pins).
constexpr int kMaxMarbles = 80;
constexpr int kMaxPins = 128;
constexpr int kSubstepsAtMost = 8;
constexpr int kFrames = 24;
constexpr int kEditEvery = 6;
// Faster marbles bounce so many times a frame (a million at 1e6 px/frame in a small box) that an
// input would take seconds under the sanitizers: the run stops there. marbles-cli stress covers
// such speeds.
constexpr double kMaxSpeed = 1e4;
// An input whose frames are slow but end (marbles bouncing thousands of times a frame between
// walls just wider than they are, up to the exact model's guards) stops after this long; a frame
// that never ends is still libFuzzer's timeout.
constexpr std::chrono::milliseconds kInputBudget{2000};

[[noreturn]] void fail(const World &w, const char *what, int marble, const std::string &scene)
{
    static const char *const names[] = {"book", "impulse", "exact"};
    std::fprintf(stderr, "fuzz_physics: %s model, frame %lld: %s (marble %d)\nscene:\n%s\n",
                 names[static_cast<int>(w.params.model)], static_cast<long long>(w.frame), what, marble,
                 scene.c_str());
    std::abort();
}

/// Aborts unless the world that kept its model and `other` stepped to the same state.
void compare(const World &kept, const World &other, const std::string &scene, const char *whose = "a fresh model's")
{
    const auto check = [&](int i, const char *what) {
        if (i >= 0)
            fail(kept, (std::string(what) + " differ from " + whose).c_str(), i, scene);
    };
    check(firstDifference(kept.position, other.position), "positions");
    check(firstDifference(kept.velocity, other.velocity), "velocities");
    check(firstDifference(kept.acceleration, other.acceleration), "pending pushes");
    check(firstDifference(kept.lastHit, other.lastHit), "collision records");
}

bool finite(Vec2 v)
{
    return std::isfinite(v.x) && std::isfinite(v.y);
}

/// The deepest overlap of a marble with another, a pin or (with walls) the stage's edge, px.
double deepestOverlap(const World &w)
{
    double deepest = 0.0;
    const int n = w.marbleCount();
    for (int i = 0; i < n; ++i) {
        const Vec2 p = w.position[static_cast<std::size_t>(i)];
        const double r = w.radius[static_cast<std::size_t>(i)];
        if (w.stage.walls)
            deepest = std::max({deepest, r - p.x, p.x + r - w.stage.width, r - p.y, p.y + r - w.stage.height});
        for (const Vec2 q : w.pins)
            deepest = std::max(deepest, r - distance(p, q));
        for (int j = i + 1; j < n; ++j)
            deepest = std::max(deepest, r + w.radius[static_cast<std::size_t>(j)] - distance(p, w.position[static_cast<std::size_t>(j)]));
    }
    return deepest;
}

bool tooFast(const World &w)
{
    for (const Vec2 v : w.velocity) {
        if (!(std::abs(v.x) <= kMaxSpeed && std::abs(v.y) <= kMaxSpeed))
            return true;
    }
    return false;
}

/// The dynamic state of a frame, as the window keeps it to step back to.
struct Snapshot {
    std::int64_t frame;
    std::vector<Vec2> position;
    std::vector<Vec2> velocity;
    std::vector<Vec2> acceleration;
    std::vector<HitRecord> lastHit;

    explicit Snapshot(const World &w)
        : frame(w.frame), position(w.position), velocity(w.velocity), acceleration(w.acceleration), lastHit(w.lastHit)
    {
    }
    /// Written into the world's fields, as Step Back does: the world keeps its model.
    void restoreInto(World &w) const
    {
        w.frame = frame;
        w.position = position;
        w.velocity = velocity;
        w.acceleration = acceleration;
        w.lastHit = lastHit;
    }
};

/// One edit of the kinds the window makes, chosen by `rng`; keeps the scene valid for its model.
/// `since` holds the frames stepped since the last edit, which Step Back can return to.
void edit(World &w, const std::vector<Snapshot> &since, SplitMix64 &rng)
{
    const double width = w.stage.width;
    const double height = w.stage.height;
    const auto anywhere = [&] { return Vec2{rng.uniform(0.0, width), rng.uniform(0.0, height)}; };
    const auto speed = [&] { return Vec2{rng.uniform(-8.0, 8.0), rng.uniform(-8.0, 8.0)}; };
    const int n = w.marbleCount();
    const int i = n > 0 ? static_cast<int>(rng.next() % static_cast<std::uint64_t>(n)) : -1;
    switch (rng.next() % 15) {
    case 0:
        if (i >= 0)
            w.position[static_cast<std::size_t>(i)] = anywhere();
        break;
    case 1:
        if (i >= 0)
            w.velocity[static_cast<std::size_t>(i)] = speed();
        break;
    case 2:
        if (i >= 0)
            w.velocity[static_cast<std::size_t>(i)] = {};
        break;
    case 3:
        if (i >= 0) {
            const Vec2 p = w.position[static_cast<std::size_t>(i)];
            w.push(i, {p.x + rng.uniform(-20.0, 20.0), p.y + rng.uniform(-20.0, 20.0)});
        }
        break;
    case 4:
        if (i >= 0)
            w.setRadius(i, rng.uniform(0.5, 40.0));
        break;
    case 5:
        if (i >= 0)
            w.setExplicitMass(i, rng.uniform(0.1, 1000.0));
        break;
    case 6:
        if (n < kMaxMarbles)
            w.addMarble(anywhere(), rng.uniform(0.5, 30.0), speed());
        break;
    case 7:
        if (n > 1)
            w.removeMarble(i);
        break;
    case 8:
        if (static_cast<int>(w.pins.size()) < kMaxPins)
            w.addPin(anywhere());
        break;
    case 9:
        if (!w.pins.empty())
            w.removePin(static_cast<int>(rng.next() % w.pins.size()));
        break;
    case 10:
        w.stage.walls = !w.stage.walls;
        break;
    case 11:
        // Inside every model's range: [0, 1) for exact and impulse.
        w.params.friction = rng.next() % 2 == 0 ? 0.0 : rng.uniform(0.0, 0.9);
        break;
    case 12:
        w.params.zeroThreshold = rng.next() % 2 == 0 ? 0.0 : rng.uniform(0.0, 1.0);
        break;
    case 13:
        w.params.gravity = rng.next() % 2 == 0 ? Vec2{} : Vec2{rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)};
        break;
    default:
        // Step Back: an earlier frame written into the same world.
        if (!since.empty())
            since[rng.next() % since.size()].restoreInto(w);
        break;
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    const std::string scene(reinterpret_cast<const char *>(data), size);
    SceneLoad load = parseScene(scene, "input");
    if (!load.ok)
        return 0;
    World kept = std::move(load.world);
    if (kept.marbleCount() > kMaxMarbles || static_cast<int>(kept.pins.size()) > kMaxPins
        || kept.params.substeps > kSubstepsAtMost || tooFast(kept))
        return 0;
    // The edits follow from the input (its FNV-1a hash), so that a finding replays.
    std::uint64_t hash = 1469598103934665603ull;
    for (const unsigned char c : scene)
        hash = (hash ^ c) * 1099511628211ull;
    SplitMix64 rng(hash);
    std::vector<Snapshot> since;
    const auto start = std::chrono::steady_clock::now();
    for (int f = 1; f <= kFrames && std::chrono::steady_clock::now() - start < kInputBudget; ++f) {
        if (f % kEditEvery == 0) {
            edit(kept, since, rng);
            since.clear(); // an edit starts the history over, as in the window
        }
        since.emplace_back(kept);
        World fresh = kept; // a copy starts without the model's caches
        // The book model's grid and skips must give the plain all-pairs transcription's bits.
        const bool book = kept.params.model == ModelKind::Book;
        World reference = book ? kept : World();
        // The exact model lets nothing sink into anything: overlaps a scene starts with (or an
        // edit makes) may stay while they part, but the deepest never grows.
        const bool exact = kept.params.model == ModelKind::Exact;
        const double overlapBefore = exact ? deepestOverlap(kept) : 0.0;
        const StepResult a = kept.step();
        const StepResult b = fresh.step();
        compare(kept, fresh, scene);
        if (book) {
            // World::step() with the book model in its reference mode: the frame's scripted
            // pushes, then the update.
            for (const Push &push : reference.pushes) {
                if (push.frame == reference.frame && push.marble >= 0 && push.marble < reference.marbleCount())
                    reference.push(push.marble, push.at);
            }
            BookModel allPairs;
            allPairs.setReferenceMode(true);
            allPairs.step(reference);
            ++reference.frame;
            compare(kept, reference, scene, "the all-pairs book model's");
        }
        if (a.finite != b.finite || a.badMarble != b.badMarble)
            fail(kept, "the report of a marble that left finite numbers differs", a.badMarble, scene);
        int bad = -1;
        for (int i = 0; i < kept.marbleCount() && bad < 0; ++i) {
            if (!finite(kept.position[static_cast<std::size_t>(i)]) || !finite(kept.velocity[static_cast<std::size_t>(i)]))
                bad = i;
        }
        if (a.finite != (bad < 0) || (!a.finite && a.badMarble != bad))
            fail(kept, "the step misreported whether every marble is finite", bad, scene);
        if (!a.finite)
            break; // the window stops the run here (and the CLI exits with code 3)
        if (exact) {
            double scale = std::max(1.0, std::max(kept.stage.width, kept.stage.height));
            for (const double r : kept.radius)
                scale = std::max(scale, r);
            if (deepestOverlap(kept) > overlapBefore + 1e-9 * scale)
                fail(kept, "an overlap grew", -1, scene);
        }
        if (tooFast(kept))
            break;
    }
    return 0;
}
