#include "ui/pinitem.h"

#include "ui/marbleitem.h"
#include "ui/worldedit.h"

#include <QPainter>

namespace marbles {

namespace {

constexpr double kDotRadius = kPinDotRadiusPx;

} // namespace

PinItem::PinItem() = default;

void PinItem::setHighlighted(bool highlighted)
{
    if (highlighted == m_highlighted)
        return;
    m_highlighted = highlighted;
    update();
}

QRectF PinItem::boundingRect() const
{
    const double r = kDotRadius + 6.0;
    return {-r, -r, 2 * r, 2 * r};
}

void PinItem::paint(QPainter *painter, const QStyleOptionGraphicsItem *, QWidget *)
{
    painter->setRenderHint(QPainter::Antialiasing);
    QPen outline(QColor(0x7f, 0x00, 0x00));
    outline.setCosmetic(true);
    painter->setPen(outline);
    painter->setBrush(QColor(0xe5, 0x1c, 0x23));
    painter->drawEllipse(QPointF(0, 0), kDotRadius, kDotRadius);
    if (m_highlighted) {
        QPen ring(MarbleItem::selectionColor());
        ring.setWidthF(2.0);
        ring.setCosmetic(true);
        ring.setStyle(Qt::DashLine);
        painter->setPen(ring);
        painter->setBrush(Qt::NoBrush);
        painter->drawEllipse(QPointF(0, 0), kDotRadius + 4.0, kDotRadius + 4.0);
    }
}

} // namespace marbles
