#include "ui/refusingspinbox.h"

#include <QCoreApplication>

#include <cmath>

namespace marbles {

QString refusedNumber(const Refusing &box, double refused, const QLocale &locale)
{
    if ((std::isinf(refused) || box.refusedUnreadable()) && !box.refusedText().isEmpty())
        return box.refusedText(); // "inf" or "nan" would not be what was typed
    QLocale loc = locale;
    loc.setNumberOptions(loc.numberOptions() | QLocale::OmitGroupSeparator);
    return loc.toString(refused, 'g', 12);
}

namespace {

// A field's limit as the field writes it, without the zeros its decimals add ("100000 px/frame",
// "0.5 px"): the velocity fields' 4 to 6 decimals wrote "100000.000000 px/frame".
QString limitText(const Refusing &box, double limit, const QLocale &locale)
{
    QString text = box.shown(limit);
    const qsizetype point = text.indexOf(locale.decimalPoint());
    if (point < 0)
        return text;
    qsizetype end = point + locale.decimalPoint().size();
    while (end < text.size() && text.at(end).isDigit())
        ++end;
    qsizetype keep = end;
    while (keep > point + locale.decimalPoint().size() && text.at(keep - 1) == QLatin1Char('0'))
        --keep;
    if (keep == point + locale.decimalPoint().size())
        keep = point;
    return text.left(keep) + text.mid(end);
}

} // namespace

QString refusalMessage(const Refusing &box, double refused, const QLocale &locale)
{
    const QString typed = refusedNumber(box, refused, locale);
    const QString kept = box.shown(box.current());
    if (box.refusal() == Refusing::Refusal::TooSmall)
        return QCoreApplication::translate("marbles", "%1 is closer to 0 than a number can be here: it stays %2.").arg(typed, kept);
    if (box.refusal() == Refusing::Refusal::NotANumber)
        return QCoreApplication::translate("marbles", "%1 is not a number: it stays %2.").arg(typed, kept);
    if (box.refusal() == Refusing::Refusal::NotWhole)
        return QCoreApplication::translate("marbles", "%1 is not taken: this field takes whole numbers, typed as digits only. It stays %2.")
            .arg(typed, kept);
    if (box.refusal() == Refusing::Refusal::Grouped)
        return QCoreApplication::translate("marbles",
                                           "%1 can be read two ways: type it without group separators, with \"%2\" "
                                           "or \"%3\" for the decimal point. It stays %4.")
            .arg(typed, locale.decimalPoint(), locale.decimalPoint() == QLatin1String(",") ? QStringLiteral(".") : QStringLiteral(","), kept);
    if (refused > box.high())
        return QCoreApplication::translate("marbles", "%1 is above this field's maximum (%2): it stays %3.")
            .arg(typed, limitText(box, box.high(), locale), kept);
    return QCoreApplication::translate("marbles", "%1 is below this field's minimum (%2): it stays %3.")
        .arg(typed, limitText(box, box.low(), locale), kept);
}

} // namespace marbles
