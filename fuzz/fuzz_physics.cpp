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
// model gives the bits of its plain all-pairs transcription, that in the exact model the deepest
// overlap never grows and keeping its sleepers' layer (or never keeping it) gives the same bits,
// and that the exact model (and the impulse model without gravity) keeps the energy and momentum
// balance of PHYSICS.md. Besides scene files, an input can name a generated crowd ("#crowd" and
// a few bytes), so that the scenes that only larger counts reach (the exact model's sleepers'
// layer, the grids' overflow lists, the impulse model's partial sort) are fuzzed too.

#include "core/bookmodel.h"
#include "core/exactmodel.h"
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
#include <cstring>
#include <numeric>
#include <optional>
#include <string>

namespace {

using namespace marbles;
using namespace marbles::fuzzbits;

// Kept small so that each input runs in milliseconds: the bugs this looks for need a few
// marbles, not thousands.
// Enough marbles and pins for every model's grid (the book model's from 48 marbles and 24 pins).
constexpr int kMaxMarbles = 80;
// Generated crowds: from the book model's grid (48 marbles) through the exact model's (more than
// 64 bodies) to past its sleepers' layer's threshold (256 marbles).
constexpr int kCrowdMin = 48;
constexpr int kCrowdMax = 320;
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

/// The deepest overlap of a marble with another, a pin or (with walls) the stage's edge, px
/// (0 when none overlaps).
double deepestOverlap(const World &w)
{
    double deepest = 0.0;
    const int n = w.marbleCount();
    const auto left = [&](int i) { return w.position[static_cast<std::size_t>(i)].x - w.radius[static_cast<std::size_t>(i)]; };
    bool sortable = true;
    for (int i = 0; i < n; ++i) {
        const Vec2 p = w.position[static_cast<std::size_t>(i)];
        const double r = w.radius[static_cast<std::size_t>(i)];
        if (w.stage.walls)
            deepest = std::max({deepest, r - p.x, p.x + r - w.stage.width, r - p.y, p.y + r - w.stage.height});
        for (const Vec2 q : w.pins)
            deepest = std::max(deepest, r - distance(p, q));
        sortable = sortable && std::isfinite(left(i)) && std::isfinite(p.x + r);
    }
    // Two marbles overlap only if their spans along x do: sorted by their left edges, each is
    // tested against those whose left edge is not past its right edge (all pairs if a span is
    // not finite). The crowds of 320 marbles cost 20 times less this way.
    std::vector<int> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    if (sortable)
        std::sort(order.begin(), order.end(), [&](int a, int b) { return left(a) < left(b); });
    for (std::size_t a = 0; a < order.size(); ++a) {
        const int i = order[a];
        const Vec2 p = w.position[static_cast<std::size_t>(i)];
        const double r = w.radius[static_cast<std::size_t>(i)];
        const double right = p.x + r;
        for (std::size_t b = a + 1; b < order.size() && (!sortable || left(order[b]) <= right); ++b) {
            const int j = order[b];
            deepest = std::max(deepest, r + w.radius[static_cast<std::size_t>(j)] - distance(p, w.position[static_cast<std::size_t>(j)]));
        }
    }
    return deepest;
}

/// What the models must keep or lose (PHYSICS.md): the mechanical energy, kinetic (with each
/// marble's pending push, which acts as an instant velocity change at the start of the frame)
/// plus gravity's potential -m g.p, the momentum and the angular momentum (about the one pin if
/// there is exactly one, else the stage's centre); with the sizes of their terms, against which
/// rounding is measured.
struct Balance {
    double energy = 0.0;
    double energyScale = 0.0; // sum of the terms' sizes
    Vec2 momentum;
    double momentumScale = 0.0; // sum of m |v|
    double angular = 0.0;
    double angularScale = 0.0; // sum of m |r| |v|

