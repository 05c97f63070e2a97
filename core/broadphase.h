#pragma once

#include "core/largebuffer.h"
#include "core/vec2.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace marbles {

/// std::max(m, v) folded over `values` from m = `floor`, in order (so NaNs are passed over), with
/// the same bits; kept as four running maxima so that the loop is not one chain of dependent
/// instructions (a 100k-marble radius scan took 0.13 ms as one chain).
double largestOf(std::span<const double> values, double floor = 0.0);

/// How a grid is sized from the radii. A grid's cells must be as wide as the largest contact, so
/// one marble far larger than the rest would make every cell hold dozens of small marbles (a
/// 100-px marble among 20,000 of radius 4 to 12 made the exact model 16 times slower). When a
/// few marbles are that much larger, they are left out of the grid ("oversize": each is tested
/// against the bodies of the cells within its reach, and every body against them) and the
/// cells are sized from the others.
struct RadiusSplit {
    /// At most this many marbles are left out: each costs every other marble one more test.
    static constexpr int maxOversize = 16;
    /// A radius above this many times the mean radius is a candidate for leaving out.
    static constexpr double oversizeFactor = 4.0;

    double largest = 0.0; ///< largestOf(radii)
    double cut = 0.0;     ///< the grid is sized for radii up to this (largest when none is left out)
    int oversize = 0;     ///< how many radii exceed `cut` (0 or 1 to maxOversize)

    /// Whether marble radius r is left out of the grid.
    bool isOversize(double r) const { return r > cut && oversize > 0; }
};

/// Splits `radii` (see RadiusSplit): when the largest exceeds oversizeFactor times the mean, the
/// radii above that bound are left out if they are at most maxOversize and the rest are at most
/// half the largest; otherwise nothing is. One pass over the radii, and a second only when the
/// largest is that far above the mean. NaN radii are passed over as in largestOf().
RadiusSplit splitRadii(std::span<const double> radii);
/// The same, for a caller that has already summed the radii and found the largest (largestOf's).
RadiusSplit splitRadii(std::span<const double> radii, double largest, double sum);

/// Per-bucket counts in counts[1..] become starts: counts[b + 1] += counts[b] in order, with
/// the running sum in a register instead of a store and a reload per bucket.
void accumulateCounts(std::span<int> counts);

/// The lattice of a uniform grid: square cells of side `cellSize` px, with cell (kx, ky)
/// covering [kx c, (kx + 1) c) x [ky c, (ky + 1) c). The plane is unbounded (marbles may leave
/// the stage when walls are off), so the lattice is *folded*: cell (kx, ky) is stored in bucket
/// (kx mod nx, ky mod ny). Two far-apart cells may share a bucket; that only adds candidates,
/// which the exact distance test then rejects, so folding never loses a contact.
/// With cellSize >= the largest contact distance, every pair in contact lies in the same or in
/// adjacent cells: the 3 x 3 neighbourhood of a cell holds all its possible partners.
class GridGeometry {
public:
    /// Cell coordinates are clamped to +-coordLimit so that far-away (or absurd) positions never
    /// overflow an integer; all bodies beyond the limit share the outermost row or column.
    static constexpr std::int64_t coordLimit = std::int64_t(1) << 40;

    /// Chooses the lattice for contact distances up to `contactPx`, over a region of about
    /// `widthPx` x `heightPx`, holding about `itemCount` bodies (at most ~2 buckets per body).
    static GridGeometry fit(double contactPx, double widthPx, double heightPx, int itemCount);

    /// Cell side, px.
    double cellSize() const { return m_cellSize; }
    /// 1 / cellSize, px^-1 (coord(x) is floor(x * inverseCellSize()) before clamping).
    double inverseCellSize() const { return m_invCellSize; }
    /// Buckets along x and y (each >= 3, so a 3 x 3 neighbourhood has 9 distinct buckets).
    int bucketsX() const { return m_nx; }
    int bucketsY() const { return m_ny; }
    /// Number of buckets, nx * ny.
    int bucketCount() const { return m_nx * m_ny; }

