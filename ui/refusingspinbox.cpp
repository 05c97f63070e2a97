#include "ui/refusingspinbox.h"

#include "ui/numbertext.h"

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

QString refusalMessage(const Refusing &box, double refused, const QLocale &locale)
{
    const QString typed = refusedNumber(box, refused, locale);
    const QString kept = box.shown(box.current());
    if (box.refusal() == Refusing::Refusal::TooSmall)
        return QCoreApplication::translate("marbles", "%1 is closer to 0 than a number can be here: it stays %2.").arg(typed, kept);
    if (box.refusal() == Refusing::Refusal::Empty)
        return QCoreApplication::translate("marbles", "The field was left empty: it stays %1.").arg(kept);
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
    // A limit as the field writes it, without the zeros its decimals add ("100000 px/frame",
    // "0.5 px"): the velocity fields' 4 to 6 decimals wrote "100000.000000 px/frame".
    if (refused > box.high())
        return QCoreApplication::translate("marbles", "%1 is above this field's maximum (%2): it stays %3.")
            .arg(typed, withoutTrailingZeros(box.shown(box.high()), locale.decimalPoint()), kept);
    return QCoreApplication::translate("marbles", "%1 is below this field's minimum (%2): it stays %3.")
        .arg(typed, withoutTrailingZeros(box.shown(box.low()), locale.decimalPoint()), kept);
}

} // namespace marbles
