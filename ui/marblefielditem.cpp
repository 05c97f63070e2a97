#include "ui/marblefielditem.h"

#include "ui/marbleitem.h"
#include "ui/worldedit.h"

#include <QImage>
#include <QPainter>
#include <QStyleOptionGraphicsItem>

#include <algorithm>
#include <cmath>
#include <utility>

namespace marbles {

namespace {

/// Room around every marble in the bounding rectangle, stage px: the selection ring, and the
/// vectors (VectorItem's book length of 30 px past the rim, plus the arrow head).
constexpr double kVectorLengthPx = 30.0;
constexpr double kBoundsPaddingPx = kVectorLengthPx + 34.0;
/// Arrow heads, stage px (as VectorItem draws them), and the shortest drawn, device px.
constexpr double kArrowHeadPx = 8.0;
constexpr double kMinHeadDevicePx = 3.0;
/// The selection ring sits this far outside the ball: 3 stage px as MarbleItem, but never less
/// than 3 device px, so that it stays visible when a crowd is zoomed out to 1-px marbles.
constexpr double kRingGapPx = 3.0;

const QColor kVectorRed(0xe0, 0x00, 0x00);
const QColor kVectorBlue(0x00, 0x55, 0xff);
const QColor kVectorGreen(0x00, 0xb0, 0x20);

QRgb parseColor(const std::string &text)
{
    if (!text.empty()) {
        const QColor c(QString::fromStdString(text));
        if (c.isValid())
            return c.rgb();
    }
    return MarbleItem::defaultColor().rgb();
}

/// Stage px to device px: QTransform::map() inlined, for the tens of thousands of points of a
/// crowd per frame (the view's transform is affine: scale and translation).
struct ToDevice {
    explicit ToDevice(const QTransform &t)
        : m11(t.m11()), m12(t.m12()), m21(t.m21()), m22(t.m22()), dx(t.dx()), dy(t.dy())
    {
    }
    QPointF operator()(QPointF p) const { return {m11 * p.x() + m21 * p.y() + dx, m12 * p.x() + m22 * p.y() + dy}; }