    explicit Balance(const World &w)
    {
        const Vec2 g = w.params.gravity;
        const Vec2 centre = w.pins.size() == 1 ? w.pins.front() : Vec2{0.5 * w.stage.width, 0.5 * w.stage.height};
        for (int i = 0; i < w.marbleCount(); ++i) {
            const auto k = static_cast<std::size_t>(i);
            const double m = w.mass[k];
            const Vec2 p = w.position[k];
            const Vec2 v{w.velocity[k].x + w.acceleration[k].x, w.velocity[k].y + w.acceleration[k].y};
            const double kinetic = 0.5 * m * (v.x * v.x + v.y * v.y);
            const double potential = -m * (g.x * p.x + g.y * p.y);
            energy += kinetic + potential;
            energyScale += kinetic + std::abs(potential);
            momentum.x += m * v.x;
            momentum.y += m * v.y;
            const double speed = std::sqrt(v.x * v.x + v.y * v.y);
            momentumScale += m * speed;
            const Vec2 r{p.x - centre.x, p.y - centre.y};
            angular += m * (r.x * v.y - r.y * v.x);
            angularScale += m * std::sqrt(r.x * r.x + r.y * r.y) * speed;
        }
    }
    bool finite() const
    {
        return std::isfinite(energyScale) && std::isfinite(momentumScale) && std::isfinite(angularScale);
    }
};

// Rounding allowed in a frame's balance of energy, momentum and angular momentum, relative to the
// size of their terms: about 1e-16 per operation, over the thousands of collisions a wedged
// marble has before the exact model's guards stop it.
constexpr double kBalanceTolerance = 1e-9;

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
void edit(World &w, const std::vector<Snapshot> &since, int maxMarbles, SplitMix64 &rng)
{
    const double width = w.stage.width;
    const double height = w.stage.height;
    const auto anywhere = [&] { return Vec2{rng.uniform(0.0, width), rng.uniform(0.0, height)}; };
    const auto speed = [&] { return Vec2{rng.uniform(-8.0, 8.0), rng.uniform(-8.0, 8.0)}; };
    const int n = w.marbleCount();
    const int i = n > 0 ? rng.below(static_cast<std::uint64_t>(n)) : -1;
    switch (rng.below(18)) {
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
        if (n < maxMarbles)
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
            w.removePin(rng.below(w.pins.size()));
        break;
    case 10:
        w.stage.walls = !w.stage.walls;
        break;
    case 11:
        // Inside every model's range: [0, 1) for exact and impulse.
        w.params.friction = rng.below(2) == 0 ? 0.0 : rng.uniform(0.0, 0.9);
        break;
    case 12:
        w.params.zeroThreshold = rng.below(2) == 0 ? 0.0 : rng.uniform(0.0, 1.0);
        break;
    case 13:
        w.params.gravity = rng.below(2) == 0 ? Vec2{} : Vec2{rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)};
        break;
    case 14:
        // The exact and impulse models' restitution, [0, 1] (the book model has none).
        w.params.restitution = rng.below(2) == 0 ? 1.0 : rng.uniform(0.0, 1.0);
        break;
    case 15:
        w.setMassScale(rng.uniform(0.01, 100.0));
        break;
    case 16:
        w.params.shortCircuit = !w.params.shortCircuit;
        break;
    default:
        // Step Back: an earlier frame written into the same world.
        if (!since.empty())
            since[rng.below(since.size())].restoreInto(w);
        break;
    }
}

/// What World::step() does, with `model` in place of the world's own: the frame's scripted
/// pushes, the update, the frame count.
void stepWith(Stepper &model, World &w)
{
    w.applyScriptedPushes();
    model.step(w);
    ++w.frame;
}

