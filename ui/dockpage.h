#pragma once

#include <QMetaObject>

class QDockWidget;
class QWidget;

namespace marbles {

/// A dock's page in a scroll area of its own, which the dock then shows. On a small screen (a
/// 1280 x 720 projector at a scale of 1.5 is 853 x 480) the page scrolls instead of growing the
/// window past the screen's edge, and a field that takes the focus (by Tab, or Alt and its
/// letter) is scrolled into sight. The returned connection does that scrolling: disconnect it in
/// the dock's destructor, before the page goes.
QMetaObject::Connection putInScrollArea(QDockWidget *dock, QWidget *page);

} // namespace marbles
