#pragma once

#include <QLocale>
#include <QString>

#include <algorithm>
#include <cmath>

namespace marbles {

/// Whether a number of this size is written whole by readableNumber() (and the plot's axes):
/// from 10^significant, where 'g' would switch to a power of ten, up to 1e12.
inline bool writtenWhole(double size, int significant = 6)
{
    return size >= std::pow(10.0, significant) && size < 1e12;
}

/// The desktop's language for the numbers the window writes (its decimal mark: "0,5" in German),
/// without group separators, as the fields show them: the Undo History, the status bar and the
/// plot had written "0.5" beside a field's "0,5" (a German-locale tester's finding). Files, the
/// CSV exports and the values handed to the scene are written in C's way whatever the language.
inline QLocale shownLocale()
{
    QLocale locale;
    locale.setNumberOptions(locale.numberOptions() | QLocale::OmitGroupSeparator);
    return locale;
}

/// `value` as QString::number(value, format, precision) writes it, in the desktop's language;
/// a zero is written without a sign, as is a small negative number rounded to one (a click
/// pushed by "(6.05, -0.00) px/frame").
inline QString shownNumber(double value, char format = 'g', int precision = 6)
{
    const QLocale locale = shownLocale();
    const QString text = locale.toString(value, format, precision);
    if (std::signbit(value) && text.startsWith(locale.negativeSign())) {
        const QString zero = locale.toString(0.0, format, precision);
        if (QStringView(text).sliced(locale.negativeSign().size()) == zero)
            return zero;
    }
    return text;
}

/// What separates numbers in a list: ", ", or "; " where the decimal mark is a comma ("0,5; 1,2").
inline QString shownListSeparator()
{
    return shownLocale().decimalPoint() == QLatin1String(",") ? QStringLiteral("; ") : QStringLiteral(", ");
}

/// "1 marble", "3 marbles": `n` and the word for one or for many. (tr("%n marble(s)") is written
/// "3 marble(s)" without a translation file, and the window loads none: its texts are English.)
inline QString counted(qint64 n, const QString &one, const QString &many)
{
    return shownLocale().toString(n) + QLatin1Char(' ') + (n == 1 ? one : many);
}

/// "(x, y)", or "(x; y)" where the decimal mark is a comma ("(0,5; 1,2)", not "(0,5, 1,2)").
inline QString shownPair(const QString &x, const QString &y)
{
    return QLatin1Char('(') + x + shownListSeparator() + y + QLatin1Char(')');
}

/// A value for a class to read: `significant` digits, but without a power of ten below 1e12,
/// where the whole number is written ("1031250", where "1.03125e+06" read badly, and "38010",
/// where four digits gave "3.801e+04").
inline QString readableNumber(double value, int significant = 6)
{
    if (writtenWhole(std::abs(value), significant))
        return shownNumber(value, 'f', 0);
    return shownNumber(value, 'g', significant);
}

/// Decimals of a velocity as the window shows it (the Inspector's fields, the Undo History): the
/// zero threshold's and two more, 3 to 6. With 3, a velocity of 0.0104 px/frame, above the
/// default threshold of 0.01 and so left moving, read "0.010", the threshold itself (a class
/// asked why it had not been set to 0).
inline int velocityDecimals(double zeroThreshold)
{
    if (!(zeroThreshold > 0.0) || !std::isfinite(zeroThreshold))
        return 3;
    const double digits = std::ceil(-std::log10(zeroThreshold) - 1e-9) + 2.0;
    return static_cast<int>(std::clamp(digits, 3.0, 6.0));
}

/// `text` without the zeros ending the digits after its first decimal `point`, nor the point
/// when none is left; what follows the digits stays ("5000.00 px" gives "5000 px", "1.2340"
/// "1.234").
inline QString withoutTrailingZeros(const QString &text, const QString &point = QStringLiteral("."))
{
    const qsizetype at = text.indexOf(point);
    if (at < 0)
        return text;
    const qsizetype digits = at + point.size();
    qsizetype end = digits;
    while (end < text.size() && text.at(end).isDigit())
        ++end;
    qsizetype keep = end;
    while (keep > digits && text.at(keep - 1) == QLatin1Char('0'))
        --keep;
    if (keep == digits)
        keep = at;
    return text.left(keep) + text.mid(end);
}

/// `value` to `decimals` places, without trailing zeros ("1.2346", "6", "0.000012").
inline QString fixedTrimmed(double value, int decimals)
{
    return withoutTrailingZeros(shownNumber(value, 'f', decimals), shownLocale().decimalPoint());
}

} // namespace marbles
