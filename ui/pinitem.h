#pragma once

#include <QGraphicsItem>

namespace marbles {

/// One pin: a small red dot (a point in the physics; the dot only shows where it is).
class PinItem : public QGraphicsItem {
public:
    enum { Type = UserType + 2 };

    PinItem();

    /// Draws the selection ring.
    void setHighlighted(bool highlighted);

    int type() const override { return Type; }
    QRectF boundingRect() const override;
    void paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *widget) override;

private:
    bool m_highlighted = false;
};

} // namespace marbles