    /// Cell coordinate floor(x / cellSize), clamped to +-coordLimit (NaN maps to 0).
    std::int64_t coord(double x) const;
    /// Position of the lattice line k * cellSize, px.
    double line(std::int64_t k) const { return static_cast<double>(k) * m_cellSize; }
    /// Bucket of cell (kx, ky).
    int bucket(std::int64_t kx, std::int64_t ky) const;
    /// Bucket of the cell holding (x, y): bucket(coord(x), coord(y)), with the common case (a cell
    /// on the unfolded lattice) done without 64-bit integers or division.
    int bucketAt(double x, double y) const
    {
        // For t >= 0, floor(t) lies in [0, n) exactly when t does, and truncation is floor.
        const double tx = x * m_invCellSize;
        const double ty = y * m_invCellSize;
        if (tx >= 0.0 && tx < m_nx && ty >= 0.0 && ty < m_ny)
            return static_cast<int>(tx) + static_cast<int>(ty) * m_nx;
        return bucket(coord(x), coord(y));
    }

    /// The 9 buckets of the 3 x 3 neighbourhood of cell (kx, ky), row by row.
    void neighbourhood(std::int64_t kx, std::int64_t ky, int out[9]) const;
    /// The 9 buckets around bucket b (the neighbourhood of any cell stored in b), row by row.
    void bucketNeighbourhood(int b, int out[9]) const;

    /// Calls run(first, last) for runs of consecutive buckets [first, last) that together are
    /// the buckets of the cells meeting the box [x0, x1] x [y0, y1], each bucket once. Returns
    /// false, calling nothing, when that is every bucket (or the box is not finite): the caller
    /// then visits everything its own way.
    template<typename Run>
    bool forEachRunInBox(double x0, double x1, double y0, double y1, Run &&run) const;

    /// The same lattice (every body lands in the same bucket).
    bool operator==(const GridGeometry &) const = default;

private:
    double m_cellSize = 1.0;
    double m_invCellSize = 1.0;
    int m_nx = 3;
    int m_ny = 3;
};

template<typename Run>
bool GridGeometry::forEachRunInBox(double x0, double x1, double y0, double y1, Run &&run) const
{
    if (!(x0 <= x1 && y0 <= y1) || !std::isfinite(x0) || !std::isfinite(x1) || !std::isfinite(y0) || !std::isfinite(y1))
        return false;
    const std::int64_t kx0 = coord(x0);
    const std::int64_t ky0 = coord(y0);
    const std::int64_t spanX = coord(x1) - kx0 + 1;
    const std::int64_t spanY = coord(y1) - ky0 + 1;
    if (spanX >= m_nx && spanY >= m_ny)
        return false;
    // Folded, the columns are one run of buckets, or two where they wrap around (all columns
    // once if there are at least nx of them); the rows are taken one by one, likewise at most ny.
    const int columns = static_cast<int>(std::min<std::int64_t>(spanX, m_nx));
    const int rows = static_cast<int>(std::min<std::int64_t>(spanY, m_ny));
    const int first = bucket(kx0, ky0);
    const int bx0 = columns == m_nx ? 0 : first % m_nx;
    const int by0 = first / m_nx;
    for (int r = 0; r < rows; ++r) {
        const int row = (by0 + r) % m_ny * m_nx;
        const int end = bx0 + columns;
        run(row + bx0, row + std::min(end, m_nx));
        if (end > m_nx)
            run(row, row + end - m_nx);
    }
    return true;
}

/// A static uniform grid: bodies sorted into buckets by a counting sort (stable, so each bucket
/// lists its bodies in ascending index order). Rebuilt from scratch when asked; the buffers are
/// kept between builds, so a steady-state rebuild allocates nothing.
class UniformGrid {
public:
    /// Sorts `points[0..count)` into the buckets of `geometry`.
    void build(const GridGeometry &geometry, const Vec2 *points, int count);

    /// The lattice in use.
    const GridGeometry &geometry() const { return m_geometry; }
    /// Bodies in bucket b: items()[begin(b) .. end(b)), ascending indices.
    int begin(int b) const { return m_start[b]; }
    int end(int b) const { return m_start[b + 1]; }
    /// The sorted body indices.
    const LargeVector<int> &items() const { return m_items; }
    /// Cell coordinates of body i at the last build.
    std::int64_t cellX(int i) const { return m_cellX[i]; }
    std::int64_t cellY(int i) const { return m_cellY[i]; }

private:
    GridGeometry m_geometry;
    LargeVector<int> m_start;
    LargeVector<int> m_items;
    LargeVector<int> m_bucketOf;
    LargeVector<std::int64_t> m_cellX;
    LargeVector<std::int64_t> m_cellY;
};

} // namespace marbles
