#pragma once

#include <QString>

#include <cmath>

namespace marbles {

/// A value for a class to read: `significant` digits, but without a power of ten between 1e5
/// and 1e12, where the whole number is written ("1031250", where "1.03125e+06" read badly).
inline QString readableNumber(double value, int significant = 6)
{
    const double size = std::abs(value);
    if (size >= 1e5 && size < 1e12)
        return QString::number(value, 'f', 0);
    return QString::number(value, 'g', significant);
}

} // namespace marbles
