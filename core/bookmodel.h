#pragma once

#include "core/broadphase.h"
#include "core/largebuffer.h"
#include "core/world.h"

#include <cstdint>
#include <span>
#include <vector>

namespace marbles {

/// A uniform grid whose bodies move one at a time: the book model updates marbles in place, so
/// the grid must follow each marble as soon as it moves. Each bucket holds a few bodies inline
/// (a quarter of a cache line) and spills the rest to an overflow list, whose nodes all buckets
/// share; moving a body is O(bucket), and nothing is allocated in steady state.
class MovingGrid {
public:
    /// Puts bodies 0..count-1 at `points` into the buckets of `geometry`.
    void build(const GridGeometry &geometry, const Vec2 *points, int count);
    /// Bodies held.
    int size() const { return static_cast<int>(m_bucketOf.size()); }
    /// Moves body i to bucket b (no-op when it is there): b must be the bucket of its position,
    /// as forEachNear() returns it. Not for a body left out.
    void moveTo(int i, int b);
    /// Takes body i out of the grid (until the next build): forEachNear() no longer visits it.
    void leaveOut(int i);
    /// Calls `visit(j)` for every body j (self included) in the 3 x 3 cells around `at`, each
    /// once, in no particular order; also calls `visit(size())` for some empty slots, which the
    /// caller must treat as a sure miss. `visit` must not move bodies. Returns the bucket of
    /// `at` (the neighbourhood's centre).
    template<typename Visit>
    int forEachNear(Vec2 at, Visit &&visit) const;
    /// Calls `visit(j)` for every body j in the cells meeting the box [x0, x1] x [y0, y1], each
    /// once (and for some empty slots, as forEachNear()); returns false, visiting nothing, when
    /// that would be every bucket.
    template<typename Visit>
    bool forEachInBox(double x0, double x1, double y0, double y1, Visit &&visit) const;

private:
    // A bucket is a quarter of a cache line. Its first `scannedSlots` slots are always read,
    // empty ones holding the index size(): in the usual sparse grid this replaces a loop whose
    // length changes from bucket to bucket (and defeats branch prediction) by straight-line code.
    // One slot: cells are 2 rMax wide, so on the crowd (packing 0.24) a cell holds 0.64 marbles
    // on average and 13 % hold more (measured on the 10k crowd: 1 slot 13 % faster than 2, and 0
    // slots, a plain loop, 30 % slower). Three inline bodies: the buckets of a neighbourhood's
    // row fit in one or two cache lines (pinned runs, medians, against seven inline bodies in
    // half a line: 10k crowd 3 % less time per frame, 100k 6 to 9 %; one inline body, with the
    // rest in the overflow list, 3 % and 12 to 17 % more).
    static constexpr int inlineCapacity = 3;
    static constexpr int scannedSlots = 1;
    struct alignas(16) Bucket {
        std::int32_t count = 0;
        std::int32_t items[inlineCapacity];
    };

    int bucketOf(Vec2 p) const;
    void insert(int i, int b);
    void remove(int i, int b);
    template<typename Visit>
    void forEachIn(int b, Visit &visit) const;

    // The bodies past a bucket's inline capacity, as a singly linked list of nodes. A node taken
    // out goes to a free list, so the nodes in use never outnumber the bodies: one vector of
    // them for the whole grid allocates a few times while it grows, where a vector per bucket
    // allocated each time one more bucket overflowed for the first time (82 allocations in 40
    // frames of a 40k crowd in the book model).
    struct OverflowNode {
        std::int32_t body;
        std::int32_t next; // -1: the last
    };
    int takeNode();
    void freeNode(int node);

