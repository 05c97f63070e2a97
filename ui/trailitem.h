#pragma once

#include "core/world.h"

#include <QGraphicsItem>

#include <deque>
#include <vector>

namespace marbles {

/// Fading trails behind every marble: the last positions of each, one per simulated frame,
/// drawn more transparent the older they are. One item for all marbles keeps the scene small.
class TrailItem : public QGraphicsItem {
public:
    enum { Type = UserType + 4 };

    /// Trails of at most `length` frames.
    explicit TrailItem(int length = 90);

    /// Area the trails may cover (the stage), stage px.
    void setArea(const QRectF &area);
    /// Appends the marbles' current positions.
    void sample(const World &world);
    /// Forgets every trail.
    void clear();

    int type() const override { return Type; }
    QRectF boundingRect() const override;
    void paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *widget) override;

private:
    int m_length;
    QRectF m_area;
    std::vector<std::deque<QPointF>> m_trails;
};

} // namespace marbles
