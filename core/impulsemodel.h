#pragma once

#include "core/broadphase.h"
#include "core/largebuffer.h"
#include "core/world.h"

#include <cstdint>
#include <vector>

namespace marbles {

/// The "impulse" model of PHYSICS.md, what games do: fixed sub-steps of h = 1/substeps frame,
/// each a semi-implicit Euler step (velocity first: drag factor (1-k)^h, gravity; then
/// position), followed by one pass that finds overlaps on a uniform grid and resolves each with
/// the exact model's momentum-conserving impulse plus a positional correction.
/// Its error against the exact model shrinks in proportion to h (first order).
///
/// Pairs are resolved one after another (each sees the corrections of the ones before). Each
/// sub-step copies the marbles into bucket order (a stable counting sort), and pairs are taken
/// in that order: bucket by bucket in row-major order, each marble with the later marbles of
/// its bucket and then with the forward half of its neighbourhood. Neighbours are thus side by
/// side in memory, and every candidate is examined once. A few marbles far larger than the rest
/// (RadiusSplit) are left out of the grid: they come last in the order, and after the buckets
/// each is paired with the marbles of the buckets within its reach (in slot order), then with
/// the other oversize ones after it.
///
/// Sleeping: a marble at rest (velocity exactly 0, no gravity) that overlapped nothing in the
/// last sub-step is asleep. Two sleeping marbles did not overlap then and have not moved since,
/// so their pair test must fail again: buckets whose pairs would all be between sleepers are
/// skipped, and sleepers are neither moved nor tested against pins and walls. Results are bit
/// for bit those of testing everything; a sleeper wakes as soon as anything touches it, and
/// any change to it between frames (position, radius, velocity, pins, stage) wakes it too.
/// While few marbles are awake, the bucket order is not sorted afresh each sub-step: the
/// awake marbles are moved within the last sub-step's order (the same order the full sort
/// gives), and only they and the sleepers they wake go through the Euler step and the pin and
/// wall pass.
class ImpulseModel final : public Stepper {
public:
    /// Advances `world` one frame. Consumes pending pushes as an instant velocity change;
    /// leaves acceleration zero; does not touch world.frame.
    void step(World &world) override;
    bool leftAllFinite() const override { return m_leftAllFinite; }

    /// Marbles asleep after the last step (they cost next to nothing in the next one).
    int sleepingCount() const { return m_sleeperCount; }
    /// Sub-steps so far whose bucket order was updated for the changed marbles only.
    std::int64_t partialSortCount() const { return m_partialSorts; }

private:
    /// A marble's shape and place, in bucket order (what the distance test reads).
    struct Body {
        double x;
        double y;
        double r;
        int id;    ///< index in the world (scene order)
        int flags; ///< asleep, touched (below)
    };

    static constexpr int asleep = 1;  ///< at rest and touching nothing since the last sub-step
    static constexpr int touched = 2; ///< overlapped a marble in this sub-step's pair pass
    static constexpr int settled = 4; ///< done by this sub-step's pin and wall pass (asserted once)
    /// The pair pass tests the buckets below a marble in windows of this many slots, and may
    /// read as many past the last marble (padding).
    static constexpr int windowPadding = 3;
    /// While at most n / partialSortShare marbles are awake, a sub-step moves only them within
    /// the kept bucket order (see resortChanged()) instead of sorting every marble again.
    static constexpr int partialSortShare = 16;

    void wakeSleepers(const World &world);
    /// Puts the marbles in bucket order; returns whether it only moved the marbles that may
    /// have changed (then only m_visit needs the pin and wall pass), not sorted them all.
    bool sortIntoBuckets(const World &world, int awake);
    void sortAll(const World &world);
    bool resortChanged(const World &world);
    int moveToBucket(int id, int from, int to);
    void markActive(int bucket);
    [[gnu::noinline, gnu::cold]] void wake(int slot, int bucket);
    int nextActive(int bucket) const;
    void resolvePairs(World &world, double e, std::int64_t hitFrame);
    /// Resolves an overlapping pair (slots si and t, si in `bucket`): wakes, impulse, correction.
    /// Out of line: the pair pass's loops stay small, and most candidates do not overlap.
    [[gnu::noinline]] void resolvePair(World &world, double e, std::int64_t hitFrame, int bucket, int si, int t);

    /// The oversize marbles' place in m_start: the bucket after the lattice's.
    int oversizeBucket() const { return m_geometry.bucketCount(); }
    void resolveOversizePairs(World &world, double e, std::int64_t hitFrame);

    GridGeometry m_geometry;
    RadiusSplit m_split;            // this frame's (the lattice is sized for radii up to m_split.cut)
    UniformGrid m_pinGrid;          // rebuilt every frame
    LargeVector<int> m_bucketOf;    // per marble (scene order): its bucket this sub-step
    LargeVector<int> m_start;       // per bucket, and the oversize marbles: first slot; then n
    LargeVector<Body> m_bodies;     // per slot, then padding (see resolvePairs())
    LargeVector<std::uint64_t> m_active; // per bucket, one bit: has pairs that may do something
    bool m_allActive = true;             // every bucket is visited (m_active unused)

    // The slot order kept from one sub-step to the next. It is valid (m_sorted) for the lattice
    // m_geometry and the marbles as they were left, except those listed in m_changed: the ones
    // the last pin and wall pass left awake, and the sleepers woken since. These are all the
    // marbles awake, unless the list outgrew the partial sort's limit (n / partialSortShare) and was cut.
    bool m_sorted = false;
    std::int64_t m_partialSorts = 0;
    LargeVector<int> m_slotOf;   // per marble (scene order): its slot, when m_slotsKnown
    bool m_slotsKnown = false;   // (the full sort leaves it to the first partial one)
    std::vector<int> m_changed;  // marbles whose slot contents must be read again from the world
    std::vector<int> m_visit;    // after a partial sort: the marbles awake in this sub-step

    // Sleeping (see step()): per marble, whether it ended the last sub-step asleep, and the
    // position and radius it was asleep with; plus the pins and stage it was checked against.
    LargeVector<unsigned char> m_sleepy;
    int m_sleeperCount = 0;
    // Every position and velocity finite after the last step: each marble's the step settled,
    // seen on the way, and the sleepers', finite when they fell asleep and the same bits since.
    bool m_leftAllFinite = false;
    LargeVector<Vec2> m_sleepPosition;
    LargeVector<double> m_sleepRadius;
    std::vector<Vec2> m_sleepPins;
    Stage m_sleepStage;
};

} // namespace marbles
