#include "core/presets.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace marbles {

std::uint64_t SplitMix64::next()
{
    std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

double SplitMix64::uniform()
{
    return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

namespace {

void named(World &w, int i, const char *name, const char *color = "")
{
    w.info[i].name = name;
    w.info[i].color = color;
}

// Figure 11.8: four blue marbles of different sizes, at rest, with two scripted clicks so that
// a run shows the push, the friction decay and the book's collision sharing.
void fourMarbles(World &w)
{
    named(w, w.addMarble({180, 300}, 40), "large");
    named(w, w.addMarble({285, 305}, 20), "small");
    named(w, w.addMarble({560, 300}, 55), "largest");
    named(w, w.addMarble({600, 430}, 30), "medium");
    // Click on the left edge of the large marble: force (35, 0) * 10 / 50 = 7 px/frame^2,
    // enough to roll it into the small one.
    w.pushes.push_back({0, 0, {145, 300}, {}});
    // Later, a click below-right of the medium marble sends it up into the largest one.
    w.pushes.push_back({150, 3, {608.2, 456.8}, {}});
}

// Example 2: marbles among pins. The pins stand in a staggered field; the marbles start moving.
void pinsExample(World &w)
{
    for (int row = 0; row < 4; ++row) {
        for (int col = 0; col < 6; ++col) {
            const double x = 140 + col * 105 + (row % 2) * 52.5;
            const double y = 140 + row * 105;
            w.addPin({x, y});
        }
    }
    named(w, w.addMarble({90, 90}, 22, {7.5, 4.0}), "medium");
    named(w, w.addMarble({700, 520}, 30, {-6.0, -5.5}), "big");
    named(w, w.addMarble({400, 70}, 16, {1.0, 8.0}), "small");
    w.params.friction = 0.02;
}

// Example 3: marbles of different masses. A light marble runs into a heavy one at rest and
// bounces back (faster than it came in the book model); a heavy one rolls on towards two light
// ones and nudges the first.
void massesExample(World &w)
{
    named(w, w.addMarble({120, 180}, 12, {9, 0}), "light");
    named(w, w.addMarble({420, 180}, 60), "heavy");
    named(w, w.addMarble({140, 430}, 50, {6, 0}), "heavy mover");
    named(w, w.addMarble({440, 420}, 15), "light A");
    named(w, w.addMarble({480, 450}, 15), "light B");
    w.params.friction = 0.02;
}

// A row of five equal marbles just touching (distance = sum of radii is not a hit), and a
// sixth rolling into the row. Without friction the exact model passes the momentum along the
// row, as the real toy does; the book model shows something else.
void newtonsCradle(World &w)
{
    const double r = 20;
    for (int k = 0; k < 5; ++k)
        w.addMarble({400 + 2 * r * k, 300}, r);
    named(w, w.addMarble({150, 300}, r, {6, 0}), "striker");
    w.params.friction = 0;
    w.params.zeroThreshold = 0;
}

// A Pachinko board: staggered rows of pins and marbles falling under gravity.
void pachinko(World &w)
{
    for (int row = 0; row < 8; ++row) {
        const double y = 140 + row * 55;
        const double offset = (row % 2) * 25;
        for (double x = 50 + offset; x < 760; x += 50)
            w.addPin({x, y});
    }
    SplitMix64 rng(11);
    for (int k = 0; k < 8; ++k) {
        // One draw per statement: the order of a call's arguments is unspecified in C++, and the
        // scene must be the same whichever compiler built it (PHYSICS.md, Determinism).
        const double vx = rng.uniform(-1, 1);
        const double x = 120 + k * 80 + rng.uniform(-10, 10);
        const double y = 40 + rng.uniform(0, 40);
        w.addMarble({x, y}, 9, {vx, 0});
    }
    w.params.gravity = {0, 0.15};
    w.params.friction = 0.01;
    w.params.restitution = 0.8;
    w.params.substeps = 4;
}

// Brownian motion: one heavy marble among hundreds of small, fast ones. Nothing pushes it, yet
// it wanders: each small marble that hits it gives it a kick in a random direction (a random
// walk), and the heavier it is, the less it moves. The small marbles start on a jittered
// lattice, clear of the heavy one and of each other, in random directions.
void brownian(World &w)
{
    const Vec2 centre{400, 300};
    const double heavyRadius = 50;
    named(w, w.addMarble(centre, heavyRadius, {}, 500), "heavy", "#c0392b");
    SplitMix64 rng(29);
    const double r = 4;
    const double spacing = 24;
    for (double y = spacing / 2; y < w.stage.height; y += spacing) {
        for (double x = spacing / 2; x < w.stage.width; x += spacing) {
            // One draw per statement (see pachinko()).
            const double dx = rng.uniform(-5, 5);
            const double dy = rng.uniform(-5, 5);
            const double speed = rng.uniform(2, 5);
            const double angle = rng.uniform(0, 6.283185307179586);
            const Vec2 p{x + dx, y + dy};
            if (distance(p, centre) < heavyRadius + r + 6)
                continue;
            w.addMarble(p, r, {speed * std::cos(angle), speed * std::sin(angle)});
        }
    }
    w.params.friction = 0;
    w.params.zeroThreshold = 0;
    w.params.restitution = 1;
    // The exact model, where each kick conserves momentum; in the book model the heavy marble
    // hardly moves (a comparison worth showing).
    w.params.model = ModelKind::Exact;
}

struct PresetEntry {
    PresetInfo info;
    void (*build)(World &);
};

const std::vector<PresetEntry> &entries()
{
    static const std::vector<PresetEntry> list = {
        {{"four-marbles", "Four marbles (Figure 11.8)",
          "Four marbles of different sizes; click one to push it: clicked as far from the centre, heavier ones move less."},
         fourMarbles},
        {{"pins", "Marbles among pins (Example 2)",
          "Marbles bounce off fixed pins: the part of the velocity along the line to the pin is reversed."},
         pinsExample},
        {{"masses", "Different masses (Example 3)",
          "A light marble hits a heavy one: the book sends it back faster than it came (its speed shared out by "
          "the mass ratio, which makes energy); the exact model sends it back slower and the heavy one on."},
         massesExample},
        {{"newtons-cradle", "Newton's cradle",
          "A row of touching marbles struck at one end: compare how each model passes the momentum on."},
         newtonsCradle},
        {{"pachinko", "Pachinko board", "Marbles fall under gravity through staggered rows of pins."},
         pachinko},
        // The heavy marble selected, its long trail drawn: its random walk is the lesson, which
        // 805 marbles' collision vectors would bury.
        {{"brownian", "Brownian motion",
          "A heavy marble among hundreds of small fast ones wanders at random, kicked by their hits.",
          {false, true, 0}},
         brownian},
    };
    return list;
}

} // namespace

const std::vector<PresetInfo> &presets()
{
    static const std::vector<PresetInfo> list = [] {
        std::vector<PresetInfo> out;
        for (const PresetEntry &e : entries())
            out.push_back(e.info);
        return out;
    }();
    return list;
}

bool makePreset(std::string_view id, World &out)
{
    for (const PresetEntry &e : entries()) {
        if (e.info.id == id) {
            World w;
            e.build(w);
            w.refreshMasses();
            out = std::move(w);
            return true;
        }
    }
    return false;
}

World defaultScene()
{
    World w;
    makePreset(presets().front().id, w);
    return w;
}

World makeCrowd(int n, std::uint64_t seed, double movingFraction)
{
    World w;
    n = std::max(n, 0);
    constexpr double cell = 30.0;
    const int columns = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n)))));
    const int rows = std::max(1, (n + columns - 1) / columns);
    w.stage = {columns * cell, rows * cell, true};
    w.params.model = ModelKind::Exact;
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    w.params.restitution = 1.0;

    w.position.reserve(n);
    SplitMix64 rng(seed);
    for (int k = 0; k < n; ++k) {
        const double r = rng.uniform(4.0, 12.0);
        // Jitter keeps the marble inside its own cell, so the scene starts without overlaps.
        const double slack = cell / 2 - r;
        const double x = (k % columns + 0.5) * cell + rng.uniform(-slack, slack);
        const double y = (k / columns + 0.5) * cell + rng.uniform(-slack, slack);
        const double speed = rng.uniform(0.0, 4.17);
        const double angle = rng.uniform(0.0, 2 * std::numbers::pi);
        const bool moving = rng.uniform() < movingFraction;
        const Vec2 v = moving ? Vec2{speed * std::cos(angle), speed * std::sin(angle)} : Vec2{};
        w.addMarble({x, y}, r, v, std::numbers::pi * r * r);
    }
    return w;
}

