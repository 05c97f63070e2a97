#include "ui/trailitem.h"

#include "ui/marbleitem.h"

#include <QPainter>

#include <algorithm>

namespace marbles {

namespace {

// A segment that draws something: its ends differ (exactly, so that counting a segment in and
// out always agrees).
bool moves(QPointF a, QPointF b)
{
    return a.x() != b.x() || a.y() != b.y();
}

// Drop a trail's oldest or newest position, keeping the count of its moving segments.
void dropOldest(std::deque<QPointF> &trail, std::size_t &moving)
{
    if (trail.size() >= 2 && moves(trail[0], trail[1]))
        --moving;
    trail.pop_front();
}

void dropNewest(std::deque<QPointF> &trail, std::size_t &moving)
{
    const std::size_t k = trail.size();
    if (k >= 2 && moves(trail[k - 2], trail[k - 1]))
        --moving;
    trail.pop_back();
}

// Appends p to a trail, counting the segment it adds if it moves.
void append(std::deque<QPointF> &trail, QPointF p, std::size_t &moving)
{
    if (!trail.empty() && moves(trail.back(), p))
        ++moving;
    trail.push_back(p);
}

} // namespace

TrailItem::TrailItem(int length)
    : m_length(length > 1 ? length : 2)
{
}

void TrailItem::setLength(int frames)
{
    m_length = frames > 1 ? frames : 2;
    while (static_cast<int>(m_frames.size()) > m_length) {
        m_frames.pop_front();
        for (auto &trail : m_trails)
            dropOldest(trail, m_movingSegments);
    }
    update();
}

void TrailItem::setAntialiased(bool antialiased)
{
    if (antialiased == m_antialiased)
        return;
    m_antialiased = antialiased;
    update();
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
    // Every trail holds the positions of the same frames, m_frames (none but the followed one's
    // when it is followed alone).
    const auto n = static_cast<std::size_t>(world.marbleCount());
    if (n != m_sampledCount || m_trails.size() != (m_followedOnly ? 0 : n)) {
        m_sampledCount = n;
        m_trails.assign(m_followedOnly ? 0 : n, {});
        m_frames.clear();
        m_movingSegments = 0;
        clearFollowed();
    }
    // While every marble stands still, every segment is a point and nothing is drawn: the next
    // sample changes the picture only if some segment moves before or after it (a crowd at rest
    // is then not redrawn every frame for its trails).
    const bool stillBefore = m_movingSegments == 0 && m_longMoving == 0;
    const bool full = static_cast<int>(m_frames.size()) >= m_length;
    if (full)
        m_frames.pop_front();
    if (!m_followedOnly)
        m_frames.push_back(world.frame);
    for (std::size_t i = 0; i < m_trails.size(); ++i) {
        auto &trail = m_trails[i];
        if (full)
            dropOldest(trail, m_movingSegments);
        append(trail, QPointF(world.position[i].x, world.position[i].y), m_movingSegments);
    }
    if (m_followed >= 0 && static_cast<std::size_t>(m_followed) < n) {
        if (m_long.size() >= static_cast<std::size_t>(kFollowedLength)) {
            dropOldest(m_long, m_longMoving);
            m_longFrames.pop_front();
        }
        const Vec2 p = world.position[static_cast<std::size_t>(m_followed)];
        append(m_long, QPointF(p.x, p.y), m_longMoving);
        m_longFrames.push_back(world.frame);
    }
    if (!(stillBefore && m_movingSegments == 0 && m_longMoving == 0))
        update();
}

void TrailItem::cutAfter(std::int64_t frame)
{
    bool cut = false;
    while (!m_frames.empty() && m_frames.back() > frame) {
        m_frames.pop_back();
        for (auto &trail : m_trails)
            dropNewest(trail, m_movingSegments);
        cut = true;
    }
    while (!m_longFrames.empty() && m_longFrames.back() > frame) {
        m_longFrames.pop_back();
        dropNewest(m_long, m_longMoving);
        cut = true;
    }
    if (cut)
        update();
}

void TrailItem::setFollowed(int i)
{
    if (i == m_followed)
        return;
    clearFollowed();
    m_followed = i < 0 ? -1 : i;
    if (m_followed >= 0 && static_cast<std::size_t>(m_followed) < m_trails.size()) {
        for (const QPointF &p : m_trails[static_cast<std::size_t>(m_followed)])
            append(m_long, p, m_longMoving);
        m_longFrames.assign(m_frames.begin(), m_frames.end());
    }
    update();
}

void TrailItem::setFollowedOnly(bool only)
{
    if (only == m_followedOnly)
        return;
    m_followedOnly = only;
    m_trails.clear();
    m_frames.clear();
    m_movingSegments = 0;
    update();
}

void TrailItem::clearFollowed()
{
    m_long.clear();
    m_longFrames.clear();
    m_longMoving = 0;
}

void TrailItem::clear()
{
    m_trails.clear();
    m_frames.clear();
    m_movingSegments = 0;
    clearFollowed();
    update();
}

std::vector<QPointF> TrailItem::points(int i) const
{
    if (i < 0 || static_cast<std::size_t>(i) >= m_trails.size())
        return {};
    const auto &trail = m_trails[static_cast<std::size_t>(i)];
    return {trail.begin(), trail.end()};
}

QRectF TrailItem::boundingRect() const
{
    return m_area.adjusted(-200, -200, 200, 200);
}

void TrailItem::paint(QPainter *painter, const QStyleOptionGraphicsItem *, QWidget *)
{
    painter->setRenderHint(QPainter::Antialiasing, m_antialiased);
    startBatches();
    for (const auto &trail : m_trails)
        addToBatches(trail);
    drawBatches(painter, MarbleItem::defaultColor(), 2.5, 0.1, 0.85);
    if (m_long.size() >= 2) {
        // One trail over the others, smooth whatever the crowd, wider, and its oldest part still
        // plain to see: the whole path is the point.
        painter->setRenderHint(QPainter::Antialiasing, true);
        startBatches();
        addToBatches(m_long);
        drawBatches(painter, MarbleItem::selectionColor(), 3.0, 0.5, 1.0);
    }
}

void TrailItem::startBatches()
{
    for (auto &lines : m_batches)
        lines.clear();
    m_batches.resize(kFadeSteps);
}

void TrailItem::addToBatches(const std::deque<QPointF> &trail)
{
    // Opacity grows linearly from the oldest segment (transparent) to the newest, in
    // kFadeSteps steps: the segments of all trails that share a step are drawn together, one
    // pen change and one drawLines() per step instead of per segment (thousands per frame).
    const auto count = trail.size();
    for (std::size_t k = 1; k < count; ++k) {
        if (!moves(trail[k - 1], trail[k]))
            continue; // a marble at rest: a point, nothing to draw
        const auto step = std::min<std::size_t>(kFadeSteps - 1, k * kFadeSteps / count);
        m_batches[step].emplace_back(trail[k - 1], trail[k]);
    }
}

void TrailItem::drawBatches(QPainter *painter, const QColor &color, double width, double oldestAlpha,
                            double newestAlpha)
{
    QPen pen(color);
    pen.setCosmetic(true);
    pen.setWidthF(width);
    // Flat caps: a round cap turns each 2-px segment into a curved outline for the stroker,
    // about ten times the cost, and consecutive segments of a trail meet end to end anyway.
    pen.setCapStyle(Qt::FlatCap);
    for (int step = 0; step < kFadeSteps; ++step) {
        const auto &lines = m_batches[static_cast<std::size_t>(step)];
        if (lines.empty())
            continue;
        QColor c = color;
        c.setAlphaF(static_cast<float>(oldestAlpha + (newestAlpha - oldestAlpha) * (step + 1) / kFadeSteps));
        pen.setColor(c);
        painter->setPen(pen);
        painter->drawLines(lines.data(), static_cast<int>(lines.size()));
    }
}

} // namespace marbles
