#include "core/impulsemodel.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace marbles {

namespace {

Vec2 unitOrZero(Vec2 u)
{
    const double len = length(u);
    if (!(len > 0.0) || !std::isfinite(len))
        return {};
    return {u.x / len, u.y / len};
}

} // namespace

void ImpulseModel::step(World &world)
{
    const int n = world.marbleCount();
    const int pinCount = static_cast<int>(world.pins.size());
    // Pushes act at the frame boundary: an instant velocity change.
    for (int i = 0; i < n; ++i) {
        world.velocity[i].x += world.acceleration[i].x;
        world.velocity[i].y += world.acceleration[i].y;
        world.acceleration[i] = {};
    }
    if (n == 0)
        return;

    double k = world.params.friction;
    assert(k >= 0.0 && k < 1.0);
    if (!(k >= 0.0))
        k = 0.0;
    if (!(k < 1.0))
        k = std::nextafter(1.0, 0.0);
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

    double rMax = 0.0;
    for (int i = 0; i < n; ++i)
        rMax = std::max(rMax, world.radius[i]);
    const GridGeometry geometry = GridGeometry::fit(2.0 * rMax, stage.width, stage.height, n + pinCount);
    m_pinGrid.build(geometry, world.pins.data(), pinCount);

    for (int s = 0; s < substeps; ++s) {
        // Semi-implicit Euler: the new velocity moves the marble.
        for (int i = 0; i < n; ++i) {
            v[i].x = v[i].x * damping + g.x * h;
            v[i].y = v[i].y * damping + g.y * h;
            p[i].x += v[i].x * h;
            p[i].y += v[i].y * h;
        }

        // Marble pairs, each once (j > i), in a fixed order: i ascending, then the 3 x 3
        // buckets row by row, then j ascending. Positions are corrected as we go.
        m_marbleGrid.build(geometry, p.data(), n);
        for (int i = 0; i < n; ++i) {
            int buckets[9];
            geometry.neighbourhood(m_marbleGrid.cellX(i), m_marbleGrid.cellY(i), buckets);
            for (int b : buckets) {
                for (int it = m_marbleGrid.begin(b); it < m_marbleGrid.end(b); ++it) {
                    const int j = m_marbleGrid.items()[it];
                    if (j <= i)
                        continue;
                    const double reach = world.radius[i] + world.radius[j];
                    const Vec2 d{p[j].x - p[i].x, p[j].y - p[i].y};
                    const double d2 = d.x * d.x + d.y * d.y;
                    if (!(d2 < reach * reach))
                        continue;
                    const double dist = std::sqrt(d2);
                    if (!(dist > 0.0))
                        continue; // coincident centres: no normal to push along
                    const Vec2 nrm{d.x / dist, d.y / dist};
                    const double wi = 1.0 / world.mass[i];
                    const double wj = 1.0 / world.mass[j];
                    const double approach = (v[i].x - v[j].x) * nrm.x + (v[i].y - v[j].y) * nrm.y;
                    if (approach > 0.0) {
                        // The exact model's impulse: J = (1 + e) approach / (1/m_i + 1/m_j).
                        const double impulse = (1.0 + e) * approach / (wi + wj);
                        const Vec2 inI = v[i];
                        const Vec2 inJ = v[j];
                        v[i].x -= impulse * wi * nrm.x;
                        v[i].y -= impulse * wi * nrm.y;
                        v[j].x += impulse * wj * nrm.x;
                        v[j].y += impulse * wj * nrm.y;
                        world.lastHit[i] = {hitFrame, unitOrZero(inI), nrm, unitOrZero(v[i])};
                        world.lastHit[j] = {hitFrame, unitOrZero(inJ), {-nrm.x, -nrm.y}, unitOrZero(v[j])};
                    }
                    // Positional correction: separate to touching, in inverse-mass proportion,
                    // which leaves the centre of mass where it was.
                    const double overlap = reach - dist;
                    const double si = overlap * wi / (wi + wj);
                    const double sj = overlap * wj / (wi + wj);
                    p[i].x -= nrm.x * si;
                    p[i].y -= nrm.y * si;
                    p[j].x += nrm.x * sj;
                    p[j].y += nrm.y * sj;
                }
            }
        }

        // Pins: immovable points; the marble is moved out to touching and reflected if approaching.
        if (pinCount > 0) {
            for (int i = 0; i < n; ++i) {
                int buckets[9];
                geometry.neighbourhood(geometry.coord(p[i].x), geometry.coord(p[i].y), buckets);
                for (int b : buckets) {
                    for (int it = m_pinGrid.begin(b); it < m_pinGrid.end(b); ++it) {
                        const int pin = m_pinGrid.items()[it];
                        const Vec2 q = world.pins[pin];
                        const double r = world.radius[i];
                        const Vec2 d{q.x - p[i].x, q.y - p[i].y};
                        const double d2 = d.x * d.x + d.y * d.y;
                        if (!(d2 < r * r))
                            continue;
                        const double dist = std::sqrt(d2);
                        if (!(dist > 0.0))
                            continue;
                        const Vec2 nrm{d.x / dist, d.y / dist};
                        const double approach = v[i].x * nrm.x + v[i].y * nrm.y;
                        if (approach > 0.0) {
                            const Vec2 in = v[i];
                            v[i].x -= (1.0 + e) * approach * nrm.x;
                            v[i].y -= (1.0 + e) * approach * nrm.y;
                            world.lastHit[i] = {hitFrame, unitOrZero(in), nrm, unitOrZero(v[i])};
                        }
                        p[i].x -= nrm.x * (r - dist);
                        p[i].y -= nrm.y * (r - dist);
                    }
                }
            }
        }

        // Walls: clamp inside, and reflect the normal component with e when moving outward.
        if (stage.walls) {
            for (int i = 0; i < n; ++i) {
                const double r = world.radius[i];
                const Vec2 in = v[i];
                Vec2 nrm{};
                if (p[i].x - r < 0.0) {
                    p[i].x = r;
                    if (v[i].x < 0.0) {
                        v[i].x = -e * v[i].x;
                        nrm = {-1.0, 0.0};
                    }
                } else if (p[i].x + r > stage.width) {
                    p[i].x = stage.width - r;
                    if (v[i].x > 0.0) {
                        v[i].x = -e * v[i].x;
                        nrm = {1.0, 0.0};
                    }
                }
                if (p[i].y - r < 0.0) {
                    p[i].y = r;
                    if (v[i].y < 0.0) {
                        v[i].y = -e * v[i].y;
                        nrm = {0.0, -1.0};
                    }
                } else if (p[i].y + r > stage.height) {
                    p[i].y = stage.height - r;
                    if (v[i].y > 0.0) {
                        v[i].y = -e * v[i].y;
                        nrm = {0.0, 1.0};
                    }
                }
                if (nrm.x != 0.0 || nrm.y != 0.0)
                    world.lastHit[i] = {hitFrame, unitOrZero(in), nrm, unitOrZero(v[i])};
            }
        }
    }

    // The zero threshold acts at the frame boundary.
    const double z = world.params.zeroThreshold;
    for (int i = 0; i < n; ++i) {
        if (std::abs(v[i].x) <= z)
            v[i].x = 0.0;
        if (std::abs(v[i].y) <= z)
            v[i].y = 0.0;
    }
}

} // namespace marbles
