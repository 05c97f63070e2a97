#pragma once

#include "core/world.h"

#include <QGraphicsItem>

namespace marbles {

/// The chapter's Figure 11.12 for one marble, drawn at the marble's centre: the velocity before
/// its last collision (blue, thick), the collision vector both ways (red hairline) and the
/// reflected velocity (green). The world keeps the unit vectors (World::lastHit); this item only draws them.
class VectorItem : public QGraphicsItem {
public:
    enum { Type = UserType + 3 };

    VectorItem();

    /// Shows `hit` (nothing when hit.frame < 0) around a marble of radius `radiusPx`. The owner
    /// hides items of marbles never hit, so that the scene skips them.
    void setHit(const HitRecord &hit, double radiusPx);

    int type() const override { return Type; }
    QRectF boundingRect() const override;
    void paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *widget) override;

private:
    double lengthPx() const;

    HitRecord m_hit;
    double m_radius = 0.0;
};

} // namespace marbles
