#include "ui/vectoritem.h"

#include <QPainter>

#include <cmath>

namespace marbles {

namespace {

/// The book multiplies the unit vectors by 30 when it draws them ("to make them large and easy
/// to see"); its marbles are small, so here the 30 px start at the marble's edge instead.
constexpr double kBookLengthPx = 30.0;

void drawArrow(QPainter *painter, QPointF from, QPointF to)
{
    painter->drawLine(from, to);
    const QPointF d = to - from;
    const double len = std::hypot(d.x(), d.y());
    if (len <= 0.0)
        return;
    const QPointF u = d / len;
    const QPointF n(-u.y(), u.x());
    const double head = 8.0;
    // A polygon, not a QPainterPath: the raster engine fills a small polygon many times faster.
    const QPointF corners[3] = {to, to - u * head + n * head * 0.5, to - u * head - n * head * 0.5};
    const QPen pen = painter->pen();
    painter->setPen(Qt::NoPen);
    painter->setBrush(pen.color());
    painter->drawPolygon(corners, 3);
    painter->setBrush(Qt::NoBrush);
    painter->setPen(pen);
}

} // namespace

VectorItem::VectorItem() = default;

void VectorItem::setHit(const HitRecord &hit, double radiusPx)
{
    if (hit == m_hit && radiusPx == m_radius)
        return;
    if (radiusPx != m_radius)
        prepareGeometryChange();
    m_hit = hit;
    m_radius = radiusPx;
    update();
}

double VectorItem::lengthPx() const
{
    return m_radius + kBookLengthPx;
}

QRectF VectorItem::boundingRect() const
{
    const double l = lengthPx() + 10.0;
    return {-l, -l, 2 * l, 2 * l};
}

void VectorItem::paint(QPainter *painter, const QStyleOptionGraphicsItem *, QWidget *)
{
    if (m_hit.frame < 0)
        return;
    painter->setRenderHint(QPainter::Antialiasing);
    const double l = lengthPx();
    const QPointF centre(0, 0);
    const auto scaled = [l](Vec2 u) { return QPointF(u.x * l, u.y * l); };

    QPen red(QColor(0xe0, 0x00, 0x00));
    red.setCosmetic(true);
    red.setWidthF(1.0);
    painter->setPen(red);
    painter->drawLine(scaled(m_hit.normal) * -1.0, scaled(m_hit.normal));

    QPen blue(QColor(0x00, 0x55, 0xff));
    blue.setCosmetic(true);
    blue.setWidthF(4.0);
    blue.setCapStyle(Qt::FlatCap);
    painter->setPen(blue);
    drawArrow(painter, centre, scaled(m_hit.velocityIn));

    QPen green(QColor(0x00, 0xb0, 0x20));
    green.setCosmetic(true);
    green.setWidthF(2.0);
    painter->setPen(green);
    drawArrow(painter, centre, scaled(m_hit.velocityOut));
}

} // namespace marbles