    double m11, m12, m21, m22, dx, dy;
};

/// Appends the three corners of VectorItem's arrow head, a triangle with its tip at `tip`
/// pointing along the unit vector `u`, in device px.
void addHead(std::vector<QPointF> &corners, const ToDevice &toDevice, QPointF tip, QPointF u)
{
    const QPointF n(-u.y(), u.x());
    corners.push_back(toDevice(tip));
    corners.push_back(toDevice(tip - u * kArrowHeadPx + n * kArrowHeadPx * 0.5));
    corners.push_back(toDevice(tip - u * kArrowHeadPx - n * kArrowHeadPx * 0.5));
}

/// Fills the triangles of `corners` (three points each) in `color`. One small polygon at a time:
/// the raster engine fills thousands of tiny triangles far faster one by one than as one big
/// path, whose antialiased scan conversion walks every edge on every scan line.
void fillTriangles(QPainter *painter, const std::vector<QPointF> &corners, const QColor &color)
{
    painter->setPen(Qt::NoPen);
    painter->setBrush(color);
    for (std::size_t k = 0; k + 2 < corners.size(); k += 3)
        painter->drawPolygon(corners.data() + k, 3);
    painter->setBrush(Qt::NoBrush);
}

/// One marble as the field draws it: a shaded ball, or for a ghost a dashed, semi-transparent
/// outline with no fill. `centre` and `r` in painter coordinates (device px).
void paintMarbleShape(QPainter *painter, QPointF centre, double r, const QColor &base, bool ghost)
{
    if (!ghost) {
        MarbleItem::paintBall(painter, centre, r, base, 1.0);
        return;
    }
    // A pale halo under the dashes keeps a ghost readable where it lies over a solid marble of
    // the same colour (the usual case: the same marble in the other model, a few px away).
    painter->setRenderHint(QPainter::Antialiasing);
    painter->setBrush(Qt::NoBrush);
    QPen halo(QColor(255, 255, 255, 190));
    halo.setWidthF(3.0);
    painter->setPen(halo);
    painter->drawEllipse(centre, r, r);
    QColor line = base.darker(130);
    line.setAlpha(230);
    QPen pen(line);
    pen.setWidthF(1.5);
    pen.setDashPattern({3.0, 3.0});
    painter->setPen(pen);
    painter->drawEllipse(centre, r, r);
}

void drawLines(QPainter *painter, const std::vector<QLineF> &lines)
{
    painter->drawLines(lines.data(), static_cast<int>(lines.size()));
}

// Makes `kept` a copy of `now`; returns whether it was not one already.
template<typename T>
bool keepCopy(const std::vector<T> &now, std::vector<T> &kept)
{
    if (now == kept)
        return false;
    kept = now;
    return true;
}

} // namespace

MarbleFieldItem::MarbleFieldItem(const World *world, Style style)
    : m_world(world)
    , m_style(style)
{
    // exposedRect then holds the part of the item that is on screen, so off-screen marbles are skipped.
    setFlag(ItemUsesExtendedStyleOption);
    setCacheMode(NoCache);
    syncFromWorld();
}

MarbleFieldItem::~MarbleFieldItem() = default;

void MarbleFieldItem::setWorld(const World *world)
{
    m_world = world;
    m_colorText.clear();
    m_color.clear();
    syncFromWorld();
    update();
}

void MarbleFieldItem::syncFromWorld()
{
    QRectF bounds;
    m_maxRadius = 0.0;
    bool changed = false;
    if (m_world) {
        const World &w = *m_world;
        double left = 0.0;
        double top = 0.0;
        double right = w.stage.width;
        double bottom = w.stage.height;
        const int n = w.marbleCount();
        for (int i = 0; i < n; ++i) {
            const Vec2 p = w.position[static_cast<std::size_t>(i)];
            const double r = w.radius[static_cast<std::size_t>(i)];
            // A marble that left finite numbers is not drawn and must not stretch the bounds.
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(r))
                continue;
            left = std::min(left, p.x - r);
            top = std::min(top, p.y - r);
            right = std::max(right, p.x + r);
            bottom = std::max(bottom, p.y + r);
            m_maxRadius = std::max(m_maxRadius, r);
        }
        const double pad = m_maxRadius + kBoundsPaddingPx;
        bounds = QRectF(QPointF(left, top), QPointF(right, bottom)).adjusted(-pad, -pad, pad, pad);
        changed = syncColors();
        changed |= keepShown();
    }
    if (bounds != m_bounds) {
        prepareGeometryChange();
        m_bounds = bounds;
        changed = true;
    }
    if (changed)
        update();
}

bool MarbleFieldItem::keepShown()
{
    // What paint() reads of the world besides the colours. A crowd at rest, played, looks the
    // same frame after frame: without this check it was redrawn at the full frame rate for
    // nothing (2,000 marbles under Xvfb: 18 % of a core).
    const World &w = *m_world;
    bool changed = keepCopy(w.position, m_shownPosition);
    changed |= keepCopy(w.radius, m_shownRadius);
    if (m_vectorsVisible)
        changed |= keepCopy(w.lastHit, m_shownHits);
    return changed;
}

bool MarbleFieldItem::syncColors()
{
    const World &w = *m_world;
    const auto n = static_cast<std::size_t>(w.marbleCount());
    const std::size_t known = m_color.size();
    bool changed = n != known;
    m_colorText.resize(n);
    m_color.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (i < known && m_colorText[i] == w.info[i].color)
            continue;
        m_colorText[i] = w.info[i].color;
        m_color[i] = parseColor(m_colorText[i]);
        if (m_colorText[i].empty()) {
            for (const auto &[marble, rgb] : m_tints) {
                if (static_cast<std::size_t>(marble) == i)
                    m_color[i] = rgb;
            }
        }
        changed = true;
    }
    return changed;
}

void MarbleFieldItem::setTints(const QList<QPair<int, QColor>> &tints)
{
    std::vector<std::pair<int, QRgb>> next;
    for (const auto &[marble, colour] : tints)
        next.emplace_back(marble, colour.rgb());
    if (next == m_tints)
        return;
    // The marbles tinted before and now are parsed again (the others keep their colours): their
    // colour text is set to one no marble has.
    for (const auto *list : {&m_tints, &next}) {
        for (const auto &[marble, rgb] : *list) {
            if (static_cast<std::size_t>(marble) < m_colorText.size())
                m_colorText[static_cast<std::size_t>(marble)] = std::string(1, '\0');
        }
    }
    m_tints = std::move(next);
    if (m_world && syncColors())
        update();
}

