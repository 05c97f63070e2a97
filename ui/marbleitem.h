#pragma once

#include <QColor>
#include <QGraphicsItem>

namespace marbles {

/// One marble on the stage: a shaded ball like the chapter's blue marbles. It mirrors the
/// world (position, radius, colour are set from outside) and owns no physics.
class MarbleItem : public QGraphicsItem {
public:
    enum { Type = UserType + 1 };

    /// A marble of radius `radiusPx`, drawn in `color` (invalid = the chapter's blue).
    explicit MarbleItem(double radiusPx = 10.0, const QColor &color = {});

    /// Radius in stage px.
    double radius() const { return m_radius; }
    /// Sets the radius, stage px.
    void setRadius(double radiusPx);
    /// Sets the colour (invalid = the chapter's blue).
    void setColor(const QColor &color);
    /// The colour set (invalid = the chapter's blue).
    QColor color() const { return m_color; }
    /// Draws the selection ring.
    void setHighlighted(bool highlighted);
    /// Draws the "held by the mouse" look.
    void setHeld(bool held);

    /// The chapter's marble blue, the colour of a marble without one.
    static QColor defaultColor();
    /// The selection's colour: the dashed ring around a selected marble or pin and the followed
    /// marble's long trail. Near-black, as no plotted line and no marble of the stage is (it was
    /// orange, which the plot's second line and its first, vermilion, looked like: a class could
    /// take the selected marble for the one plotted in orange).
    static QColor selectionColor();
    /// The ring of a marble held by the mouse (solid, where the selection's is dashed).
    static QColor heldColor();
    /// Paints a shaded ball of radius `r` centred on `centre` (painter coordinates) in `base`, with
    /// a `outlinePx`-wide dark rim; MarbleFieldItem renders its sprites with it, so both look alike.
    static void paintBall(QPainter *painter, QPointF centre, double r, const QColor &base, double outlinePx);

    int type() const override { return Type; }
    QRectF boundingRect() const override;
    void paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *widget) override;

private:
    double m_radius;
    QColor m_color;
    bool m_highlighted = false;
    bool m_held = false;
};

} // namespace marbles
