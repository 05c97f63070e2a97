#include "ui/dockpage.h"

#include <QApplication>
#include <QDockWidget>
#include <QFrame>
#include <QScrollArea>

namespace marbles {

QMetaObject::Connection putInScrollArea(QDockWidget *dock, QWidget *page)
{
    auto *scroll = new QScrollArea(dock);
    scroll->setWidgetResizable(true);
    scroll->setFrameShape(QFrame::NoFrame);
    scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAsNeeded);
    scroll->setWidget(page);
    // Not a stop of its own for Tab (it showed no focus, and the arrow keys then scrolled it).
    scroll->setFocusPolicy(Qt::NoFocus);
    dock->setWidget(scroll);
    return QObject::connect(qApp, &QApplication::focusChanged, scroll, [scroll, page](QWidget *, QWidget *now) {
        if (now && page->isAncestorOf(now))
            scroll->ensureWidgetVisible(now);
    });
}

} // namespace marbles
