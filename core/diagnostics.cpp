#include "core/diagnostics.h"

#include "core/broadphase.h"

#include <algorithm>

namespace marbles {

double maxOverlap(const World &world)
{
    const int n = world.marbleCount();
    double worst = 0.0;
    const double rMax = largestOf(world.radius);

    if (world.stage.walls) {
        for (int i = 0; i < n; ++i) {
            const Vec2 p = world.position[i];
            const double r = world.radius[i];
            worst = std::max({worst, r - p.x, p.x + r - world.stage.width, r - p.y, p.y + r - world.stage.height});
        }
    }
    if (n == 0)
        return worst;

    // Any overlapping pair is closer than 2 rMax: with cells that large, partners are in the
    // 3 x 3 neighbourhood. Each pair is visited from its lower index only.
    UniformGrid grid;
    grid.build(GridGeometry::fit(2.0 * rMax, world.stage.width, world.stage.height, n), world.position.data(), n);
    const GridGeometry &geometry = grid.geometry();
    for (int i = 0; i < n; ++i) {
        int buckets[9];
        geometry.neighbourhood(grid.cellX(i), grid.cellY(i), buckets);
        for (int b : buckets) {
            for (int k = grid.begin(b); k < grid.end(b); ++k) {
                const int j = grid.items()[static_cast<std::size_t>(k)];
                if (j <= i)
                    continue;
                const double depth = world.radius[i] + world.radius[j] - distance(world.position[i], world.position[j]);
                worst = std::max(worst, depth);
            }
        }
    }
    if (!world.pins.empty()) {
        for (const Vec2 &q : world.pins) {
            int buckets[9];
            geometry.neighbourhood(geometry.coord(q.x), geometry.coord(q.y), buckets);
            for (int b : buckets) {
                for (int k = grid.begin(b); k < grid.end(b); ++k) {
                    const int i = grid.items()[static_cast<std::size_t>(k)];
                    worst = std::max(worst, world.radius[i] - distance(world.position[i], q));
                }
            }
        }
    }
    return worst;
}

int escapedMarbles(const World &world)
{
    if (!world.stage.walls)
        return 0;
    int count = 0;
    for (const Vec2 &p : world.position) {
        if (!(p.x >= 0 && p.x <= world.stage.width && p.y >= 0 && p.y <= world.stage.height))
            ++count;
    }
    return count;
}

double momentumScale(const World &world)
{
    double s = 0.0;
    for (int i = 0; i < world.marbleCount(); ++i)
        s += world.mass[i] * length(world.velocity[i]);
    return s;
}

} // namespace marbles
