#include "core/bookmodel.h"

namespace marbles {

namespace {

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

// Reflection of a velocity against a collision vector (the chapter's "hocus pocus"):
// with unit v and unit c, the part of v along c is (v.c) c; subtracting it twice turns it
// round and keeps the part across c:  v' = v - 2 (v.c) c.  |v'| = |v| = 1 in exact
// arithmetic; the book still measures it (cur) and rescales v' to the old speed.
bool bookReflectOffPin(Vec2 p, Vec2 pin, Vec2 &v, HitRecord *record)
{
    const double oldMag = length(v);
    Vec2 c{pin.x - p.x, pin.y - p.y};
    Vec2 w = v;
    if (!normalize(w) || !normalize(c))
        return false;
    const Vec2 unitIn = w;
    const double d = dot(w, c);
    w.x -= 2 * d * c.x;
    w.y -= 2 * d * c.y;
    const double cur = length(w);
    if (cur == 0.0)
        return false;
    const Vec2 unitOut{w.x / cur, w.y / cur};
    scaleToMagnitude(w, cur, oldMag);
    v = w;
    if (record) {
        record->velocityIn = unitIn;
        record->normal = c;
        record->velocityOut = unitOut;
    }
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
    Vec2 c{pj.x - pi.x, pj.y - pi.y};
    Vec2 wi = vi;
    if (!normalize(wi) || !normalize(c))
        return false;
    const Vec2 unitIn = wi;
    const double d = dot(wi, c);
    wi.x -= 2 * d * c.x;
    wi.y -= 2 * d * c.y;
    const double curI = length(wi);
    if (curI == 0.0)
        return false;
    const Vec2 unitOut{wi.x / curI, wi.y / curI};
    const double newI = (mj / mi) * (oldMag / 2);
    const double newJ = (mi / mj) * (oldMag / 2);
    scaleToMagnitude(wi, curI, newI);
    Vec2 wj = vj;
    wj.x += 2 * d * c.x;
    wj.y += 2 * d * c.y;
    const double curJ = length(wj);
    if (!scaleToMagnitude(wj, curJ, newJ))
        return false;
    vi = wi;
    vj = wj;
    if (record) {
        record->velocityIn = unitIn;
        record->normal = c;
        record->velocityOut = unitOut;
    }
    return true;
}

void BookModel::step(World &world)
{
    const int n = world.marbleCount();
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

    for (int i = 0; i < n; ++i) {
        Vec2 &p = pos[i];
        Vec2 &v = vel[i];
        Vec2 &a = acc[i];
        const double r = world.radius[i];

        // 1. Air friction is a force opposite to the velocity, a fraction k of it:
        //    a += -v * k. Then gravity, a constant acceleration: a += g.
        a.x += (-v.x) * k;
        a.y += (-v.y) * k;
        a.x += g.x;
        a.y += g.y;

        // 2. Explicit Euler for the velocity, one frame at a time: v(f+1) = v(f) + a.
        //    With friction alone this is v(f+1) = (1 - k) v(f): a geometric decay by (1 - k)
        //    per frame. For k > 1 the factor is negative (the velocity flips sign every frame);
        //    for k > 2 its size exceeds 1 and speeds grow without bound.
        v.x += a.x;
        v.y += a.y;

        // 3. The book's ZERO: a geometric decay never reaches 0, so small components are
        //    declared to be exactly 0 (the marbles stop "sliding like on ice").
        if (v.x >= -zero && v.x <= zero)
            v.x = 0;
        if (v.y >= -zero && v.y <= zero)
            v.y = 0;

        // 4. Move: p(f+1) = p(f) + v(f+1), keeping the old position to fall back to.
        const Vec2 old = p;
        p.x += v.x;
        p.y += v.y;

        bool hit = false;

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
        if (!(hit && shortCircuit)) {
            for (const Vec2 &q : world.pins) {
                if (distance(q, p) <= r) {
                    p = old;
                    hit = true;
                    HitRecord record;
                    if (bookReflectOffPin(p, q, v, &record)) {
                        record.frame = producedFrame;
                        world.lastHit[i] = record;
                    }
                    if (shortCircuit)
                        break;
                }
            }
        }

        // 7. Other marbles, in scene order: closer than the sum of the radii is a hit.
        //    Marbles before i have already moved this frame, marbles after i have not.
        if (!(hit && shortCircuit)) {
            for (int j = 0; j < n; ++j) {
                if (j == i)
                    continue;
                if (distance(p, pos[j]) < r + world.radius[j]) {
                    p = old;
                    hit = true;
                    HitRecord record;
                    if (bookShareCollision(p, v, world.mass[i], pos[j], vel[j], world.mass[j], &record)) {
                        record.frame = producedFrame;
                        world.lastHit[i] = record;
                    }
                    if (shortCircuit)
                        break;
                }
            }
        }

        // 8. A force acts for one frame only: the acceleration starts again from zero.
        a.x = 0;
        a.y = 0;
    }
}

} // namespace marbles
