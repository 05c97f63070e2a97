#include "core/bookmodel.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>

namespace marbles {

namespace {

bool isPositiveZero(double x)
{
    return std::bit_cast<std::uint64_t>(x) == 0;
}

bool isNegativeZero(double x)
{
    return x == 0.0 && std::signbit(x);
}

// True when sqrt(d2) >= reach is certain: d2 > 1.0000001 reach^2 means d > reach (1 + 4e-8),
// far beyond rounding. Only used while reach^2 is a normal number (no underflow).
bool isClearMiss(double d2, double reach)
{
    const double reach2 = reach * reach;
    return reach2 > 1e-290 && d2 > 1.0000001 * reach2;
}

// Hit test exactly as the book: sqrt(dx^2 + dy^2) < r_i + r_j. The squared distance first rules
// out clear misses (d^2 > 1.0000001 R^2 implies d > R even after rounding), which skips the square
// root without changing any result.
bool touches(Vec2 p, double r, Vec2 q, double rq)
{
    const double reach = r + rq;
    const double dx = p.x - q.x;
    const double dy = p.y - q.y;
    const double d2 = dx * dx + dy * dy;
    if (isClearMiss(d2, reach))
        return false;
    return std::sqrt(d2) < reach;
}

// Insertion sort: candidate lists hold a handful of indices, where it beats std::sort.
template<typename It>
void sortSmall(It first, It last)
{
    for (It i = first; i != last; ++i) {
        const auto value = *i;
        It j = i;
        for (; j != first && *(j - 1) > value; --j)
            *j = *(j - 1);
        *j = value;
    }
}

// The book's helpers, with its arithmetic. Each returns false where the book would divide by
// zero, so that the caller can keep the state as it was (PHYSICS.md's one deviation).

// normalize(u): d = |u|; u.x /= d; u.y /= d.
bool normalize(Vec2 &u)
{
    const double d = length(u);
    if (d == 0.0)
        return false;
    u.x /= d;
    u.y /= d;
    return true;
}

// scaleVectorToMag(u, s, t): f = t / s; u.x *= f; u.y *= f.
bool scaleToMagnitude(Vec2 &u, double currentMag, double targetMag)
{
    if (currentMag == 0.0)
        return false;
    const double f = targetMag / currentMag;
    u.x *= f;
    u.y *= f;
    return true;
}

} // namespace

namespace {

// Reflection of a velocity against a collision vector (the chapter's "hocus pocus"), the step
// both responses share: with unit v and unit c (from the marble towards what it hit), the part
// of v along c is (v.c) c; subtracting it twice turns it round and keeps the part across c:
// v' = v - 2 (v.c) c.  |v'| = |v| = 1 in exact arithmetic; the book still measures it (cur)
// before rescaling v'.
struct Reflection {
    Vec2 unitIn;  // v / |v|
    Vec2 c;       // unit collision vector
    double d;     // v.c, with unit v
    Vec2 w;       // v - 2 d c
    double cur;   // |w| as measured
};

bool reflectUnit(Vec2 from, Vec2 towards, Vec2 v, Reflection &r)
{
    r.c = {towards.x - from.x, towards.y - from.y};
    r.w = v;
    if (!normalize(r.w) || !normalize(r.c))
        return false;
    r.unitIn = r.w;
    r.d = dot(r.w, r.c);
    r.w.x -= 2 * r.d * r.c.x;
    r.w.y -= 2 * r.d * r.c.y;
    r.cur = length(r.w);
    return r.cur != 0.0;
}

// Figure 11.12's three vectors for the collision vectors overlay.
void recordReflection(const Reflection &r, HitRecord *record)
{
    if (!record)
        return;
    record->velocityIn = r.unitIn;
    record->normal = r.c;
    record->velocityOut = {r.w.x / r.cur, r.w.y / r.cur};
}

} // namespace

// Off a pin: the reflected velocity rescaled to the old speed.
bool bookReflectOffPin(Vec2 p, Vec2 pin, Vec2 &v, HitRecord *record)
{
    const double oldMag = length(v);
    Reflection r;
    if (!reflectUnit(p, pin, v, r))
        return false;
    recordReflection(r, record);
    scaleToMagnitude(r.w, r.cur, oldMag);
    v = r.w;
    return true;
}

// The book's circle-to-circle response. Marble i reflects as off a pin, with c pointing from
// i to j; marble j is given the opposite change, +2 (v.c) c (v here is i's *unit* velocity, as
// in the book). Then the old speed of i is "shared by mass": each marble gets half of it,
// scaled by the ratio of the other's mass to its own:
//   |v_i'| = (m_j / m_i) * |v_i| / 2,   |v_j'| = (m_i / m_j) * |v_i| / 2.
// This is the book's model, not Newton's: momentum is not conserved and j's own speed is
// forgotten. The exact model shows the correct answer beside it.
bool bookShareCollision(Vec2 pi, Vec2 &vi, double mi, Vec2 pj, Vec2 &vj, double mj, HitRecord *record)
{
    const double oldMag = length(vi);
    Reflection r;
    if (!reflectUnit(pi, pj, vi, r))
        return false;
    const double newI = (mj / mi) * (oldMag / 2);
    const double newJ = (mi / mj) * (oldMag / 2);
    Vec2 wi = r.w;
    scaleToMagnitude(wi, r.cur, newI);
    Vec2 wj = vj;
    wj.x += 2 * r.d * r.c.x;
    wj.y += 2 * r.d * r.c.y;
    const double curJ = length(wj);
    if (!scaleToMagnitude(wj, curJ, newJ))
        return false;
    vi = wi;
    vj = wj;
    recordReflection(r, record);
    return true;
}

void BookModel::step(World &world)
{
    const int n = world.marbleCount();
    const int pinCount = static_cast<int>(world.pins.size());
    const double k = world.params.friction;
    const double zero = world.params.zeroThreshold;
    const Vec2 g = world.params.gravity;
    const bool walls = world.stage.walls;
    const double width = world.stage.width;
    const double height = world.stage.height;
    const bool shortCircuit = world.params.shortCircuit;
    const std::int64_t producedFrame = world.frame + 1;

    std::vector<Vec2> &pos = world.position;
    std::vector<Vec2> &vel = world.velocity;
    std::vector<Vec2> &acc = world.acceleration;

    // Skipping what the scene does not need. Each skip leaves the results bit-identical:
    // - k = 0: the friction term adds (-v) * 0 = +-0 to a; g = 0 likewise. Adding a zero can
    //   only flip the sign of a zero, and step 3 turns any zero velocity component into +0
    //   (-Z <= +-0 <= Z), so the velocity and position come out the same bits.
    // - A sleeping marble (v and a exactly +0, no gravity) is a no-op in its own update: the
    //   friction term is -0 * k, v stays +0, p + 0 = p, no wall test fires (v is neither < 0
    //   nor > 0), and every pin or marble hit has |v| = 0, where the reflection keeps all
    //   velocities. So it is skipped; other marbles still find it and can wake it up.
    const bool reference = m_forceAllPairs;
    const bool friction = reference || k != 0.0;
    const bool gravity = reference || g.x != 0.0 || g.y != 0.0;

    prepare(world);

    // Whether every number seen is finite. Seen are the places of the marbles skipped (their
    // velocities are +0), every marble's place and velocity at the end of its turn, and every
    // velocity a hit changed after it: if all are finite, so is the frame's end (World::step()
    // skips its own check then).
    bool finite = true;
    for (int i = 0; i < n; ++i) {
        Vec2 &p = pos[i];
        Vec2 &v = vel[i];
        Vec2 &a = acc[i];

        if (!gravity && !reference && isPositiveZero(v.x) && isPositiveZero(v.y) && isPositiveZero(a.x)
            && isPositiveZero(a.y) && !isNegativeZero(p.x) && !isNegativeZero(p.y)) {
            finite &= finiteBits(p);
            continue;
        }

        const double r = world.radius[i];

        // 1. Air friction is a force opposite to the velocity, a fraction k of it:
        //    a += -v * k. Then gravity, a constant acceleration: a += g.
        if (friction) {
            a.x += (-v.x) * k;
            a.y += (-v.y) * k;
        }
        if (gravity) {
            a.x += g.x;
            a.y += g.y;
        }

        // 2. Explicit Euler for the velocity, one frame at a time: v(f+1) = v(f) + a.
        //    With friction alone this is v(f+1) = (1 - k) v(f): a geometric decay by (1 - k)
        //    per frame. For k > 1 the factor is negative (the velocity flips sign every frame);
        //    for k > 2 its size exceeds 1 and speeds grow without bound.
        v.x += a.x;
        v.y += a.y;

        // 3. The book's ZERO: a geometric decay never reaches 0, so small components are
        //    declared to be exactly 0 (the marbles stop "sliding like on ice").
        //    The book tests -ZERO <= v.x <= ZERO, written here as |v.x| <= ZERO: the same
        //    answer for every pair of doubles (+-0, infinities and NaN included, and a negative
        //    ZERO, which holds for none), in one comparison. Compiled as the book writes it, the
        //    first half alone became a branch that held for every other moving marble and could
        //    not be predicted.
        if (std::abs(v.x) <= zero)
            v.x = 0;
        if (std::abs(v.y) <= zero)
            v.y = 0;

        // 4. Move: p(f+1) = p(f) + v(f+1), keeping the old position to fall back to.
        const Vec2 old = p;
        p.x += v.x;
        p.y += v.y;

        bool hit = false;
        // The grid's bucket of p where it looked for marbles (-1: did not look).
        int newBucket = -1;

        // 5. Walls: a marble past an edge and still moving outwards goes back to where it was
        //    and its velocity component across that edge is reversed (a mirror bounce).
        if (walls) {
            if ((p.x - r < 0 && v.x < 0) || (p.x + r > width && v.x > 0)) {
                p = old;
                v.x = -v.x;
                hit = true;
            }
            if (!(hit && shortCircuit)
                && ((p.y - r < 0 && v.y < 0) || (p.y + r > height && v.y > 0))) {
                p = old;
                v.y = -v.y;
                hit = true;
            }
        }

        // 6. Pins: a pin inside the marble (distance <= r) is a hit. The marble goes back to
        //    its last position (the book's stand-in for the true contact point) and its
        //    velocity is reflected about the line from its centre to the pin.
        if (pinCount > 0 && !(hit && shortCircuit)) {
            const std::span<const int> pins = pinCandidates(old, p);
            for (int j : pins) {
                const Vec2 q = world.pins[j];
                // dist(q, p) <= r as the book computes it, after the same sure-miss test.
                const double dx = q.x - p.x;
                const double dy = q.y - p.y;
                const double d2 = dx * dx + dy * dy;
                if (isClearMiss(d2, r))
                    continue;
                if (std::sqrt(d2) <= r) {
                    p = old;
                    hit = true;
                    HitRecord &record = world.lastHit[i]; // written only by a reflection
                    if (bookReflectOffPin(p, q, v, &record))
                        record.frame = producedFrame;
                    if (shortCircuit)
                        break;
                }
            }
        }

        // 7. Other marbles, in scene order: closer than the sum of the radii is a hit.
        //    Marbles before i have already moved this frame, marbles after i have not.
        if (!(hit && shortCircuit)) {
            auto collide = [&](int j, Vec2 pj, double mj) {
                p = old;
                hit = true;
                // The record is written in place, and only when the collision reflects: a copy from
                // the stack loaded in 16 bytes what had just been stored in 8, which the processor
                // could not forward (perf, 100k crowd: 11 % of step()'s samples on that load).
                HitRecord &record = world.lastHit[i];
                if (bookShareCollision(p, v, world.mass[i], pj, vel[j], mj, &record))
                    record.frame = producedFrame;
                finite &= finiteBits(vel[j]);
            };
            if (!m_useMarbleGrid) {
                for (int j = 0; j < n; ++j) {
                    if (j != i && touches(p, r, pos[j], world.radius[j])) {
                        collide(j, pos[j], world.mass[j]);
                        if (shortCircuit)
                            break;
                    }
                }
            } else {
                // Which marbles the all-pairs loop hits, without walking all pairs. A hit test
                // depends on positions only, and a hit changes velocities only, so:
                // - until its first hit, marble i is tested at p: the first hit is the smallest
                //   j touching p;
                // - from then on it is tested at old (p = old at every hit): the later hits are
                //   every j > first touching old, in ascending order.
                // (When a wall or pin has already put it back, p = old throughout.) The grid lists
                // every marble that can touch a point, so these are exactly the all-pairs hits.
                // Oversize marbles (RadiusSplit) are not in the grid: every marble is tested
                // against them, and they against the marbles of the cells within their radius
                // and the grid's largest (every marble, where that is the whole lattice).
                const bool oversize = m_split.isOversize(r);
                // Returns the bucket of `at` (-1 for an oversize marble, which is in none).
                auto touchersOf = [&](Vec2 at, int after) -> int {
                    m_hits.clear();
                    auto test = [&](int j) __attribute__((always_inline)) {
                        // One well-predicted branch per candidate: the clear-miss test of
                        // touches() evaluated without short-circuits. Only near neighbours get
                        // past it (and, where `at` is at infinity too, the records there: the
                        // empty slots' and marble i's own, see below).
                        const Body &b = m_bodies[static_cast<std::size_t>(j)];
                        const double reach = r + b.r;
                        const double dx = at.x - b.p.x;
                        const double dy = at.y - b.p.y;
                        const double d2 = dx * dx + dy * dy;
                        const double reach2 = reach * reach;
                        if (!(d2 > 1.0000001 * reach2) | !(reach2 > 1e-290)) [[unlikely]] {
                            if (j > after && j != i && j < n && touches(at, r, b.p, b.r))
                                m_hits.push_back(j);
                        }
                    };
                    int bucket = -1;
                    if (!oversize) [[likely]] {
                        bucket = m_marbleGrid.forEachNear(at, test);
                    } else if (const double reach = r + m_split.cut;
                               !m_marbleGrid.forEachInBox(at.x - reach, at.x + reach, at.y - reach, at.y + reach,
                                                          test)) {
                        for (int j = after + 1; j < n; ++j)
                            test(j); // in ascending order: no sort
                        return bucket;
                    }
                    for (const int j : m_oversize)
                        test(j);
                    sortSmall(m_hits.begin(), m_hits.end());
                    return bucket;
                };
                // Marble i's own record is put at infinity while it looks for others (the end of
                // its turn, step 8, writes its place there again): the grid lists i itself near
                // its old place, and every time it passed the test below to be turned down later,
                // a branch mispredicted.
                m_bodies[static_cast<std::size_t>(i)].p = m_bodies.back().p;
                newBucket = touchersOf(p, -1);
                if (!m_hits.empty() && !(p == old)) {
                    const int first = m_hits.front();
                    collide(first, m_bodies[static_cast<std::size_t>(first)].p, m_bodies[static_cast<std::size_t>(first)].m);
                    if (shortCircuit)
                        m_hits.clear();
                    else
                        touchersOf(old, first);
                }
                for (int j : m_hits) {
                    collide(j, m_bodies[static_cast<std::size_t>(j)].p, m_bodies[static_cast<std::size_t>(j)].m);
                    if (shortCircuit)
                        break;
                }
            }
        }

        // 8. A force acts for one frame only: the acceleration starts again from zero.
        a.x = 0;
        a.y = 0;
        finite &= finiteBits(p) & finiteBits(v);

        // The grid's record of i (at infinity if i looked for marbles in it) follows i. After a
        // hit p is old again, in the bucket i was in (prepare() checked that the records are the
        // marbles' places, and i's own turn alone moves i); otherwise p is where i looked from,
        // whose bucket that look found.
        if (m_useMarbleGrid && !sameBits(p, m_bodies[static_cast<std::size_t>(i)].p)) {
            m_bodies[static_cast<std::size_t>(i)].p = p;
            if (!m_split.isOversize(r) && !sameBits(p, old)) {
                assert(newBucket >= 0);
                m_marbleGrid.moveTo(i, newBucket);
            }
        }
    }
    m_leftAllFinite = finite;
}

// The broad phase. A hit needs distance < r_i + r_j <= 2 rMax (marbles) or <= r_i <= rMax
// (pins), so with cells of side >= 2 rMax every partner of a point lies in the 3 x 3 cells
// around it. The marble grid's rMax leaves out a few far larger marbles (RadiusSplit), which
// are tested apart (see step 7); the pin grid's is the largest radius. Marble i is tested at its
// new position and, after a first hit, at its old one; pins are tested in sorted order and
// marble hits are collided in scene order (see step 7), so the results are bit-identical to the
// all-pairs loop.
void BookModel::prepare(const World &world)
{
    const int n = world.marbleCount();
    const int pinCount = static_cast<int>(world.pins.size());
    m_useMarbleGrid = !m_forceAllPairs && n >= kGridMinMarbles;
    m_usePinGrid = !m_forceAllPairs && pinCount >= kGridMinPins;

    if (!m_usePinGrid && static_cast<int>(m_allPins.size()) != pinCount) {
        m_allPins.resize(static_cast<std::size_t>(pinCount));
        std::iota(m_allPins.begin(), m_allPins.end(), 0);
    }
    if (!m_useMarbleGrid && !m_usePinGrid)
        return;

    // The marble grid is a cache kept from the last frame. It is still valid only if no marble
    // moved or changed since (an edit, an undo or a jump back in time rebuilds it). This check
    // reads every marble once per frame: World's fields are public, so nothing cheaper can tell
    // that none was edited. It runs without early exit so that it compiles to straight-line
    // (vectorizable) code; the bits are compared, so -0 differs from +0 and a NaN equals itself.
    bool valid = false;
    if (m_useMarbleGrid && m_marbleGrid.size() == n && m_bodies.size() == static_cast<std::size_t>(n) + 1) {
        std::uint64_t differ = 0;
        for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
            const Body &b = m_bodies[i];
            differ |= (std::bit_cast<std::uint64_t>(b.p.x) ^ std::bit_cast<std::uint64_t>(world.position[i].x))
                | (std::bit_cast<std::uint64_t>(b.p.y) ^ std::bit_cast<std::uint64_t>(world.position[i].y))
                | (std::bit_cast<std::uint64_t>(b.r) ^ std::bit_cast<std::uint64_t>(world.radius[i]))
                | (std::bit_cast<std::uint64_t>(b.m) ^ std::bit_cast<std::uint64_t>(world.mass[i]));
        }
        valid = differ == 0;
    }
    // Same radii as at the last build: the same split.
    const RadiusSplit split = valid ? m_split : splitRadii(world.radius);

