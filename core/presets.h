#pragma once

#include "core/world.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace marbles {

/// How the window best shows a preset, where its lesson needs more than the teacher's own view:
/// applied as the preset opens (the teacher can change it back at once).
struct PresetView {
    std::optional<bool> vectors; ///< collision vectors on or off (unset: as they are)
    std::optional<bool> trails;  ///< trails on or off (unset: as they are)
    int selectedMarble = -1;     ///< selected (inspected, plotted, its trail kept long), or -1
};

/// A built-in scene, shared by the app's Presets menu, the tests and the benchmarks.
struct PresetInfo {
    std::string id;          ///< "four-marbles", "pins", "masses", "newtons-cradle", "pachinko", "brownian"
    std::string title;       ///< menu text
    std::string description; ///< one sentence for a teacher
    PresetView view = {};    ///< how the window shows it
};

/// The built-in presets, in menu order; the first is the default scene.
const std::vector<PresetInfo> &presets();

/// Builds preset `id` into `out` (replacing it); false for an unknown id.
bool makePreset(std::string_view id, World &out);

/// The default scene: the chapter's four marbles of different sizes (Figure 11.8).
World defaultScene();

/// The "crowd" reference scene: n marbles, radii uniform in [4, 12] px, one per 30-px grid cell
/// with jitter (packing about 0.24), walls on, e = 1, friction 0, zero threshold 0, speeds
/// uniform in [0, 4.17] px/frame in random directions, mass pi r^2. Only a fraction
/// `movingFraction` of the marbles (chosen at random) moves; the rest start at rest.
/// The same (n, seed, movingFraction) gives the same scene on every machine.
World makeCrowd(int n, std::uint64_t seed, double movingFraction = 1.0);

/// The crowd with `giants` marbles of radius `giantRadius` (mass pi r^2, moving or not like the
/// others) spread across the stage, in turn a quarter of its height above and below its middle,
/// and the marbles they would overlap taken out. A scene whose grids are sized from the small
/// marbles (RadiusSplit), for benchmarks and tests.
World makeCrowdWithGiants(int n, std::uint64_t seed, int giants, double giantRadius, double movingFraction = 1.0);

/// A gas: 2,000 marbles of radius uniform in [1, 3] px at speeds uniform in [0, 60] px/frame in
/// random directions, one per 60 x 56 px cell of a 3000 x 2250 stage, walls on, e = 1, friction
/// and zero threshold 0: each moves many diameters a frame, far from the others.
World makeSparseGas();

/// A small deterministic random source (SplitMix64), identical on every platform.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : m_state(seed) {}
    /// Next 64 random bits.
    std::uint64_t next();
    /// Uniform in [0, 1), 53 random bits.
    double uniform();
    /// Uniform in [lo, hi).
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    /// An index in [0, count), count > 0: next() % count (the remainder's bias, under
    /// count / 2^64, does not matter to the tests and fuzzers that draw them).
    int below(std::uint64_t count) { return static_cast<int>(next() % count); }

private:
    std::uint64_t m_state;
};

} // namespace marbles