    GridGeometry m_geometry;
    LargeVector<Bucket> m_buckets;
    LargeVector<std::int32_t> m_overflowHead; // per bucket: first node, or -1
    LargeVector<OverflowNode> m_overflow;
    int m_freeNode = -1;                      // first node of the free list, or -1
    LargeVector<int> m_bucketOf;              // bucket of each body
};

template<typename Visit>
[[gnu::always_inline]] inline void MovingGrid::forEachIn(int b, Visit &visit) const
{
    const Bucket &bucket = m_buckets[static_cast<std::size_t>(b)];
    for (int k = 0; k < scannedSlots; ++k)
        visit(bucket.items[k]);
    if (bucket.count > scannedSlots) [[unlikely]] {
        const int inlineCount = bucket.count < inlineCapacity ? bucket.count : inlineCapacity;
        for (int k = scannedSlots; k < inlineCount; ++k)
            visit(bucket.items[k]);
        if (bucket.count > inlineCapacity) {
            for (int node = m_overflowHead[static_cast<std::size_t>(b)]; node >= 0;
                 node = m_overflow[static_cast<std::size_t>(node)].next)
                visit(m_overflow[static_cast<std::size_t>(node)].body);
        }
    }
}

template<typename Visit>
int MovingGrid::forEachNear(Vec2 at, Visit &&visit) const
{
    // The 9 buckets of a neighbourhood are distinct (the lattice has >= 3 buckets a side), so
    // every body is visited once. Inside the lattice (the common case) the neighbourhood is
    // three runs of three adjacent buckets and needs no wrap-around arithmetic.
    // For t >= 1, floor(t) lies in [1, n - 1) exactly when t does, and truncation is floor.
    const double tx = at.x * m_geometry.inverseCellSize();
    const double ty = at.y * m_geometry.inverseCellSize();
    const int nx = m_geometry.bucketsX();
    if (tx >= 1.0 && ty >= 1.0 && tx < nx - 1 && ty < m_geometry.bucketsY() - 1) [[likely]] {
        const int centre = static_cast<int>(tx) + static_cast<int>(ty) * nx;
        for (int row : {centre - nx, centre, centre + nx}) {
            forEachIn(row - 1, visit);
            forEachIn(row, visit);
            forEachIn(row + 1, visit);
        }
        return centre;
    }
    int buckets[9];
    m_geometry.neighbourhood(m_geometry.coord(at.x), m_geometry.coord(at.y), buckets);
    for (int b : buckets)
        forEachIn(b, visit);
    return buckets[4]; // bucket(coord(at.x), coord(at.y)), as bucketAt() computes it
}

template<typename Visit>
bool MovingGrid::forEachInBox(double x0, double x1, double y0, double y1, Visit &&visit) const
{
    return m_geometry.forEachRunInBox(x0, x1, y0, y1, [&](int b0, int b1) {
        for (int b = b0; b < b1; ++b)
            forEachIn(b, visit);
    });
}

/// The chapter's updateMarbles(), verbatim (PHYSICS.md, model "book"): one explicit update per
/// frame, marbles processed in scene order and in place, with the book's arithmetic, flaws included.
/// Large scenes use a uniform grid for the pin and marble tests; hits are resolved in
/// scene order, so the results are bit-identical to the all-pairs loop (tested).
class BookModel final : public Stepper {
public:
    /// Marble count from which the marble grid is used (below it, all pairs are cheaper).
    static constexpr int kGridMinMarbles = 48;
    /// Pin count from which the pin grid is used.
    static constexpr int kGridMinPins = 24;

    /// Advances one frame. Consumes pending pushes (acceleration) and leaves it zero.
    void step(World &world) override;
    bool leftAllFinite() const override { return m_leftAllFinite; }

    /// Reference mode (true): the plain transcription, all pairs and no skipping of sleeping
    /// marbles or zero terms. For tests and benchmarks; the results are the same bits either way.
    void setReferenceMode(bool on) { m_forceAllPairs = on; }

private:
    void prepare(const World &world);
    std::span<const int> pinCandidates(Vec2 oldPosition, Vec2 newPosition);

    bool m_forceAllPairs = false;
    // Every position and velocity finite after the last step: each one the step wrote, and each
    // marble's it skipped, was seen finite on the way.
    bool m_leftAllFinite = false;
    bool m_useMarbleGrid = false;
    bool m_usePinGrid = false;
    MovingGrid m_marbleGrid; // every marble but the oversize ones
    UniformGrid m_pinGrid;
    // What the marble tests read of each marble, packed in one cache line's half: the position
    // the grid holds it at, the radius and the mass (kept equal to the world's, bit for bit).
    struct alignas(32) Body {
        Vec2 p;
        double r;
        double m;
    };
    LargeVector<Body> m_bodies;
    RadiusSplit m_split;     // the radii when the marble grid was built
    std::vector<int> m_oversize; // the marbles left out of the marble grid, ascending
    std::vector<int> m_allPins; // 0..pins-1
    std::vector<int> m_candidates;
    std::vector<int> m_hits;
    std::vector<std::uint64_t> m_pinMark;
    std::uint64_t m_stamp = 0;
};

/// The book's reflection off a pin at `pin` for a marble restored to `p` moving with `v`:
/// returns false (and leaves `v` alone) where the book would divide by zero. `record`, if given,
/// gets the reflection's three vectors (not its frame) only when it returns true.
bool bookReflectOffPin(Vec2 p, Vec2 pin, Vec2 &v, HitRecord *record = nullptr);

/// The book's marble-to-marble response: marble i (restored to `pi`, velocity `vi`, mass `mi`)
/// hit marble j (at `pj`, velocity `vj`, mass `mj`). Returns false, leaving both velocities
/// alone, where the book would divide by zero. `record` as for bookReflectOffPin().
bool bookShareCollision(Vec2 pi, Vec2 &vi, double mi, Vec2 pj, Vec2 &vj, double mj,
                        HitRecord *record = nullptr);

} // namespace marbles
