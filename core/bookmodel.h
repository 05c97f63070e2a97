#pragma once

#include "core/broadphase.h"
#include "core/world.h"

#include <cstdint>
#include <span>
#include <vector>

namespace marbles {

/// A uniform grid whose bodies move one at a time: the book model updates marbles in place, so
/// the grid must follow each marble as soon as it moves. Each bucket holds a few bodies inline
/// (one half cache line) and spills the rest to an overflow list; moving a body is O(bucket),
/// and nothing is allocated in steady state.
class MovingGrid {
public:
    /// Puts bodies 0..count-1 at `points` into the buckets of `geometry`.
    void build(const GridGeometry &geometry, const Vec2 *points, int count);
    /// Bodies held.
    int size() const { return static_cast<int>(m_bucketOf.size()); }
    /// Moves body i to the bucket of `to` (no-op when the bucket is unchanged).
    void update(int i, Vec2 to);
    /// Appends to `out` every body except `self` in the 3 x 3 cells around `at`, each once,
    /// in no particular order.
    void gather(int self, Vec2 at, std::vector<int> &out) const;

private:
    static constexpr int inlineCapacity = 7;
    struct Bucket {
        std::int32_t count = 0;
        std::int32_t items[inlineCapacity];
    };

    int bucketOf(Vec2 p) const;
    void insert(int i, int b);
    void remove(int i, int b);

    GridGeometry m_geometry;
    std::vector<Bucket> m_buckets;
    std::vector<std::vector<int>> m_overflow; // bodies past the inline capacity, per bucket
    std::vector<int> m_bucketOf;              // bucket of each body
};

/// The chapter's updateMarbles(), verbatim (PHYSICS.md, model "book"): one explicit update per
/// frame, marbles processed in scene order and in place, with the book's arithmetic, flaws included.
/// Large scenes use a uniform grid for the pin and marble tests; its candidates are tested in
/// scene order, so the results are bit-identical to the all-pairs loop (tested).
class BookModel final : public Stepper {
public:
    /// Marble count from which the marble grid is used (below it, all pairs are cheaper).
    static constexpr int kGridMinMarbles = 48;
    /// Pin count from which the pin grid is used.
    static constexpr int kGridMinPins = 24;

    /// Advances one frame. Consumes pending pushes (acceleration) and leaves it zero.
    void step(World &world) override;

    /// Reference mode (true): the plain transcription, all pairs and no skipping of sleeping
    /// marbles or zero terms. For tests and benchmarks; the results are the same bits either way.
    void setReferenceMode(bool on) { m_forceAllPairs = on; }

private:
    void prepare(const World &world);
    std::span<const int> pinCandidates(Vec2 oldPosition, Vec2 newPosition);

    bool m_forceAllPairs = false;
    bool m_useMarbleGrid = false;
    bool m_usePinGrid = false;
    MovingGrid m_marbleGrid;
    UniformGrid m_pinGrid;
    std::vector<Vec2> m_gridPositions; // positions the marble grid was left with
    std::vector<double> m_gridRadii;
    std::vector<int> m_allPins;    // 0..pins-1
    std::vector<int> m_candidates;
    std::vector<int> m_widened;
    std::vector<std::uint64_t> m_pinMark;
    std::uint64_t m_stamp = 0;
};

/// The book's reflection off a pin at `pin` for a marble restored to `p` moving with `v`:
/// returns false (and leaves `v` alone) where the book would divide by zero.
bool bookReflectOffPin(Vec2 p, Vec2 pin, Vec2 &v, HitRecord *record = nullptr);

/// The book's marble-to-marble response: marble i (restored to `pi`, velocity `vi`, mass `mi`)
/// hit marble j (at `pj`, velocity `vj`, mass `mj`). Returns false, leaving both velocities
/// alone, where the book would divide by zero.
bool bookShareCollision(Vec2 pi, Vec2 &vi, double mi, Vec2 pj, Vec2 &vj, double mj,
                        HitRecord *record = nullptr);

} // namespace marbles