World makeCrowdWithGiants(int n, std::uint64_t seed, int giants, double giantRadius, double movingFraction)
{
    World w = makeCrowd(n, seed, movingFraction);
    constexpr double cell = 30.0; // makeCrowd's lattice
    const int columns = static_cast<int>(std::lround(w.stage.width / cell));
    std::vector<int> giant;
    for (int k = 0; k < giants && n > 0; ++k) {
        const double x = std::clamp(w.stage.width * (k + 0.5) / giants, giantRadius, w.stage.width - giantRadius);
        const double y = std::clamp(w.stage.height * (0.5 + (k % 2 == 0 ? -0.25 : 0.25)), giantRadius,
                                    w.stage.height - giantRadius);
        // The marble of the lattice cell there becomes the giant.
        const int i = std::min(n - 1, static_cast<int>(y / cell) * columns + static_cast<int>(x / cell));
        w.position[i] = {x, y};
        w.setRadius(i, giantRadius);
        w.setExplicitMass(i, std::numbers::pi * giantRadius * giantRadius);
        giant.push_back(i);
    }
    for (int i = w.marbleCount() - 1; i >= 0; --i) {
        if (std::find(giant.begin(), giant.end(), i) != giant.end())
            continue;
        bool clear = true;
        for (const int g : giant)
            clear = clear && distance(w.position[i], w.position[g]) > w.radius[i] + w.radius[g];
        if (!clear) {
            w.removeMarble(i);
            for (int &g : giant)
                g -= g > i ? 1 : 0;
        }
    }
    return w;
}

World makeSparseGas()
{
    World w;
    w.stage = {3000, 2250, true};
    w.params.friction = 0.0;
    w.params.zeroThreshold = 0.0;
    w.params.restitution = 1.0;
    SplitMix64 rng(7);
    for (int k = 0; k < 2000; ++k) {
        const Vec2 p{(k % 50 + 0.5) * 60.0, (k / 50 + 0.5) * 56.0};
        // One draw per statement (see pachinko()).
        const double r = rng.uniform(1, 3);
        const double angle = rng.uniform(0, 6.283185307179586);
        const double speed = rng.uniform(0, 60);
        w.addMarble(p, r, {speed * std::cos(angle), speed * std::sin(angle)});
    }
    return w;
}

} // namespace marbles
