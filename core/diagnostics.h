#pragma once

#include "core/world.h"

namespace marbles {

/// Largest penetration in the world, px: max over marble pairs of (r_i + r_j - distance),
/// over marble-pin pairs of (r_i - distance), and, with walls, over marbles of how far the
/// disc reaches past an edge. 0 when nothing overlaps. O(n) with a uniform grid.
double maxOverlap(const World &world);

/// Marbles whose centre is outside the stage rectangle while walls are on (0 with walls off).
int escapedMarbles(const World &world);

/// Sum over marbles of m |v| (mass px/frame): a scale for relative momentum errors that is not
/// zero when the total momentum is.
double momentumScale(const World &world);

} // namespace marbles
