#include "ui/elidingstatusbar.h"

#include <QHelpEvent>
#include <QPainter>
#include <QStyleOption>
#include <QToolTip>

#include <algorithm>
#include <utility>

namespace marbles {

ElidingStatusBar::ElidingStatusBar(QWidget *parent)
    : QStatusBar(parent)
{
    connect(this, &QStatusBar::messageChanged, this, &ElidingStatusBar::makeRoom);
}

void ElidingStatusBar::setYielding(const QList<QWidget *> &widgets)
{
    m_yielding = widgets;
    makeRoom();
}

void ElidingStatusBar::resizeEvent(QResizeEvent *event)
{
    QStatusBar::resizeEvent(event);
    makeRoom();
}

void ElidingStatusBar::makeRoom()
{
    const QString message = currentMessage();
    int fixed = 0;
    qreal asked = 0;
    for (const QWidget *child : findChildren<QWidget *>(QString(), Qt::FindDirectChildrenOnly)) {
        if (!child->isVisibleTo(this))
            continue;
        if (m_yielding.contains(child))
            asked += child->sizeHint().width();
        else
            fixed += child->sizeHint().width();
        fixed += 8; // the item's frame and the layout's spacing
    }
    const int want = message.isEmpty() ? 0 : std::min(fontMetrics().horizontalAdvance(message) + 8, width() * 2 / 5);
    const int room = width() - 18 - want - fixed;
    for (QWidget *w : std::as_const(m_yielding)) {
        const int limit = message.isEmpty() || room >= asked || asked <= 0
            ? QWIDGETSIZE_MAX
            : std::max(0, static_cast<int>(room * (w->sizeHint().width() / asked)));
        if (w->maximumWidth() != limit)
            w->setMaximumWidth(limit);
    }
}

QRect ElidingStatusBar::messageRect() const
{
    // As QStatusBar places its message: from 6 px in, up to 2 px before the leftmost permanent
    // widget shown (or 12 px before the edge). Where the widgets take the whole bar (a narrow
    // window while comparing) there is no room: one at the bar's left edge was passed over, and
    // the message was drawn on top of it.
    int right = width() - 12;
    for (const QWidget *child : findChildren<QWidget *>(QString(), Qt::FindDirectChildrenOnly)) {
        if (child->isVisible() && child->isWidgetType())
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
    // A figure's text changed length, or one was shown or hidden: the room is shared out again.
    if (event->type() == QEvent::LayoutRequest)
        makeRoom();
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