void MarbleFieldItem::setStyle(Style style)
{
    if (style == m_style)
        return;
    m_style = style;
    update();
}

void MarbleFieldItem::setVectorsVisible(bool visible)
{
    if (visible == m_vectorsVisible)
        return;
    m_vectorsVisible = visible;
    if (visible && m_world)
        m_shownHits = m_world->lastHit;
    update();
}

void MarbleFieldItem::setSelectedMarbles(const QList<int> &indices)
{
    if (indices == m_selected)
        return;
    m_selected = indices;
    update();
}

void MarbleFieldItem::setHeldMarble(int i)
{
    if (i == m_held)
        return;
    m_held = i;
    update();
}

void MarbleFieldItem::setAntialiasThreshold(int marbles)
{
    if (marbles == m_antialiasThreshold)
        return;
    m_antialiasThreshold = marbles;
    update();
}

bool MarbleFieldItem::vectorsLegibleAt(double scale)
{
    return kVectorLengthPx * scale >= kMinVectorDevicePx;
}

bool MarbleFieldItem::isAntialiased() const
{
    return !m_world || m_world->marbleCount() <= m_antialiasThreshold;
}

int MarbleFieldItem::marbleAt(QPointF p) const
{
    return m_world ? marbles::marbleAt(*m_world, {p.x(), p.y()}) : -1;
}

QColor MarbleFieldItem::marbleColor(int i) const
{
    if (i >= 0 && i < static_cast<int>(m_color.size()))
        return QColor::fromRgb(m_color[static_cast<std::size_t>(i)]);
    if (m_world && i >= 0 && i < m_world->marbleCount())
        return QColor::fromRgb(parseColor(m_world->info[static_cast<std::size_t>(i)].color));
    return MarbleItem::defaultColor();
}

QRectF MarbleFieldItem::boundingRect() const
{
    return m_bounds;
}

const QPixmap &MarbleFieldItem::sprite(const SpriteKey &key)
{
    const auto found = m_sprites.constFind(key);
    if (found != m_sprites.cend())
        return *found;
    if (m_sprites.size() >= kMaxCachedSprites || m_spriteBytes > kMaxSpriteCacheBytes) {
        m_sprites.clear();
        m_spriteBytes = 0;
    }

    const double dpr = key.dprPercent / 100.0;
    const double r = key.radiusSteps * kSpriteRadiusStepDevicePx;
    // Two device px of room on each side for the rim (a 1-px pen straddles the radius) and
    // antialiasing; an even side puts the centre on a pixel corner, as rounded positions expect.
    int side = static_cast<int>(std::ceil((2.0 * r + 4.0) * dpr));
    side += side % 2;
    QImage image(side, side, QImage::Format_ARGB32_Premultiplied);
    image.setDevicePixelRatio(dpr);
    image.fill(Qt::transparent);
    QPainter painter(&image);
    const double centre = side / (2.0 * dpr);
    paintMarbleShape(&painter, QPointF(centre, centre), r, QColor::fromRgb(key.color), key.ghost);
    painter.end();
    m_spriteBytes += image.sizeInBytes();
    return *m_sprites.insert(key, QPixmap::fromImage(std::move(image)));
}

