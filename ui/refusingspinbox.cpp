#include "ui/refusingspinbox.h"

#include <QCoreApplication>

#include <cmath>

namespace marbles {

QString refusedNumber(const Refusing &box, double refused, const QLocale &locale)
{
    if (std::isinf(refused) && !box.refusedText().isEmpty())
        return box.refusedText(); // "inf" would not be what was typed
    QLocale loc = locale;
    loc.setNumberOptions(loc.numberOptions() | QLocale::OmitGroupSeparator);
    return loc.toString(refused, 'g', 12);
}

QString refusalMessage(const Refusing &box, double refused, const QLocale &locale)
{
    const QString typed = refusedNumber(box, refused, locale);
    const QString kept = box.shown(box.current());
    if (refused > box.high())
        return QCoreApplication::translate("marbles", "%1 is above this field's maximum (%2): it stays %3.")
            .arg(typed, box.shown(box.high()), kept);
    return QCoreApplication::translate("marbles", "%1 is below this field's minimum (%2): it stays %3.")
        .arg(typed, box.shown(box.low()), kept);
}

} // namespace marbles
