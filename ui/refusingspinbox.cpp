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
            .arg(typed, box.shown(box.high()), kept);
    return QCoreApplication::translate("marbles", "%1 is below this field's minimum (%2): it stays %3.")
        .arg(typed, box.shown(box.low()), kept);
}

} // namespace marbles