    if (m_usePinGrid) {
        // Pins change only between frames (by editing); sorting them costs O(pins).
        m_pinGrid.build(GridGeometry::fit(std::max(2.0 * split.largest, 1e-6), world.stage.width,
                                          world.stage.height, pinCount),
                        world.pins.data(), pinCount);
        m_pinMark.assign(static_cast<std::size_t>(pinCount), 0);
    }
    if (m_useMarbleGrid && !valid) {
        m_marbleGrid.build(GridGeometry::fit(std::max(2.0 * split.cut, 1e-6), world.stage.width, world.stage.height, n),
                           world.position.data(), n);
        m_oversize.clear();
        for (int i = 0; split.oversize > 0 && i < n; ++i) {
            if (split.isOversize(world.radius[i])) {
                m_oversize.push_back(i);
                m_marbleGrid.leaveOut(i);
            }
        }
        // One record past the end stands for the grid's empty slots: at infinity with no
        // radius, every distance to it is infinite (or NaN), never a hit.
        m_bodies.resize(static_cast<std::size_t>(n) + 1);
        for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i)
            m_bodies[i] = {world.position[i], world.radius[i], world.mass[i]};
        constexpr double far = std::numeric_limits<double>::infinity();
        m_bodies.back() = {Vec2{far, far}, 0.0, 0.0};
        m_split = split;
    }
}

