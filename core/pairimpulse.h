#pragma once

#include "core/world.h"

#include <cassert>
#include <cmath>
#include <cstdint>

namespace marbles {

/// The friction k both Newtonian models (exact and impulse) work with: in [0, 1), as the
/// loader and setParam() accept for them. A World edited directly past that range (caught by
/// the assert in debug builds) is held inside it: below 0 (or NaN) as 0, from 1 up as the
/// largest double below 1, so that the drag's log(1 - k) stays finite.
inline double newtonianFriction(double k)
{
    assert(k >= 0.0 && k < 1.0);
    if (!(k >= 0.0))
        return 0.0;
    if (!(k < 1.0))
        return std::nextafter(1.0, 0.0);
    return k;
}

/// The velocity change both Newtonian models (exact and impulse) give a colliding pair: an
/// impulse J along the unit normal n (from marble i towards marble j), v_i -= J w_i n and
/// v_j += J w_j n, where w is the inverse mass, so that momentum is kept. Records both hits,
/// produced in `frame`, for the collision vectors overlay.
inline void applyPairImpulse(double impulse, Vec2 n, Vec2 &vi, double wi, Vec2 &vj, double wj,
                             HitRecord &hitI, HitRecord &hitJ, std::int64_t frame)
{
    const Vec2 inI = vi;
    const Vec2 inJ = vj;
    vi.x -= impulse * wi * n.x;
    vi.y -= impulse * wi * n.y;
    vj.x += impulse * wj * n.x;
    vj.y += impulse * wj * n.y;
    hitI = HitRecord::of(frame, inI, n, vi);
    hitJ = HitRecord::of(frame, inJ, {-n.x, -n.y}, vj);
}

} // namespace marbles
