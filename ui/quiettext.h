#pragma once

#include <QColor>
#include <QPalette>
#include <QWidget>

namespace marbles {

/// Draws `widget`'s text as the quieter line under a field or a chart (an explanation, a note):
/// its text colour two thirds of the way from the background's, about 6:1 against it. The
/// palette's PlaceholderText, used before, is half-transparent: about 2.9:1, too faint to read
/// from the back of a classroom on a projector.
inline void setQuietText(QWidget *widget)
{
    QPalette palette = widget->palette();
    const QColor text = palette.color(QPalette::WindowText);
    const QColor back = palette.color(QPalette::Window);
    const auto mix = [](int t, int b) { return (2 * t + b) / 3; };
    palette.setColor(QPalette::WindowText, QColor(mix(text.red(), back.red()), mix(text.green(), back.green()),
                                                  mix(text.blue(), back.blue())));
    widget->setPalette(palette);
    widget->setForegroundRole(QPalette::WindowText);
}

} // namespace marbles
