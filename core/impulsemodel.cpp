#include "core/impulsemodel.h"

#include "core/pairimpulse.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

namespace marbles {

namespace {

/// A run of consecutive slots [begin, end).
struct SlotRange {
    int begin;
    int end;
};

/// Appends the slots [lo, hi) (one bucket's, or several adjacent buckets') to the runs, merged
/// into the last run when they continue it.
void appendRun(SlotRange out[], int &count, int lo, int hi)
{
    if (lo >= hi)
        return;
    if (count > 0 && out[count - 1].end == lo)
        out[count - 1].end = hi;
    else
        out[count++] = {lo, hi};
}

// The walls along one axis for a marble of radius r at x moving at v, on a stage `side` wide:
// clamped inside, and the velocity across the wall reflected with e when moving outward.
// Returns the outward normal's sign along the axis where it bounced (-1 the low wall, +1 the
// high one), else 0. A marble too wide for the stage along the axis cannot be clamped inside:
// put against one wall it is past the other, and it jumped from wall to wall by 2 r - side
// every sub-step. It is held centred between the two walls instead, stopped along that axis
// (the exact model holds it likewise).
[[gnu::always_inline]] inline int clampToWalls(double &x, double &v, double r, double side, double e)
{
    if (2.0 * r > side) {
        x = 0.5 * side;
        v = 0.0;
    } else if (x - r < 0.0) {
        x = r;
        if (v < 0.0) {
            v = -e * v;
            return -1;
        }
    } else if (x + r > side) {
        x = side - r;
        if (v > 0.0) {
            v = -e * v;
            return 1;
        }
    }
    return 0;
}

} // namespace

bool ImpulseModel::sortIntoBuckets(const World &world, int awake)
{
    const int n = world.marbleCount();
    const bool partial = m_sorted && resortChanged(world);
    if (!partial)
        sortAll(world);
    m_sorted = true;
    if (partial) {
        m_visit.swap(m_changed);
        ++m_partialSorts;
    } else {
        m_visit.clear();
    }
    m_changed.clear();

    // A bucket's pairs can do something only if it or a forward neighbour holds a marble that
    // is awake: mark, for each awake marble, its bucket and the buckets that have it ahead.
    // With most marbles awake, every bucket is visited and the marks are not kept.
    m_allActive = awake > n / 4;
    if (!m_allActive) {
        m_active.assign((static_cast<std::size_t>(m_geometry.bucketCount()) + 63) / 64, 0);
        if (partial) {
            for (int i : m_visit) {
                if (m_sleepy[i] != 1)
                    markActive(m_bucketOf[i]);
            }
        } else {
            for (int i = 0; i < n; ++i) {
                if (m_sleepy[i] != 1)
                    markActive(m_bucketOf[i]);
            }
        }
    }
    return partial;
}

void ImpulseModel::sortAll(const World &world)
{
    // Counting sort, stable: each bucket lists its marbles in ascending scene order.
    const int n = world.marbleCount();
    const int buckets = m_geometry.bucketCount();
    m_start.assign(static_cast<std::size_t>(buckets) + 2, 0);
    m_bucketOf.resize(static_cast<std::size_t>(n));
    m_bodies.resize(static_cast<std::size_t>(n) + windowPadding);
    constexpr double far = std::numeric_limits<double>::infinity();
    std::fill(m_bodies.begin() + n, m_bodies.end(), Body{far, far, 0.0, -1, 0});
    const bool oversize = m_split.oversize > 0;
    for (int i = 0; i < n; ++i) {
        int b = m_geometry.bucketAt(world.position[i].x, world.position[i].y);
        if (oversize && m_split.isOversize(world.radius[i]))
            b = buckets;
        m_bucketOf[i] = b;
        ++m_start[b + 1];
    }
    accumulateCounts(m_start);
    // Place with a running cursor per bucket (m_start shifted by one), then shift it back.
    for (int i = 0; i < n; ++i) {
        const int slot = m_start[m_bucketOf[i]]++;
        m_bodies[slot] = {world.position[i].x, world.position[i].y, world.radius[i], i,
                          m_sleepy[i] == 1 ? asleep : 0};
    }
    for (int b = buckets + 1; b > 0; --b)
        m_start[b] = m_start[b - 1];
    m_start[0] = 0;
    m_slotsKnown = false;
}

bool ImpulseModel::resortChanged(const World &world)
{
    // The slots of the marbles not listed in m_changed hold what sortAll would put there: they
    // are asleep, unmoved since their slot was last written (those that fell asleep in the
    // last pass had not moved since the sort; that pass set their flag), and wakeSleepers
    // found them unchanged since. So moving the listed marbles to their buckets, each to its
    // place in scene order, and reading them again gives sortAll's order. Each move shifts the
    // slots and bucket starts between its old and new place (one row down is about 650 on the
    // 100k crowd); past a budget of 4 n shifts the full sort, which scatters every marble, is
    // taken instead (it starts over from the world, so a half-done pass here does no harm).
    // On the 100k crowd with 1 % moving, budgets of 2 n, 4 n and 8 n gave the same times and
    // n / 2 took 65 % more: it fell back to the full sort from the eighth frame on.
    const int n = world.marbleCount();
    if (static_cast<int>(m_changed.size()) > n / partialSortShare)
        return false;
    if (!m_slotsKnown) {
        m_slotOf.resize(static_cast<std::size_t>(n));
        for (int slot = 0; slot < n; ++slot)
            m_slotOf[m_bodies[slot].id] = slot;
        m_slotsKnown = true;
    }
    long budget = 4L * n;
    for (int id : m_changed) {
        const Vec2 p = world.position[id];
        const int to = m_split.isOversize(world.radius[id]) ? oversizeBucket() : m_geometry.bucketAt(p.x, p.y);
        const int from = m_bucketOf[id];
        if (to != from) {
            budget -= moveToBucket(id, from, to);
            if (budget < 0)
                return false;
        }
        const int slot = m_slotOf[id];
        m_bodies[slot] = {p.x, p.y, world.radius[id], id, m_sleepy[id] == 1 ? asleep : 0};
    }
    return true;
}

int ImpulseModel::moveToBucket(int id, int from, int to)
{
    // The marble's new slot: in bucket `to`, before its first marble with a larger index. The
    // slots between the old and the new place shift by one towards the old, and so do the
    // starts of the buckets in between. Returns the number of slots and starts shifted.
    const int old = m_slotOf[id];
    int at = m_start[to];
    while (at < m_start[to + 1] && m_bodies[at].id < id)
        ++at;
    const Body body = m_bodies[old];
    int slot;
    if (to > from) {
        for (int k = old + 1; k < at; ++k) {
            m_bodies[k - 1] = m_bodies[k];
            m_slotOf[m_bodies[k - 1].id] = k - 1;
        }
        for (int b = from + 1; b <= to; ++b)
            --m_start[b];
        slot = at - 1;
    } else {
        for (int k = old; k > at; --k) {
            m_bodies[k] = m_bodies[k - 1];
            m_slotOf[m_bodies[k].id] = k;
        }
        for (int b = to + 1; b <= from; ++b)
            ++m_start[b];
        slot = at;
    }
    m_bodies[slot] = body;
    m_slotOf[id] = slot;
    m_bucketOf[id] = to;
    return std::abs(slot - old) + std::abs(to - from);
}

void ImpulseModel::markActive(int bucket)
{
    // The bucket itself and its backward half (left, and the three above): the buckets whose
    // forward half holds it. (The oversize marbles' pairs are all visited anyway.)
    if (m_allActive || bucket == oversizeBucket())
        return;
    const int nx = m_geometry.bucketsX();
    const int ny = m_geometry.bucketsY();
    const int bx = bucket % nx;
    const int by = bucket / nx;
    const int left = bx == 0 ? nx - 1 : bx - 1;
    const int right = bx + 1 < nx ? bx + 1 : 0;
    const int above = (by == 0 ? ny - 1 : by - 1) * nx;
    for (int b : {bucket, left + by * nx, left + above, bx + above, right + above})
        m_active[static_cast<std::size_t>(b) >> 6] |= std::uint64_t(1) << (b & 63);
}

void ImpulseModel::wake(int slot, int bucket)
{
    // A sleeper that wakes makes the buckets that have it ahead worth visiting, and joins the
    // marbles the pin and wall pass visits.
    markActive(bucket);
    m_visit.push_back(m_bodies[slot].id);
}

int ImpulseModel::nextActive(int bucket) const
{
    const int buckets = m_geometry.bucketCount();
    if (bucket >= buckets)
        return buckets;
    std::size_t w = static_cast<std::size_t>(bucket) >> 6;
    std::uint64_t bits = m_active[w] & (~std::uint64_t(0) << (bucket & 63));
    while (bits == 0) {
        if (++w >= m_active.size())
            return buckets;
        bits = m_active[w];
    }
    return std::min(buckets, static_cast<int>(w * 64) + std::countr_zero(bits));
}

void ImpulseModel::wakeSleepers(const World &world)
{
    // Sleepers stay asleep only if nothing about them changed since the last frame: the same
    // position and radius, still at rest (+0, so that skipping the Euler step changes no bit),
    // and the same pins and stage around them. Anything else wakes them (or all of them).
    const int n = world.marbleCount();
    const Vec2 g = world.params.gravity;
    const bool valid = static_cast<int>(m_sleepy.size()) == n && g.x == 0.0 && g.y == 0.0
                       && world.stage == m_sleepStage && world.pins == m_sleepPins;
    if (!valid) {
        m_sorted = false;
        m_sleepy.assign(static_cast<std::size_t>(n), 0);
        m_sleepPosition.resize(static_cast<std::size_t>(n));
        m_sleepRadius.resize(static_cast<std::size_t>(n));
        return;
    }
    if (m_sleeperCount == 0)
        return;
    for (int i = 0; i < n; ++i) {
        if (m_sleepy[i] != 1)
            continue;
        const Vec2 p = world.position[i];
        const Vec2 v = world.velocity[i];
        const bool same = p.x == m_sleepPosition[i].x && p.y == m_sleepPosition[i].y
                          && world.radius[i] == m_sleepRadius[i] && std::bit_cast<std::uint64_t>(v.x) == 0
                          && std::bit_cast<std::uint64_t>(v.y) == 0;
        if (!same) {
            m_sleepy[i] = 0;
            m_changed.push_back(i);
        }
    }
}

void ImpulseModel::resolvePair(World &world, double e, std::int64_t hitFrame, int bucket, int si, int t)
{
    // Marbles in slots si and t overlap (or touch within rounding): both are awake from now on.
    Body &bi = m_bodies[si];
    Body &bj = m_bodies[t];
    if (bi.flags == asleep)
        wake(si, bucket);
    if (bj.flags == asleep)
        wake(t, m_bucketOf[bj.id]);
    bi.flags |= touched;
    bj.flags |= touched;
    const double reach = bi.r + bj.r;
    const Vec2 d{bj.x - bi.x, bj.y - bi.y};
    const double d2 = d.x * d.x + d.y * d.y;
    const double dist = std::sqrt(d2);
    if (!(dist > 0.0))
        return; // coincident centres: no normal to push along
    // Velocities are not copied into bucket order: only overlapping pairs read them.
    Vec2 &vi = world.velocity[bi.id];
    Vec2 &vj = world.velocity[bj.id];
    const Vec2 nrm{d.x / dist, d.y / dist};
    const double wi = 1.0 / world.mass[bi.id];
    const double wj = 1.0 / world.mass[bj.id];
    const double approach = (vi.x - vj.x) * nrm.x + (vi.y - vj.y) * nrm.y;
    if (approach > 0.0) {
        // The exact model's impulse: J = (1 + e) approach / (1/m_i + 1/m_j).
        const double impulse = (1.0 + e) * approach / (wi + wj);
        applyPairImpulse(impulse, nrm, vi, wi, vj, wj, world.lastHit[bi.id], world.lastHit[bj.id], hitFrame);
    }
    // Positional correction: separate to touching, in inverse-mass proportion, which leaves
    // the centre of mass where it was.
    const double overlap = reach - dist;
    const double sI = overlap * wi / (wi + wj);
    const double sJ = overlap * wj / (wi + wj);
    bi.x -= nrm.x * sI;
    bi.y -= nrm.y * sI;
    bj.x += nrm.x * sJ;
    bj.y += nrm.y * sJ;
}

void ImpulseModel::resolveOversizePairs(World &world, double e, std::int64_t hitFrame)
{
    // Each oversize marble (the last slots) in turn: with the marbles of the buckets it reaches
    // where it is when its turn comes (its radius and the grid's largest, around its centre), in
    // slot order, then with the oversize marbles after it.
    const int n = static_cast<int>(m_bodies.size()) - windowPadding;
    const int first = m_start[static_cast<std::size_t>(oversizeBucket())];
    for (int so = first; so < n; ++so) {
        auto test = [&](int t) __attribute__((always_inline)) {
            const Body &bi = m_bodies[so];
            const Body &bj = m_bodies[t];
            const double reach = bi.r + bj.r;
            const double dx = bj.x - bi.x;
            const double dy = bj.y - bi.y;
            if (dx * dx + dy * dy < reach * reach) [[unlikely]]
                resolvePair(world, e, hitFrame, oversizeBucket(), so, t);
        };
        const Body &giant = m_bodies[so];
        const double reach = giant.r + m_split.cut;
        const auto slots = [&](int b0, int b1) {
            for (int t = m_start[b0]; t < m_start[b1]; ++t)
                test(t);
        };
        if (!m_geometry.forEachRunInBox(giant.x - reach, giant.x + reach, giant.y - reach, giant.y + reach, slots))
            slots(0, oversizeBucket()); // the box covers the lattice: every marble of the grid
        for (int t = so + 1; t < n; ++t)
            test(t);
    }
}

void ImpulseModel::resolvePairs(World &world, double e, std::int64_t hitFrame)
{
    // Marble pairs, each once, in a fixed order: buckets in row-major order; in a bucket its
    // marbles in scene order, each paired with the marbles after it in the same bucket, then
    // with the forward half of its neighbourhood: the bucket to the right, then the three
    // below (left to right). Each pair of neighbouring buckets is thus visited from one side
    // only (a lattice of at least 3 x 3 buckets has no bucket that is both ahead and behind).
    // Positions are corrected as we go, so later pairs see earlier corrections.
    const int nx = m_geometry.bucketsX();
    const int ny = m_geometry.bucketsY();
    // Visit every bucket, or only the marked ones, keeping the column and row at hand.
    const int bucketCount = m_geometry.bucketCount();
    const bool allActive = m_allActive;
    int b = allActive ? 0 : nextActive(0);
    int bx = b % nx;
    int by = b / nx;
    while (b < bucketCount) {
        const int lo = m_start[b];
        const int hi = m_start[b + 1];
        if (lo < hi) {
            const int below = (by + 1 < ny ? by + 1 : 0) * nx; // folded: the last row's next is row 0
            // Slots after the marble in its own bucket, followed directly by the right-hand
            // bucket when that is the next bucket in storage (no fold).
            SlotRange runs[4];
            int runCount = 0;
            int sameEnd = hi;
            if (bx + 1 < nx)
                sameEnd = m_start[b + 2];
            else
                appendRun(runs, runCount, m_start[by * nx], m_start[by * nx + 1]);
            if (bx >= 1 && bx + 1 < nx) {
                appendRun(runs, runCount, m_start[below + bx - 1], m_start[below + bx + 2]);
            } else {
                const int xs[3] = {bx == 0 ? nx - 1 : bx - 1, bx, bx + 1 < nx ? bx + 1 : 0};
                for (int x : xs)
                    appendRun(runs, runCount, m_start[below + x], m_start[below + x + 1]);
            }
            for (int si = lo; si < hi; ++si) {
                const Body &bi = m_bodies[si];
                auto test = [&](int t, bool inRun) __attribute__((always_inline)) {
                    const Body &bj = m_bodies[t];
                    const double reach = bi.r + bj.r;
                    const double dx = bj.x - bi.x;
                    const double dy = bj.y - bi.y;
                    const double d2 = dx * dx + dy * dy;
                    if ((d2 < reach * reach) & inRun) [[unlikely]]
                        resolvePair(world, e, hitFrame, b, si, t);
                };
                for (int t = si + 1; t < sameEnd; ++t)
                    test(t, true);
                // The three buckets below: a loop whose length changes from marble to marble
                // ends in a mispredicted branch, where testing a window of a fixed number of
                // slots costs less (slots past the run fail the test, and the padding after the
                // last marble is readable). 10k crowd: 8 % less time per frame than a plain loop
                // here (1 % at 100k); windows of 2 or 4 slots, or one on the bucket's own run
                // too, did worse.
                for (int run = 0; run < runCount; ++run) {
                    const int first = runs[run].begin;
                    const int last = runs[run].end;
                    for (int k = 0; k < windowPadding; ++k)
                        test(first + k, first + k < last);
                    for (int t = first + windowPadding; t < last; ++t) [[unlikely]]
                        test(t, true);
                }
            }
        }
        const int next = allActive ? b + 1 : nextActive(b + 1);
        if (next == b + 1) {
            if (++bx == nx) {
                bx = 0;
                ++by;
            }
        } else {
            bx = next % nx;
            by = next / nx;
        }
        b = next;
    }
}

void ImpulseModel::step(World &world)
{
    const int n = world.marbleCount();
    const int pinCount = static_cast<int>(world.pins.size());
    // Pushes act at the frame boundary: an instant velocity change.
    double rMax = 0.0;
    double rSum = 0.0;
    for (int i = 0; i < n; ++i) {
        world.velocity[i].x += world.acceleration[i].x;
        world.velocity[i].y += world.acceleration[i].y;
        world.acceleration[i] = {};
        rMax = std::max(rMax, world.radius[i]);
        rSum += world.radius[i];
    }
    m_leftAllFinite = n == 0;
    if (n == 0)
        return;

    const double k = newtonianFriction(world.params.friction);
    const int substeps = std::max(1, world.params.substeps);
    const double h = 1.0 / substeps;
    // Drag: dv/dt = -lambda v over h multiplies v by e^{-lambda h} = (1 - k)^h, so the n factors of
    // a frame multiply to the book's (1 - k) (up to rounding).
    const double damping = std::pow(1.0 - k, h);
    const Vec2 g = world.params.gravity;
    const double e = std::clamp(world.params.restitution, 0.0, 1.0);
    const Stage stage = world.stage;
    std::vector<Vec2> &p = world.position;
    std::vector<Vec2> &v = world.velocity;
    const std::int64_t hitFrame = world.frame + 1;
    const double z = world.params.zeroThreshold;

    const RadiusSplit split = splitRadii(world.radius, rMax, rSum);
    const GridGeometry geometry = GridGeometry::fit(2.0 * split.cut, stage.width, stage.height, n + pinCount);
    if (!(geometry == m_geometry) || m_bodies.size() != static_cast<std::size_t>(n) + windowPadding
        || split.cut != m_split.cut || split.oversize != m_split.oversize)
        m_sorted = false;
    m_geometry = geometry;
    m_split = split;
    if (pinCount > 0)
        m_pinGrid.build(m_geometry, world.pins.data(), pinCount);
    // Without gravity a marble at rest stays at rest unless something touches it: only then can
    // marbles sleep.
    const bool canSleep = g.x == 0.0 && g.y == 0.0;
    wakeSleepers(world);

    const std::size_t changedLimit = static_cast<std::size_t>(n / partialSortShare);
    // Whether every place and velocity settled is finite (World::step() skips its own check then).
    bool finite = true;
    for (int s = 0; s < substeps; ++s) {
        // Semi-implicit Euler: the new velocity moves the marble. A sleeper's step would be
        // v = 0 * damping + 0 = +0 and p += 0: nothing, so it is skipped. A marble that starts
        // the sub-step at rest is noted (m_sleepy 2): it may fall asleep at the end.
        // While the kept order is valid, the marbles awake are those listed in m_changed (when
        // the list is complete), in any order: each marble's step is its own.
        int awake = 0;
        int resting = 0;
        auto advance = [&](int i) __attribute__((always_inline)) {
            ++awake;
            const bool rest = canSleep && std::bit_cast<std::uint64_t>(v[i].x) == 0
                              && std::bit_cast<std::uint64_t>(v[i].y) == 0;
            resting += rest;
            m_sleepy[i] = rest ? 2 : 0;
            v[i].x = v[i].x * damping + g.x * h;
            v[i].y = v[i].y * damping + g.y * h;
            p[i].x += v[i].x * h;
            p[i].y += v[i].y * h;
        };
        if (m_sorted && m_changed.size() <= changedLimit) {
            for (int i : m_changed)
                advance(i);
        } else {
            for (int i = 0; i < n; ++i) {
                if (m_sleepy[i] != 1)
                    advance(i);
            }
        }

        const bool partial = sortIntoBuckets(world, awake);
        const std::size_t visitBeforePairs = m_visit.size();
        resolvePairs(world, e, hitFrame);
        if (m_split.oversize > 0)
            resolveOversizePairs(world, e, hitFrame);
        const int woken = static_cast<int>(m_visit.size() - visitBeforePairs);

        // Pins and walls act on each marble alone, so the order they run in changes nothing. A
        // sleeper that nothing touched is known to clear every pin and wall: it stays as it is.
        // With no sleeper and no marble at rest, no marble can be asleep after this sub-step.
        // The marbles left awake here are listed for the next sub-step, up to the number its
        // partial sort takes (beyond it, everything is sorted again anyway).
        const bool trackSleep = resting > 0 || awake < n;
        auto settle = [&](Body &b) __attribute__((always_inline)) {
            Vec2 &vel = v[b.id];
            const double r = b.r;
            bool clear = (b.flags & touched) == 0; // overlapped nothing in this sub-step
            // Pins: immovable points; the marble is moved out to touching and reflected if approaching.
            auto pin = [&](const Vec2 q) __attribute__((always_inline)) {
                const Vec2 d{q.x - b.x, q.y - b.y};
                const double d2 = d.x * d.x + d.y * d.y;
                if (!(d2 < r * r))
                    return;
                clear = false;
                const double dist = std::sqrt(d2);
                if (!(dist > 0.0))
                    return;
                const Vec2 nrm{d.x / dist, d.y / dist};
                const double approach = vel.x * nrm.x + vel.y * nrm.y;
                if (approach > 0.0) {
                    const Vec2 in = vel;
                    vel.x -= (1.0 + e) * approach * nrm.x;
                    vel.y -= (1.0 + e) * approach * nrm.y;
                    world.lastHit[b.id] = HitRecord::of(hitFrame, in, nrm, vel);
                }
                b.x -= nrm.x * (r - dist);
                b.y -= nrm.y * (r - dist);
            };
            if (pinCount > 0 && m_split.isOversize(r)) {
                // Left out of the grid (the pin grid's cells are too small for it): every pin.
                for (const Vec2 q : world.pins)
                    pin(q);
            } else if (pinCount > 0) {
                int buckets[9];
                m_geometry.neighbourhood(m_geometry.coord(b.x), m_geometry.coord(b.y), buckets);
                for (int bucket : buckets) {
                    for (int it = m_pinGrid.begin(bucket); it < m_pinGrid.end(bucket); ++it)
                        pin(world.pins[m_pinGrid.items()[it]]);
                }
            }

            // Walls: clamp inside, and reflect the normal component with e when moving outward.
            if (stage.walls) {
                const Vec2 in = vel;
                if (trackSleep && (b.x - r < 0.0 || b.x + r > stage.width || b.y - r < 0.0 || b.y + r > stage.height))
                    clear = false;
                const int bounceX = clampToWalls(b.x, vel.x, r, stage.width, e);
                const int bounceY = clampToWalls(b.y, vel.y, r, stage.height, e);
                // The record's normal is the last wall's (y after x, in a corner).
                const Vec2 nrm = bounceY != 0 ? Vec2{0.0, static_cast<double>(bounceY)} : Vec2{static_cast<double>(bounceX), 0.0};
                if (nrm.x != 0.0 || nrm.y != 0.0)
                    world.lastHit[b.id] = HitRecord::of(hitFrame, in, nrm, vel);
            }
            // The zero threshold acts at the frame boundary (after the last sub-step).
            if (s + 1 == substeps) {
                if (std::abs(vel.x) <= z)
                    vel.x = 0.0;
                if (std::abs(vel.y) <= z)
                    vel.y = 0.0;
            }
            p[b.id] = {b.x, b.y};
            finite &= finiteBits(Vec2{b.x, b.y}) & finiteBits(vel);
            // Asleep for the next sub-step: at rest all through this one (so the Euler step did
            // not move it) and clear of everything. A zero coordinate could be -0, which the
            // skipped "p += 0" would have turned into +0: such a marble stays awake.
            if (!trackSleep)
                return;
            // One that falls asleep has not moved since the sort (it was at rest and clear), so
            // its slot holds what the next sort would put there but for the flag, set here; one
            // that stays awake is listed for the next sort to read again.
            // (In finite numbers: a sleeper's place is then known to be finite while it sleeps.)
            const bool sleepy = m_sleepy[b.id] == 2 && clear && b.x != 0.0 && b.y != 0.0 && finiteBits(Vec2{b.x, b.y});
            m_sleepy[b.id] = sleepy ? 1 : 0;
            if (sleepy) {
                m_sleepPosition[b.id] = {b.x, b.y};
                m_sleepRadius[b.id] = r;
                ++m_sleeperCount;
                b.flags = asleep;
            } else if (m_changed.size() <= changedLimit) {
                m_changed.push_back(b.id);
            }
        };
        if (partial) {
            // The marbles awake: those sorted again (awake at the sort) and the sleepers the
            // pairs woke (asleep at the sort), so each is listed once. The sleepers at the
            // sort, less those woken, stay asleep.
            m_sleeperCount = n - awake - woken;
            for (int id : m_visit) {
                const int slot = m_slotOf[id];
                Body &b = m_bodies[slot];
                assert(b.flags != asleep && (b.flags & settled) == 0);
                b.flags |= settled;
                settle(b);
            }
        } else {
            m_sleeperCount = 0;
            for (int slot = 0; slot < n; ++slot) {
                // Velocities and positions are read and written in slot order, which drifts
                // from scene order as the marbles move: request a marble's a few slots ahead (a
                // hint, no effect on results; 100k crowd: 2 to 3 % of a frame, 8 or 16 ahead alike).
                if (slot + 8 < n) {
                    const int ahead = m_bodies[slot + 8].id;
                    __builtin_prefetch(&v[ahead], 1);
                    __builtin_prefetch(&p[ahead], 1);
                }
                Body &b = m_bodies[slot];
                if (b.flags == asleep) {
                    ++m_sleeperCount;
                    continue;
                }
                settle(b);
            }
        }
        // Without sleepers every marble is sorted again next time.
        if (!trackSleep)
            m_sorted = false;
    }

    m_leftAllFinite = finite;
    if (!(m_sleepStage == stage))
        m_sleepStage = stage;
    if (m_sleepPins != world.pins)
        m_sleepPins = world.pins;
}

} // namespace marbles
