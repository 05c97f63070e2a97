#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace marbles {

/// A 2-D vector in stage coordinates: px, px/frame or px/frame^2 depending on use.
/// y grows downwards (screen convention).
struct Vec2 {
    double x = 0.0;
    double y = 0.0;

    friend constexpr bool operator==(const Vec2 &, const Vec2 &) = default;
};

/// Euclidean length, computed as the book's dist(0, 0, x, y): sqrt(x*x + y*y), no fused multiply-add.
inline double length(Vec2 u)
{
    return std::sqrt(u.x * u.x + u.y * u.y);
}

/// Distance between two points, as the book's dist(): sqrt((a.x-b.x)^2 + (a.y-b.y)^2).
inline double distance(Vec2 a, Vec2 b)
{
    const double dx = a.x - b.x;
    const double dy = a.y - b.y;
    return std::sqrt(dx * dx + dy * dy);
}

/// Dot product, the book's dotProduct(): (a.x * b.x) + (a.y * b.y).
inline double dot(Vec2 a, Vec2 b)
{
    return a.x * b.x + a.y * b.y;
}

/// u / |u|, or (0, 0) where |u| is zero, infinite or NaN.
inline Vec2 unitOrZero(Vec2 u)
{
    const double len = length(u);
    if (!(len > 0.0) || !std::isfinite(len))
        return {};
    return {u.x / len, u.y / len};
}

/// True when both components are finite (neither NaN nor infinite).
inline bool isFinite(Vec2 u)
{
    return std::isfinite(u.x) && std::isfinite(u.y);
}

/// The same bits: +0 and -0 differ, and a NaN equals itself (a copy that is valid only while it
/// is the value).
inline bool sameBits(double a, double b)
{
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline bool sameBits(Vec2 a, Vec2 b)
{
    return sameBits(a.x, b.x) && sameBits(a.y, b.y);
}

/// isFinite(u) without a branch, from the bits (an exponent of all ones is an infinity or a
/// NaN): for a model's loops that note on the way whether every number they wrote is finite, one
/// AND a value, where a branch or a chain of floating-point sums cost a loop over resting
/// marbles a tenth of its time.
inline bool finiteBits(Vec2 u)
{
    constexpr std::uint64_t exponent = 0x7ff0000000000000;
    return ((std::bit_cast<std::uint64_t>(u.x) & exponent) != exponent) & ((std::bit_cast<std::uint64_t>(u.y) & exponent) != exponent);
}

} // namespace marbles
