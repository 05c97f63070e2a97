#pragma once

// Bit-for-bit comparisons for the fuzz targets: +0 and -0 differ, and a NaN equals itself.

#include "core/world.h"

#include <bit>
#include <cstdint>
#include <vector>

namespace marbles::fuzzbits {

inline bool same(double a, double b)
{
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline bool same(Vec2 a, Vec2 b)
{
    return same(a.x, b.x) && same(a.y, b.y);
}

inline bool same(const HitRecord &a, const HitRecord &b)
{
    return a.frame == b.frame && same(a.velocityIn, b.velocityIn) && same(a.normal, b.normal)
        && same(a.velocityOut, b.velocityOut);
}

/// The first index at which `a` and `b` differ (0 when their sizes do), or -1.
template<typename T>
int firstDifference(const std::vector<T> &a, const std::vector<T> &b)
{
    if (a.size() != b.size())
        return 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!same(a[i], b[i]))
            return static_cast<int>(i);
    }
    return -1;
}

template<typename T>
bool same(const std::vector<T> &a, const std::vector<T> &b)
{
    return firstDifference(a, b) < 0;
}

} // namespace marbles::fuzzbits
