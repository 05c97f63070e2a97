#include "ui/trailitem.h"

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
            popOldest(trail);
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
    // Every trail holds the positions of the same frames, m_frames.
    const auto n = static_cast<std::size_t>(world.marbleCount());
    if (m_trails.size() != n) {
        m_trails.assign(n, {});
        m_frames.clear();
        m_movingSegments = 0;
    }
    // While every marble stands still, every segment is a point and nothing is drawn: the next
    // sample changes the picture only if some segment moves before or after it (a crowd at rest
    // is then not redrawn every frame for its trails).
    const bool stillBefore = m_movingSegments == 0;
    const bool full = static_cast<int>(m_frames.size()) >= m_length;
    if (full)
        m_frames.pop_front();
    m_frames.push_back(world.frame);
    for (std::size_t i = 0; i < n; ++i) {
        auto &trail = m_trails[i];
        if (full)
            popOldest(trail);
        const QPointF p(world.position[i].x, world.position[i].y);
        if (!trail.empty() && moves(trail.back(), p))
            ++m_movingSegments;
        trail.push_back(p);
    }
    if (!(stillBefore && m_movingSegments == 0))
        update();
}

void TrailItem::popOldest(std::deque<QPointF> &trail)
{
    if (trail.size() >= 2 && moves(trail[0], trail[1]))
        --m_movingSegments;
    trail.pop_front();
}

void TrailItem::cutAfter(std::int64_t frame)
{
    bool cut = false;
    while (!m_frames.empty() && m_frames.back() > frame) {
        m_frames.pop_back();
        for (auto &trail : m_trails) {
            const std::size_t k = trail.size();
            if (k >= 2 && moves(trail[k - 2], trail[k - 1]))
                --m_movingSegments;
            trail.pop_back();
        }
        cut = true;
    }
    if (cut)
        update();
}

void TrailItem::clear()
{
    m_trails.clear();
    m_frames.clear();
    m_movingSegments = 0;
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
    // Opacity grows linearly from the oldest segment (transparent) to the newest, in
    // kFadeSteps steps: the segments of all trails that share a step are drawn together, one
    // pen change and one drawLines() per step instead of per segment (thousands per frame).
    for (auto &lines : m_batches)
        lines.clear();
    m_batches.resize(kFadeSteps);
    for (const auto &trail : m_trails) {
        const auto count = trail.size();
        for (std::size_t k = 1; k < count; ++k) {
            if (!moves(trail[k - 1], trail[k]))
                continue; // a marble at rest: a point, nothing to draw
            const auto step = std::min<std::size_t>(kFadeSteps - 1, k * kFadeSteps / count);
            m_batches[step].emplace_back(trail[k - 1], trail[k]);
        }
    }
    painter->setRenderHint(QPainter::Antialiasing, m_antialiased);
    QPen pen(QColor(0x24, 0x63, 0xd1));
    pen.setCosmetic(true);
    pen.setWidthF(2.0);
    // Flat caps: a round cap turns each 2-px segment into a curved outline for the stroker,
    // about ten times the cost, and consecutive segments of a trail meet end to end anyway.
    pen.setCapStyle(Qt::FlatCap);
    for (int step = 0; step < kFadeSteps; ++step) {
        const auto &lines = m_batches[static_cast<std::size_t>(step)];
        if (lines.empty())
            continue;
        QColor c = pen.color();
        c.setAlphaF(0.6f * static_cast<float>(step + 1) / static_cast<float>(kFadeSteps));
        pen.setColor(c);
        painter->setPen(pen);
        painter->drawLines(lines.data(), static_cast<int>(lines.size()));
    }
}

} // namespace marbles
