#include "core/broadphase.h"

#include <algorithm>
#include <cmath>

namespace marbles {

double largestOf(std::span<const double> values, double floor)
{
    // For values that are not NaN, max is exact, associative and commutative, and a value equal
    // to the running maximum never replaces it (a -0 never replaces a +0, nor the reverse), so
    // the lanes folded in order give the sequential result bit for bit.
    double lane[4] = {floor, floor, floor, floor};
    const std::size_t n = values.size();
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        for (int k = 0; k < 4; ++k)
            lane[k] = std::max(lane[k], values[i + static_cast<std::size_t>(k)]);
    }
    for (; i < n; ++i)
        lane[0] = std::max(lane[0], values[i]);
    return std::max(std::max(lane[0], lane[1]), std::max(lane[2], lane[3]));
}

RadiusSplit splitRadii(std::span<const double> radii)
{
    const std::size_t n = radii.size();
    if (n <= static_cast<std::size_t>(RadiusSplit::maxOversize)) {
        const double largest = largestOf(radii);
        return {largest, largest, 0};
    }
    // The largest and the sum in one pass, each in four lanes: the largest as largestOf() finds
    // it (the same bits), the sum in an order of its own (its rounding decides nothing but the
    // grid's size).
    double top[4] = {0.0, 0.0, 0.0, 0.0};
    double lane[4] = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        for (int k = 0; k < 4; ++k) {
            const double r = radii[i + static_cast<std::size_t>(k)];
            top[k] = std::max(top[k], r);
            lane[k] += r;
        }
    }
    for (; i < n; ++i) {
        top[0] = std::max(top[0], radii[i]);
        lane[0] += radii[i];
    }
    const double largest = std::max(std::max(top[0], top[1]), std::max(top[2], top[3]));
    return splitRadii(radii, largest, (lane[0] + lane[1]) + (lane[2] + lane[3]));
}

RadiusSplit splitRadii(std::span<const double> radii, double largest, double sum)
{
    RadiusSplit split{largest, largest, 0};
    const std::size_t n = radii.size();
    if (n <= static_cast<std::size_t>(RadiusSplit::maxOversize))
        return split;
    const double bound = RadiusSplit::oversizeFactor * sum / static_cast<double>(n);
    if (!(split.largest > bound)) // also when the sum is not finite
        return split;
    double rest = 0.0;
    int over = 0;
    for (const double r : radii) {
        if (r > bound)
            ++over;
        else
            rest = std::max(rest, r);
    }
    if (over > RadiusSplit::maxOversize || !(rest > 0.0) || !(2.0 * rest <= split.largest))
        return split;
    split.cut = rest;
    split.oversize = over;
    return split;
}

void accumulateCounts(std::span<int> counts)
{
    if (counts.empty())
        return;
    int sum = counts[0];
    for (std::size_t b = 1; b < counts.size(); ++b) {
        sum += counts[b];
        counts[b] = sum;
    }
}

GridGeometry GridGeometry::fit(double contactPx, double widthPx, double heightPx, int itemCount)
{
    GridGeometry g;
    // A hair larger than the contact distance, so that rounding in a position can never put two
    // touching bodies two cells apart.
    double c = contactPx * (1.0 + 1e-9);
    if (!(c > 0.0) || !std::isfinite(c))
        c = 1.0;
    g.m_cellSize = c;
    g.m_invCellSize = 1.0 / c;

    auto cells = [c](double side) {
        const double n = std::isfinite(side) && side > 0.0 ? std::ceil(side / c) : 3.0;
        return std::clamp(n, 3.0, 32768.0);
    };
    double nx = cells(widthPx);
    double ny = cells(heightPx);
    // More buckets than ~2 per body only costs memory and clearing time: fold the lattice more.
    const double limit = std::max(9.0, 2.0 * std::max(itemCount, 0) + 16.0);
    if (nx * ny > limit) {
        const double f = std::sqrt(limit / (nx * ny));
        nx = std::max(3.0, std::floor(nx * f));
        ny = std::max(3.0, std::floor(ny * f));
    }
    g.m_nx = static_cast<int>(nx);
    g.m_ny = static_cast<int>(ny);
    return g;
}

std::int64_t GridGeometry::coord(double x) const
{
    const double k = std::floor(x * m_invCellSize);
    constexpr double limit = static_cast<double>(coordLimit);
    if (!(k > -limit)) // also catches NaN
        return std::isnan(k) ? 0 : -coordLimit;
    if (k >= limit)
        return coordLimit;
    return static_cast<std::int64_t>(k);
}

int GridGeometry::bucket(std::int64_t kx, std::int64_t ky) const
{
    // Most cells lie on the stage, where no folding is needed: skip the (slow) 64-bit division.
    std::int64_t bx = kx;
    std::int64_t by = ky;
    if (bx < 0 || bx >= m_nx) {
        bx %= m_nx;
        if (bx < 0)
            bx += m_nx;
    }
    if (by < 0 || by >= m_ny) {
        by %= m_ny;
        if (by < 0)
            by += m_ny;
    }
    return static_cast<int>(bx + by * m_nx);
}

void GridGeometry::neighbourhood(std::int64_t kx, std::int64_t ky, int out[9]) const
{
    bucketNeighbourhood(bucket(kx, ky), out);
}

void GridGeometry::bucketNeighbourhood(int b, int out[9]) const
{
    // Folding: compute the wrapped column and row once, then step with wrap-around.
    const int bx = b % m_nx;
    const int by = b / m_nx;
    const int xs[3] = {bx == 0 ? m_nx - 1 : bx - 1, bx, bx == m_nx - 1 ? 0 : bx + 1};
    const int ys[3] = {by == 0 ? m_ny - 1 : by - 1, by, by == m_ny - 1 ? 0 : by + 1};
    int n = 0;
    for (int y : ys) {
        for (int x : xs)
            out[n++] = x + y * m_nx;
    }
}

void UniformGrid::build(const GridGeometry &geometry, const Vec2 *points, int count)
{
    m_geometry = geometry;
    const int buckets = geometry.bucketCount();
    m_start.assign(static_cast<std::size_t>(buckets) + 1, 0);
    m_items.resize(static_cast<std::size_t>(count));
    m_bucketOf.resize(static_cast<std::size_t>(count));
    m_cellX.resize(static_cast<std::size_t>(count));
    m_cellY.resize(static_cast<std::size_t>(count));
    // Counting sort: count per bucket, prefix sums, then place in index order (stable).
    for (int i = 0; i < count; ++i) {
        m_cellX[i] = geometry.coord(points[i].x);
        m_cellY[i] = geometry.coord(points[i].y);
        m_bucketOf[i] = geometry.bucket(m_cellX[i], m_cellY[i]);
        ++m_start[m_bucketOf[i] + 1];
    }
    accumulateCounts(m_start);
    // Place using a running cursor per bucket: reuse m_start shifted by one, then restore.
    for (int i = 0; i < count; ++i)
        m_items[m_start[m_bucketOf[i]]++] = i;
    for (int b = buckets; b > 0; --b)
        m_start[b] = m_start[b - 1];
    m_start[0] = 0;
}

} // namespace marbles