/// Aborts if the frame from `start` to `after` broke the balance of PHYSICS.md: the mechanical
/// energy never grows (e <= 1, drag, the zero threshold and the exact model's guards' freezing only
/// take energy away); none is lost with e = 1 and neither friction, gravity nor zero threshold;
/// without walls, pins, gravity and zero threshold the momentum is multiplied by the drag's 1 - k
/// and nothing else (pair impulses keep it), and in the exact model the angular momentum too, also
/// with one pin, about it. (Between events p(t) = a + b phi1(t) and v(t) = b e^(-lambda t), so
/// m p x v = m a x b e^(-lambda t) decays like the momentum; a pair's impulses are opposite and along
/// the line of the centres at contact, so their torques cancel, and a pin's impulse acts along the
/// line through the pin, so it has no torque about it. An impulse along any other line keeps energy
/// and momentum but not this.) The exact model holds all of this in continuous time. The impulse
/// model holds it without gravity (its impulses act only on approaching pairs, and its positional
/// correction moves no velocity), the angular momentum aside (that correction moves marbles without
/// their velocity, which changes it); with gravity its explicit sub-steps can gain energy, and the
/// caller checks it only without. In the exact model a frame in which the guard against endless
/// collision sequences froze a marble (which takes energy and momentum away) is excused: a suspect
/// frame is stepped again from `start` to count them.
void checkBalance(const Balance &before, const World &after, const Snapshot &start, const std::string &scene)
{
    const Balance now(after);
    if (!now.finite())
        return;
    const Params &params = after.params;
    const double energyTolerance = kBalanceTolerance * std::max(before.energyScale, now.energyScale);
    if (!(now.energy <= before.energy + energyTolerance))
        fail(after, "the mechanical energy grew", -1, scene);
    const bool noGravity = params.gravity == Vec2{};
    const bool elastic
        = params.restitution == 1.0 && params.friction == 0.0 && params.zeroThreshold == 0.0 && noGravity;
    // Nothing acts on the marbles from outside but the drag (and the pins, counted apart).
    const bool unwalled = !after.stage.walls && noGravity && params.zeroThreshold == 0.0;
    const bool free = unwalled && after.pins.empty();
    const double decay = 1.0 - params.friction;
    const Vec2 expected{decay * before.momentum.x, decay * before.momentum.y};
    const double momentumTolerance = kBalanceTolerance * std::max(before.momentumScale, now.momentumScale);
    const bool energyLost = elastic && !(before.energy - now.energy <= energyTolerance);
    const bool momentumChanged = free
        && !(std::abs(now.momentum.x - expected.x) <= momentumTolerance
             && std::abs(now.momentum.y - expected.y) <= momentumTolerance);
    const bool exact = params.model == ModelKind::Exact;
    const double angularTolerance = kBalanceTolerance * std::max(before.angularScale, now.angularScale);
    const bool angularChanged = unwalled && after.pins.size() <= 1 && exact
        && !(std::abs(now.angular - decay * before.angular) <= angularTolerance);
    if (!energyLost && !momentumChanged && !angularChanged)
        return;
    const char *const what = energyLost        ? "an elastic frame lost energy"
                             : momentumChanged ? "the momentum changed otherwise than by the drag"
                                               : "the angular momentum changed otherwise than by the drag";
    if (!exact)
        fail(after, what, -1, scene);
    World again = after;
    start.restoreInto(again);
    ExactModel model;
    stepWith(model, again);
    compare(after, again, scene, "the exact model's stepped again");
    if (model.lastFrozenCount() == 0)
        fail(after, what, -1, scene);
}

/// A crowd described by the bytes after "#crowd": its size, model, share of moving marbles,
/// pins, substeps, and up to three giants (marbles the grids leave out, see RadiusSplit) and
/// their radius. The rest of the scene is marbles-cli gen crowd's (walls, e = 1, no friction or
/// gravity; edits change those).
World crowdFromBytes(const std::uint8_t *data, std::size_t size, std::uint64_t hash)
{
    const auto byte = [&](std::size_t k) -> unsigned { return k < size ? data[k] : 0u; };
    const int n = kCrowdMin + static_cast<int>((byte(0) | byte(1) << 8) % (kCrowdMax - kCrowdMin + 1));
    static constexpr double moving[] = {0.0, 0.005, 0.02, 0.0625, 0.25, 1.0};
    const int giants = static_cast<int>(byte(6) % 4);
    const double giantRadius = 40.0 + 10.0 * (byte(7) % 8);
    World w = makeCrowdWithGiants(n, hash, giants, giantRadius, moving[byte(3) % std::size(moving)]);
    w.params.model = static_cast<ModelKind>(byte(2) % 3);
    w.params.substeps = 1 + static_cast<int>(byte(5) % kSubstepsAtMost);
    SplitMix64 rng(hash ^ 0x9e3779b97f4a7c15ull);
    for (unsigned k = byte(4) % 40; k > 0; --k)
        w.addPin({rng.uniform(0.0, w.stage.width), rng.uniform(0.0, w.stage.height)});
    return w;
}