void MarbleFieldItem::paint(QPainter *painter, const QStyleOptionGraphicsItem *option, QWidget *)
{
    if (!m_world)
        return;
    const World &w = *m_world;
    const int n = std::min(w.marbleCount(), static_cast<int>(m_color.size()));
    const QTransform toDevice = painter->worldTransform();
    // The view never rotates or shears, so one number converts stage px to device px.
    const double scale = std::sqrt(std::abs(toDevice.determinant()));
    if (n == 0 || !(scale > 0.0))
        return;
    const QRectF visible = option && !option->exposedRect.isEmpty() ? option->exposedRect : m_bounds;
    const double dpr = painter->device() ? painter->device()->devicePixelRatio() : 1.0;
    const bool antialias = isAntialiased();
    const bool ghost = m_style == Style::Ghost;
    const double squareBelow = antialias ? kSmallestSpriteRadiusDevicePx : kTinyRadiusDevicePx;

    painter->save();
    // Everything below is placed in device px: sprites are blitted unscaled, lines are hairlines.
    painter->setWorldTransform(QTransform());
    painter->setRenderHint(QPainter::Antialiasing, antialias);
    painter->setRenderHint(QPainter::SmoothPixmapTransform, false);

    // Marbles too small for a sprite, batched per colour (a scene rarely has more than a few).
    // The buffers keep their capacity from frame to frame.
    for (auto &bucket : m_tiny)
        bucket.second.clear();
    const ToDevice map(toDevice);
    SpriteKey key;
    key.dprPercent = static_cast<int>(std::lround(dpr * 100.0));
    key.ghost = ghost;
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Vec2 p = w.position[k];
        const double r = w.radius[k];
        if (!(p.x + r >= visible.left() && p.x - r <= visible.right() && p.y + r >= visible.top()
              && p.y - r <= visible.bottom()))
            continue; // off screen, or not finite
        const QPointF c = map(QPointF(p.x, p.y));
        const double rDevice = r * scale;
        if (rDevice < squareBelow) {
            // Whole pixels, so that every tiny marble is a crisp square of the same size as its
            // neighbours of the same radius, not a 1x2 or 2x1 sliver of a rounded fractional rectangle.
            const double side = std::max(1.0, std::round(2.0 * rDevice));
            auto bucket = std::find_if(m_tiny.begin(), m_tiny.end(), [&](const auto &b) { return b.first == m_color[k]; });
            if (bucket == m_tiny.end()) {
                m_tiny.emplace_back(m_color[k], std::vector<QRectF>());
                bucket = std::prev(m_tiny.end());
            }
            bucket->second.emplace_back(std::round(c.x() - side / 2), std::round(c.y() - side / 2), side, side);
            continue;
        }
        if (rDevice > kMaxSpriteRadiusDevicePx) {
            // Zoomed far in: few marbles are on screen, each would need a large sprite of its own.
            painter->save();
            paintMarbleShape(painter, c, rDevice, QColor::fromRgb(m_color[k]), ghost);
            painter->restore();
            continue;
        }
        key.radiusSteps = static_cast<int>(std::lround(rDevice / kSpriteRadiusStepDevicePx));
        key.color = m_color[k];
        const QPixmap &pixmap = sprite(key);
        const double half = pixmap.width() / (2.0 * dpr);
        painter->drawPixmap(QPointF(std::round(c.x() - half), std::round(c.y() - half)), pixmap);
    }
    for (const auto &[rgb, rects] : m_tiny) {
        if (rects.empty())
            continue;
        QColor color = QColor::fromRgb(rgb);
        if (ghost) {
            color.setAlpha(200);
            QPen pen(color);
            pen.setCosmetic(true);
            painter->setPen(pen);
            painter->setBrush(Qt::NoBrush);
        } else {
            painter->setPen(Qt::NoPen);
            painter->setBrush(color);
        }
        painter->drawRects(rects.data(), static_cast<int>(rects.size()));
    }

    if (m_vectorsVisible && vectorsLegibleAt(scale))
        paintVectors(painter, toDevice, scale, visible, antialias);
    paintRings(painter, toDevice, scale);
    painter->restore();
}