std::span<const int> BookModel::pinCandidates(Vec2 oldPosition, Vec2 newPosition)
{
    if (!m_usePinGrid)
        return m_allPins;
    m_candidates.clear();
    ++m_stamp;
    const GridGeometry &geometry = m_pinGrid.geometry();
    for (Vec2 at : {newPosition, oldPosition}) {
        int buckets[9];
        geometry.neighbourhood(geometry.coord(at.x), geometry.coord(at.y), buckets);
        for (int b : buckets) {
            for (int k = m_pinGrid.begin(b); k < m_pinGrid.end(b); ++k) {
                const int j = m_pinGrid.items()[static_cast<std::size_t>(k)];
                if (m_pinMark[static_cast<std::size_t>(j)] != m_stamp) {
                    m_pinMark[static_cast<std::size_t>(j)] = m_stamp;
                    m_candidates.push_back(j);
                }
            }
        }
        if (oldPosition == newPosition)
            break;
    }
    sortSmall(m_candidates.begin(), m_candidates.end());
    return m_candidates;
}

void MovingGrid::build(const GridGeometry &geometry, const Vec2 *points, int count)
{
    m_geometry = geometry;
    const auto buckets = static_cast<std::size_t>(geometry.bucketCount());
    Bucket empty;
    std::fill(std::begin(empty.items), std::end(empty.items), count);
    m_buckets.assign(buckets, empty);
    m_overflowHead.assign(buckets, -1);
    m_overflow.clear();
    m_freeNode = -1;
    m_bucketOf.resize(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        const int b = bucketOf(points[i]);
        m_bucketOf[static_cast<std::size_t>(i)] = b;
        insert(i, b);
    }
}