std::string describeCrowd(const World &w)
{
    return "a generated crowd of " + std::to_string(w.marbleCount()) + " marbles and " + std::to_string(w.pins.size())
        + " pins (replay the input file)";
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    std::string scene(reinterpret_cast<const char *>(data), size);
    // The edits follow from the input (its FNV-1a hash), so that a finding replays.
    std::uint64_t hash = 1469598103934665603ull;
    for (const unsigned char c : scene)
        hash = (hash ^ c) * 1099511628211ull;
    static constexpr char crowdTag[] = "#crowd";
    constexpr std::size_t tagLength = sizeof crowdTag - 1;
    World kept;
    int maxMarbles = kMaxMarbles;
    if (size >= tagLength && std::memcmp(data, crowdTag, tagLength) == 0) {
        kept = crowdFromBytes(data + tagLength, size - tagLength, hash);
        scene = describeCrowd(kept);
        maxMarbles = kCrowdMax;
    } else {
        SceneLoad load = parseScene(scene, "input");
        if (!load.ok)
            return 0;
        kept = std::move(load.world);
        if (kept.marbleCount() > kMaxMarbles || static_cast<int>(kept.pins.size()) > kMaxPins
            || kept.params.substeps > kSubstepsAtMost || tooFast(kept))
            return 0;
    }
    SplitMix64 rng(hash);
    // The exact model with its sleepers' layer always kept (wherever there is a grid and no
    // gravity) and never kept: each keeps its caches from frame to frame, and both must give
    // the bits of the world's own model.
    ExactModel alwaysLayer;
    alwaysLayer.setSleeping(ExactModel::Sleeping::Always);
    ExactModel neverLayer;
    neverLayer.setSleeping(ExactModel::Sleeping::Never);
    World withLayer;
    World withoutLayer;
    std::vector<Snapshot> since;
    const auto start = std::chrono::steady_clock::now();
    for (int f = 1; f <= kFrames && std::chrono::steady_clock::now() - start < kInputBudget; ++f) {
        if (f % kEditEvery == 0) {
            edit(kept, since, maxMarbles, rng);
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
        // Only where the layer can be kept (a grid, no gravity), and without it only where the
        // world's own model may keep it: the exact model's worst frames (marbles wedged, which it
        // collides thousands of times a frame) take seconds under the sanitizers.
        const bool layerPossible = exact && kept.params.gravity == Vec2{}
            && kept.marbleCount() + static_cast<int>(kept.pins.size()) > ExactModel::singleCellItems;
        const bool layerByDefault = layerPossible && kept.marbleCount() >= ExactModel::sleepingLayerFrom;
        // The same state; a World's copy has no model of its own, these are stepped by the two
        // kept above.
        if (layerPossible)
            withLayer = kept;
        if (layerByDefault)
            withoutLayer = kept;
        // The balance of energy and momentum (checkBalance) in the exact model, and in the impulse
        // model without gravity; not in a frame with a scripted push (it adds energy before the
        // update), nor with a marble as wide as the stage (held centred between the walls, which
        // may lift it).
        const bool scripted = std::any_of(kept.pushes.begin(), kept.pushes.end(),
                                          [&](const Push &push) { return kept.appliesNow(push); });
        const double side = std::min(kept.stage.width, kept.stage.height);
        const bool tooWide = kept.stage.walls
            && std::any_of(kept.radius.begin(), kept.radius.end(), [&](double r) { return !(2.0 * r < side); });
        const bool impulseWithoutGravity
            = kept.params.model == ModelKind::Impulse && kept.params.gravity == Vec2{};
        std::optional<Balance> before;
        if ((exact || impulseWithoutGravity) && !scripted && !tooWide)
            before.emplace(kept);
        const StepResult a = kept.step();
        const StepResult b = fresh.step();
        compare(kept, fresh, scene);
        if (book) {
            BookModel allPairs;
            allPairs.setReferenceMode(true);
            stepWith(allPairs, reference);
            compare(kept, reference, scene, "the all-pairs book model's");
        }
        if (layerPossible) {
            stepWith(alwaysLayer, withLayer);
            compare(kept, withLayer, scene, "the exact model's with its sleepers' layer always kept");
        }
        if (layerByDefault) {
            stepWith(neverLayer, withoutLayer);
            compare(kept, withoutLayer, scene, "the exact model's without its sleepers' layer");
        }
        if (a.finite != b.finite || a.badMarble != b.badMarble)
            fail(kept, "the report of a marble that left finite numbers differs", a.badMarble, scene);
        int bad = -1;
        for (int i = 0; i < kept.marbleCount() && bad < 0; ++i) {
            if (!isFinite(kept.position[static_cast<std::size_t>(i)]) || !isFinite(kept.velocity[static_cast<std::size_t>(i)]))
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
        if (before && before->finite())
            checkBalance(*before, kept, since.back(), scene);
        if (tooFast(kept))
            break;
    }
    return 0;
}
