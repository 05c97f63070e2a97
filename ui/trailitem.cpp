#include "ui/trailitem.h"

#include <QPainter>

namespace marbles {

TrailItem::TrailItem(int length)
    : m_length(length > 1 ? length : 2)
{
}

void TrailItem::setArea(const QRectF &area)
{
    if (area == m_area)
        return;
    prepareGeometryChange();
    m_area = area;
}

void TrailItem::sample(const World &world)
{
    const auto n = static_cast<std::size_t>(world.marbleCount());
    if (m_trails.size() != n)
        m_trails.assign(n, {});
    for (std::size_t i = 0; i < n; ++i) {
        auto &trail = m_trails[i];
        trail.emplace_back(world.position[i].x, world.position[i].y);
        while (static_cast<int>(trail.size()) > m_length)
            trail.pop_front();
    }
    update();
}

void TrailItem::clear()
{
    m_trails.clear();
    update();
}

QRectF TrailItem::boundingRect() const
{
    return m_area.adjusted(-200, -200, 200, 200);
}

void TrailItem::paint(QPainter *painter, const QStyleOptionGraphicsItem *, QWidget *)
{
    painter->setRenderHint(QPainter::Antialiasing);
    QPen pen(QColor(0x24, 0x63, 0xd1));
    pen.setCosmetic(true);
    pen.setWidthF(2.0);
    pen.setCapStyle(Qt::RoundCap);
    for (const auto &trail : m_trails) {
        const auto count = trail.size();
        for (std::size_t k = 1; k < count; ++k) {
            // Opacity grows linearly from the oldest segment (transparent) to the newest.
            QColor c = pen.color();
            c.setAlphaF(0.6f * static_cast<float>(k) / static_cast<float>(count));
            pen.setColor(c);
            painter->setPen(pen);
            painter->drawLine(trail[k - 1], trail[k]);
        }
    }
}

} // namespace marbles