int MovingGrid::bucketOf(Vec2 p) const
{
    return m_geometry.bucketAt(p.x, p.y);
}

void MovingGrid::insert(int i, int b)
{
    Bucket &bucket = m_buckets[static_cast<std::size_t>(b)];
    if (bucket.count < inlineCapacity) {
        bucket.items[bucket.count] = i;
    } else {
        const int node = takeNode();
        std::int32_t &head = m_overflowHead[static_cast<std::size_t>(b)];
        m_overflow[static_cast<std::size_t>(node)] = {i, head};
        head = node;
    }
    ++bucket.count;
}

void MovingGrid::remove(int i, int b)
{
    Bucket &bucket = m_buckets[static_cast<std::size_t>(b)];
    const int inlineCount = std::min(bucket.count, inlineCapacity);
    if (bucket.count <= inlineCapacity) {
        // The common case: no overflow list to touch. The last body fills the hole i leaves.
        const int last = bucket.items[inlineCount - 1];
        for (int k = 0; k < inlineCount; ++k) {
            if (bucket.items[k] == i) {
                bucket.items[k] = last;
                break;
            }
        }
    } else {
        // The first body of the overflow list (the cheapest to take off it) fills the hole.
        std::int32_t &head = m_overflowHead[static_cast<std::size_t>(b)];
        const int first = head;
        const int filler = m_overflow[static_cast<std::size_t>(first)].body;
        bool found = false;
        for (int k = 0; k < inlineCount && !found; ++k) {
            if (bucket.items[k] == i) {
                bucket.items[k] = filler;
                found = true;
            }
        }
        for (int node = first; node >= 0 && !found; node = m_overflow[static_cast<std::size_t>(node)].next) {
            if (m_overflow[static_cast<std::size_t>(node)].body == i) {
                m_overflow[static_cast<std::size_t>(node)].body = filler;
                found = true;
            }
        }
        head = m_overflow[static_cast<std::size_t>(first)].next;
        freeNode(first);
    }
    --bucket.count;
    if (bucket.count < inlineCapacity)
        bucket.items[bucket.count] = size(); // the slot is empty again
}

int MovingGrid::takeNode()
{
    if (m_freeNode < 0) {
        m_overflow.push_back({});
        return static_cast<int>(m_overflow.size()) - 1;
    }
    const int node = m_freeNode;
    m_freeNode = m_overflow[static_cast<std::size_t>(node)].next;
    return node;
}

void MovingGrid::freeNode(int node)
{
    m_overflow[static_cast<std::size_t>(node)].next = m_freeNode;
    m_freeNode = node;
}

void MovingGrid::leaveOut(int i)
{
    remove(i, m_bucketOf[static_cast<std::size_t>(i)]);
    m_bucketOf[static_cast<std::size_t>(i)] = -1;
}

void MovingGrid::moveTo(int i, int b)
{
    int &current = m_bucketOf[static_cast<std::size_t>(i)];
    if (b == current)
        return;
    remove(i, current);
    insert(i, b);
    current = b;
}

} // namespace marbles
