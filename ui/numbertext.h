#pragma once

#include <QString>

#include <cmath>

namespace marbles {

/// Whether a number of this size is written whole by readableNumber() (and the plot's axes):
/// from 10^significant, where 'g' would switch to a power of ten, up to 1e12.
inline bool writtenWhole(double size, int significant = 6)
{
    return size >= std::pow(10.0, significant) && size < 1e12;
}

/// A value for a class to read: `significant` digits, but without a power of ten below 1e12,
/// where the whole number is written ("1031250", where "1.03125e+06" read badly, and "38010",
/// where four digits gave "3.801e+04").
inline QString readableNumber(double value, int significant = 6)
{
    if (writtenWhole(std::abs(value), significant))
        return QString::number(value, 'f', 0);
    return QString::number(value, 'g', significant);
}

} // namespace marbles
