#pragma once

#include "core/world.h"

#include <QGraphicsItem>
#include <QLineF>

#include <cstdint>
#include <deque>
#include <vector>

namespace marbles {

/// Fading trails behind every marble: the last positions of each, one per simulated frame,
/// drawn more transparent the older they are. One item for all marbles keeps the scene small.
/// One marble (the selected one) can be followed: its trail is kept far longer, and drawn in the
/// selection's colour, so that a slow wander (a heavy marble's Brownian motion) shows as a path.
class TrailItem : public QGraphicsItem {
public:
    enum { Type = UserType + 4 };

    /// Longest trail, frames.
    static constexpr int kMaxLength = 90;
    /// Longest trail of the followed marble, frames (a minute at the default 20 ms a frame).
    static constexpr int kFollowedLength = 3000;

    /// Trails of at most `length` frames (at least 2).
    explicit TrailItem(int length = kMaxLength);

    /// Longest trail kept, frames.
    int length() const { return m_length; }
    /// Keeps at most `frames` positions per marble (at least 2); longer trails are cut.
    void setLength(int frames);
    /// True when the segments are drawn antialiased.
    bool isAntialiased() const { return m_antialiased; }
    /// Draws the segments antialiased or hard (faster for thousands of segments).
    void setAntialiased(bool antialiased);

    /// Area the trails may cover (the stage), stage px.
    void setArea(const QRectF &area);
    /// Appends the marbles' current positions (of frame world.frame).
    void sample(const World &world);
    /// Forgets the positions of frames after `frame` (the timeline went back to it); the older
    /// part of every trail stays.
    void cutAfter(std::int64_t frame);
    /// Forgets every trail.
    void clear();
    /// The trail of marble i, oldest position first (empty when it has none).
    std::vector<QPointF> points(int i) const;
    /// Follows marble i (-1: none) from now on: its long trail starts from its trail so far.
    void setFollowed(int i);
    /// Keeps and draws the followed marble's trail alone (a crowd too large for every trail);
    /// switching drops the other trails.
    void setFollowedOnly(bool only);
    /// True when only the followed marble's trail is kept.
    bool followedOnly() const { return m_followedOnly; }
    /// The marble followed, or -1.
    int followed() const { return m_followed; }
    /// The followed marble's long trail, oldest position first.
    std::vector<QPointF> followedPoints() const { return {m_long.begin(), m_long.end()}; }

    int type() const override { return Type; }
    QRectF boundingRect() const override;
    void paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *widget) override;

private:
    /// Opacity levels of a trail's fade (segments are batched per level).
    static constexpr int kFadeSteps = 12;

    /// Forgets the followed marble's long trail (not which marble it is).
    void clearFollowed();
    /// Empties the fade levels' batches.
    void startBatches();
    /// Adds a trail's moving segments to the batch of each one's fade level.
    void addToBatches(const std::deque<QPointF> &trail);
    /// Draws the batches in `color`, `width` px wide, the levels' opacity rising in equal steps
    /// from `oldestAlpha` (exclusive) to `newestAlpha`.
    void drawBatches(QPainter *painter, const QColor &color, double width, double oldestAlpha, double newestAlpha);

    int m_length;
    bool m_antialiased = true;
    QRectF m_area;
    std::vector<std::deque<QPointF>> m_trails;
    std::deque<std::int64_t> m_frames; ///< frame of each position, shared by all trails
    std::size_t m_movingSegments = 0;  ///< segments whose ends differ, over all trails
    std::vector<std::vector<QLineF>> m_batches; ///< per fade level, kept between paints
    std::size_t m_sampledCount = 0; ///< marbles of the world sampled last
    bool m_followedOnly = false;
    int m_followed = -1;
    std::deque<QPointF> m_long;            ///< the followed marble's positions
    std::deque<std::int64_t> m_longFrames; ///< and their frames
    std::size_t m_longMoving = 0;          ///< segments of m_long whose ends differ
};

} // namespace marbles
