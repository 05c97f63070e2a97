#include "ui/marbleitem.h"

#include <QPainter>
#include <QRadialGradient>

namespace marbles {

namespace {

/// The chapter's marble blue.
const QColor kMarbleBlue(0x24, 0x63, 0xd1);
const QColor kSelection(0x1a, 0x1a, 0x1a);
const QColor kHeld(0x2e, 0x7d, 0x32);
/// Room around the ball for the selection ring, px.
constexpr double kRingMargin = 6.0;

} // namespace

MarbleItem::MarbleItem(double radiusPx, const QColor &color)
    : m_radius(radiusPx)
    , m_color(color)
{
    // The ball is rendered once into a pixmap in device pixels and blitted as it moves; it is
    // redrawn only on a zoom or a change of look (radius, colour, ring).
    setCacheMode(DeviceCoordinateCache);
}

void MarbleItem::setRadius(double radiusPx)
{
    if (radiusPx == m_radius)
        return;
    prepareGeometryChange();
    m_radius = radiusPx;
}

void MarbleItem::setColor(const QColor &color)
{
    if (color == m_color)
        return;
    m_color = color;
    update();
}

void MarbleItem::setHighlighted(bool highlighted)
{
    if (highlighted == m_highlighted)
        return;
    m_highlighted = highlighted;
    update();
}

void MarbleItem::setHeld(bool held)
{
    if (held == m_held)
        return;
    m_held = held;
    update();
}

QRectF MarbleItem::boundingRect() const
{
    const double r = m_radius + kRingMargin;
    return {-r, -r, 2 * r, 2 * r};
}

QColor MarbleItem::defaultColor()
{
    return kMarbleBlue;
}

QColor MarbleItem::selectionColor()
{
    return kSelection;
}

QColor MarbleItem::heldColor()
{
    return kHeld;
}

void MarbleItem::paintBall(QPainter *painter, QPointF centre, double r, const QColor &base, double outlinePx)
{
    // Light from the upper left: a highlight off-centre, the base colour, a dark rim.
    QRadialGradient gradient(centre, r, centre + QPointF(-0.38 * r, -0.42 * r));
    gradient.setColorAt(0.0, base.lighter(230));
    gradient.setColorAt(0.18, base.lighter(150));
    gradient.setColorAt(0.65, base);
    gradient.setColorAt(1.0, base.darker(230));
    painter->setRenderHint(QPainter::Antialiasing);
    QPen outline(base.darker(300));
    outline.setWidthF(outlinePx);
    outline.setCosmetic(true);
    painter->setPen(outline);
    painter->setBrush(gradient);
    painter->drawEllipse(centre, r, r);
}

void MarbleItem::paint(QPainter *painter, const QStyleOptionGraphicsItem *, QWidget *)
{
    const double r = m_radius;
    paintBall(painter, QPointF(0, 0), r, m_color.isValid() ? m_color : kMarbleBlue, 1.0);
    if (m_highlighted || m_held) {
        QPen ring(m_held ? kHeld : kSelection);
        ring.setWidthF(2.0);
        ring.setCosmetic(true);
        ring.setStyle(m_held ? Qt::SolidLine : Qt::DashLine);
        painter->setPen(ring);
        painter->setBrush(Qt::NoBrush);
        painter->drawEllipse(QPointF(0, 0), r + 3.0, r + 3.0);
    }
}

} // namespace marbles