void MarbleFieldItem::paintVectors(QPainter *painter, const QTransform &toDevice, double scale, const QRectF &visible,
                                   bool antialias)
{
    const World &w = *m_world;
    const int n = std::min(w.marbleCount(), static_cast<int>(w.lastHit.size()));
    // Zoomed out, VectorItem's 4-px and 2-px pens would be thicker than the marbles themselves
    // and bury the stage: the widths shrink with the zoom, down to 1 px (which the raster engine
    // also draws far faster than thick lines), in whole pixels: a 1.2-px pen looks like a 1-px
    // one but goes through the stroker (2,000 marbles fitted to the window: paint 3.65 -> 2.98
    // ms). Heads shorter than kMinHeadDevicePx would be a blot, not an arrow: they are left out,
    // the colours still tell the vectors apart.
    const double widthScale = std::clamp(scale, 0.25, 1.0);
    const bool heads = kArrowHeadPx * scale >= kMinHeadDevicePx;
    // Buffers kept from frame to frame: no allocation (and no fresh pages to fault in) per frame.
    std::vector<QLineF> &red = m_redLines;
    std::vector<QLineF> &blue = m_blueLines;
    std::vector<QLineF> &green = m_greenLines;
    std::vector<QPointF> &blueHeads = m_blueHeads;
    std::vector<QPointF> &greenHeads = m_greenHeads;
    red.clear();
    blue.clear();
    green.clear();
    blueHeads.clear();
    greenHeads.clear();
    const ToDevice map(toDevice);
    const double reach = m_maxRadius + kVectorLengthPx + kArrowHeadPx;
    const QRectF near = visible.adjusted(-reach, -reach, reach, reach);
    for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const HitRecord &hit = w.lastHit[k];
        const QPointF c(w.position[k].x, w.position[k].y);
        if (hit.frame < 0 || !near.contains(c))
            continue;
        // As VectorItem: the book's unit vectors drawn 30 px long past the marble's rim.
        const double l = w.radius[k] + kVectorLengthPx;
        const QPointF normal(hit.normal.x, hit.normal.y);
        const QPointF in(hit.velocityIn.x, hit.velocityIn.y);
        const QPointF out(hit.velocityOut.x, hit.velocityOut.y);
        const QPointF centre = map(c);
        red.emplace_back(map(c - normal * l), map(c + normal * l));
        blue.emplace_back(centre, map(c + in * l));
        green.emplace_back(centre, map(c + out * l));
        if (heads) {
            addHead(blueHeads, map, c + in * l, in);
            addHead(greenHeads, map, c + out * l, out);
        }
    }
    if (red.empty())
        return;
    painter->setRenderHint(QPainter::Antialiasing, antialias && red.size() <= static_cast<std::size_t>(kMaxSmoothVectors));
    painter->setBrush(Qt::NoBrush);

    QPen pen(kVectorRed);
    pen.setCosmetic(true);
    pen.setWidthF(1.0);
    painter->setPen(pen);
    drawLines(painter, red);

    pen.setColor(kVectorBlue);
    pen.setWidthF(std::max(1.0, std::round(4.0 * widthScale)));
    pen.setCapStyle(Qt::FlatCap);
    painter->setPen(pen);
    drawLines(painter, blue);
    fillTriangles(painter, blueHeads, kVectorBlue);

    pen.setColor(kVectorGreen);
    pen.setWidthF(std::max(1.0, std::round(2.0 * widthScale)));
    painter->setPen(pen);
    drawLines(painter, green);
    fillTriangles(painter, greenHeads, kVectorGreen);
}

void MarbleFieldItem::paintRings(QPainter *painter, const QTransform &toDevice, double scale)
{
    const World &w = *m_world;
    const auto ring = [&](int i, const QColor &color, Qt::PenStyle style) {
        if (i < 0 || i >= w.marbleCount())
            return;
        const auto k = static_cast<std::size_t>(i);
        const double rDevice = w.radius[k] * scale;
        const double ringDevice = std::max((w.radius[k] + kRingGapPx) * scale, rDevice + kRingGapPx);
        QPen pen(color);
        pen.setWidthF(2.0);
        pen.setCosmetic(true);
        pen.setStyle(style);
        painter->setPen(pen);
        painter->setBrush(Qt::NoBrush);
        painter->drawEllipse(toDevice.map(QPointF(w.position[k].x, w.position[k].y)), ringDevice, ringDevice);
    };
    if (m_selected.isEmpty() && m_held < 0)
        return;
    // Few rings: always smooth, whatever the marble count.
    painter->setRenderHint(QPainter::Antialiasing, true);
    for (int i : m_selected) {
        if (i != m_held)
            ring(i, MarbleItem::selectionColor(), Qt::DashLine);
    }
    ring(m_held, MarbleItem::heldColor(), Qt::SolidLine);
}

} // namespace marbles
