#include "ui/elidingstatusbar.h"

#include <QHelpEvent>
#include <QPainter>
#include <QStyleOption>
#include <QToolTip>

#include <algorithm>

namespace marbles {

QRect ElidingStatusBar::messageRect() const
{
    // As QStatusBar places its message: from 6 px in, up to 2 px before the leftmost permanent
    // widget shown (or 12 px before the edge).
    int right = width() - 12;
    for (const QWidget *child : findChildren<QWidget *>(QString(), Qt::FindDirectChildrenOnly)) {
        if (child->isVisible() && child->isWidgetType() && child->x() > 6)
            right = std::min(right, child->x() - 2);
    }
    return QRect(6, 0, std::max(0, right - 6), height());
}

QString ElidingStatusBar::shownMessage() const
{
    return fontMetrics().elidedText(currentMessage(), Qt::ElideRight, messageRect().width());
}

void ElidingStatusBar::paintEvent(QPaintEvent *event)
{
    // QStatusBar::paintEvent() with the message elided: the panel, a frame for each widget shown
    // (every one is permanent here), then the text.
    QPainter painter(this);
    QStyleOption panel;
    panel.initFrom(this);
    style()->drawPrimitive(QStyle::PE_PanelStatusBar, &panel, &painter, this);
    for (const QWidget *child : findChildren<QWidget *>(QString(), Qt::FindDirectChildrenOnly)) {
        const QRect frame = child->geometry().adjusted(-2, -1, 2, 1);
        if (!child->isVisible() || !event->rect().intersects(frame))
            continue;
        QStyleOption option(0);
        option.rect = frame;
        option.palette = palette();
        option.state = QStyle::State_None;
        style()->drawPrimitive(QStyle::PE_FrameStatusBarItem, &option, &painter, child);
    }
    if (!currentMessage().isEmpty()) {
        painter.setPen(palette().windowText().color());
        painter.drawText(messageRect(), Qt::AlignLeading | Qt::AlignVCenter | Qt::TextSingleLine, shownMessage());
    }
}

bool ElidingStatusBar::event(QEvent *event)
{
    if (event->type() == QEvent::ToolTip) {
        const auto *help = static_cast<QHelpEvent *>(event);
        if (messageRect().contains(help->pos()) && shownMessage() != currentMessage()) {
            QToolTip::showText(help->globalPos(), currentMessage(), this, messageRect());
            return true;
        }
    }
    return QStatusBar::event(event);
}

} // namespace marbles
