// MarbleFieldItem: one item draws every marble of a world (shaded sprites, tiny squares when
// zoomed far out, ghost outlines), the Figure 11.12 vectors batched, selection rings, and finds
// the marble under a point by searching the world.

#include "core/world.h"
#include "ui/marblefielditem.h"
#include "ui/marbleitem.h"

#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QTest>

#include <cmath>

using namespace marbles;

namespace {

const QColor kBackground(0xfb, 0xfa, 0xf6);

/// Renders `item` (in a scene of its own) into an image: stage px times `scale` = image px.
QImage render(MarbleFieldItem *item, QSize size, double scale)
{
    QGraphicsScene scene;
    scene.addItem(item);
    QImage image(size, QImage::Format_ARGB32_Premultiplied);
    image.fill(kBackground);
    QPainter painter(&image);
    scene.render(&painter, QRectF(QPointF(0, 0), QSizeF(size)), QRectF(0, 0, size.width() / scale, size.height() / scale),
                 Qt::IgnoreAspectRatio);
    painter.end();
    scene.removeItem(item);
    return image;
}

/// Hue distance in degrees, on the colour circle.
int hueDistance(const QColor &a, const QColor &b)
{
    const int d = std::abs(a.hsvHue() - b.hsvHue()) % 360;
    return std::min(d, 360 - d);
}

QPoint imagePoint(Vec2 p, double scale)
{
    return QPoint(static_cast<int>(std::floor(p.x * scale)), static_cast<int>(std::floor(p.y * scale)));
}

/// The fraction of the pixels of `image` within the annulus [r0, r1] about `c` (image px) for
/// which `counts(colour)` holds.
template <typename Predicate>
double annulusFraction(const QImage &image, QPointF c, double r0, double r1, Predicate counts)
{
    int inside = 0;
    int hits = 0;
    for (int y = static_cast<int>(c.y() - r1) - 1; y <= static_cast<int>(c.y() + r1) + 1; ++y) {
        for (int x = static_cast<int>(c.x() - r1) - 1; x <= static_cast<int>(c.x() + r1) + 1; ++x) {
            const double d = std::hypot(x + 0.5 - c.x(), y + 0.5 - c.y());
            if (d < r0 || d > r1 || !image.rect().contains(x, y))
                continue;
            ++inside;
            hits += counts(image.pixelColor(x, y)) ? 1 : 0;
        }
    }
    return inside > 0 ? static_cast<double>(hits) / inside : 0.0;
}

/// The pixels of `image` within 4 px (a 9 x 9 square) of stage point `p` drawn at `scale` for
/// which `counts(colour)` holds.
template <typename Predicate>
int pixelsAround(const QImage &image, Vec2 p, double scale, Predicate counts)
{
    const QPoint c = imagePoint(p, scale);
    int n = 0;
    for (int y = c.y() - 4; y <= c.y() + 4; ++y) {
        for (int x = c.x() - 4; x <= c.x() + 4; ++x)
            n += counts(image.pixelColor(x, y)) ? 1 : 0;
    }
    return n;
}

/// Pixels within the annulus that differ from the background.
double changedFraction(const QImage &image, QPointF c, double r0, double r1)
{
    return annulusFraction(image, c, r0, r1, [](const QColor &colour) { return colour != kBackground; });
}

/// Pixels within the annulus that are dark (HSL lightness below 180 of 255): the ink of a
/// line, not the background or a pale halo.
double darkFraction(const QImage &image, QPointF c, double r0, double r1)
{
    return annulusFraction(image, c, r0, r1, [](const QColor &colour) { return colour.lightness() < 180; });
}

World twoMarbles()
{
    World w;
    w.stage = {400, 200, true};
    w.addMarble({100, 100}, 30);
    w.addMarble({300, 100}, 20);
    w.info[1].color = "#e53935";
    return w;
}

} // namespace

class TestMarbleFieldItem : public QObject {
    Q_OBJECT

private Q_SLOTS:
    void drawsMarblesOverTheBackground_data();
    void drawsMarblesOverTheBackground();
    void ghostDrawsOutlinesNotFills();
    void vectorsFollowLastHit();
    void vectorsOnlyWhenLegible_data();
    void vectorsOnlyWhenLegible();
    void manyVectorsAreSharp_data();
    void manyVectorsAreSharp();
    void tinyMarblesAreWholePixelSquares();
    void smallMarblesAreRoundInSmallCrowds();
    void selectionAndHeldRings();
    void boundsCoverMarblesOffTheStage();
    void spritesAreSharedBetweenMarbles();
    void marbleAtSearchesTheWorld_data();
    void marbleAtSearchesTheWorld();
    void antialiasingStopsAboveTheThreshold();
    void setWorldResyncs();
};

void TestMarbleFieldItem::drawsMarblesOverTheBackground_data()
{
    QTest::addColumn<double>("scale"); // image px per stage px
    QTest::addRow("sprites, 1:1") << 1.0;
    QTest::addRow("sprites, zoomed in") << 2.0;
    QTest::addRow("sprites, zoomed out") << 0.3;
    QTest::addRow("tiny squares") << 0.05;
}

void TestMarbleFieldItem::drawsMarblesOverTheBackground()
{
    QFETCH(double, scale);
    const World w = twoMarbles();
    auto *item = new MarbleFieldItem(&w);
    const QSize size(static_cast<int>(std::ceil(400 * scale)), static_cast<int>(std::ceil(200 * scale)));
    const QImage image = render(item, size, scale);
    for (int i = 0; i < w.marbleCount(); ++i) {
        const QColor expected = item->marbleColor(i);
        const QColor seen = image.pixelColor(imagePoint(w.position[i], scale));
        // The centre of a shaded ball is between the base colour and its highlight: same hue.
        QVERIFY2(seen != kBackground, qPrintable(QStringLiteral("marble %1 not drawn").arg(i)));
        QCOMPARE_LE(hueDistance(seen, expected), 12);
        QCOMPARE_GE(seen.hsvSaturation(), 100);
    }
    QCOMPARE(item->marbleColor(0), MarbleItem::defaultColor());
    QCOMPARE(item->marbleColor(1), QColor(0xe5, 0x39, 0x35));
    // Between and beside the marbles: the background.
    for (Vec2 p : {Vec2{200, 100}, Vec2{100, 30}, Vec2{300, 150}, Vec2{20, 20}})
        QCOMPARE(image.pixelColor(imagePoint(p, scale)), kBackground);
    delete item;
}

void TestMarbleFieldItem::ghostDrawsOutlinesNotFills()
{
    const World w = twoMarbles();
    auto *item = new MarbleFieldItem(&w, MarbleFieldItem::Style::Ghost);
    QCOMPARE(item->style(), MarbleFieldItem::Style::Ghost);
    const QImage ghost = render(item, QSize(400, 200), 1.0);
    for (int i = 0; i < w.marbleCount(); ++i) {
        const QPointF c(w.position[i].x, w.position[i].y);
        const double r = w.radius[i];
        // Nothing inside the disc; on its rim a pale halo under dark dashes (the dashes cover
        // well over a third of the rim, and the gaps between them stay light).
        QCOMPARE(changedFraction(ghost, c, 0.0, r - 2.5), 0.0);
        QCOMPARE_GE(darkFraction(ghost, c, r - 1.0, r + 1.0), 0.35);
        QCOMPARE_LE(darkFraction(ghost, c, r - 1.0, r + 1.0), 0.9);
    }
    item->setStyle(MarbleFieldItem::Style::Solid);
    const QImage solid = render(item, QSize(400, 200), 1.0);
    QCOMPARE(changedFraction(solid, QPointF(100, 100), 0.0, 27.5), 1.0);
    delete item;
}

void TestMarbleFieldItem::vectorsFollowLastHit()
{
    World w = twoMarbles();
    w.lastHit[0] = HitRecord::of(5, {1, 0}, {0, 1}, {-1, 0});
    auto *item = new MarbleFieldItem(&w);
    const auto colourAt = [&](Vec2 p) { return render(item, QSize(400, 200), 1.0).pixelColor(imagePoint(p, 1.0)); };
    // Marble 0 (radius 30 at (100, 100)): the vectors reach 30 px past its rim, 60 px from the centre.
    const Vec2 alongIn{145, 100};
    const Vec2 alongOut{55, 100};
    const Vec2 alongNormal{100, 145};
    QVERIFY(!item->vectorsVisible());
    QCOMPARE(colourAt(alongIn), kBackground);
    item->setVectorsVisible(true);
    QCOMPARE_LE(hueDistance(colourAt(alongIn), QColor(0x00, 0x55, 0xff)), 5);
    QCOMPARE_LE(hueDistance(colourAt(alongOut), QColor(0x00, 0xb0, 0x20)), 5);
    QCOMPARE_LE(hueDistance(colourAt(alongNormal), QColor(0xe0, 0x00, 0x00)), 5);
    // Marble 1 was never hit: nothing around it.
    QCOMPARE(colourAt({345, 100}), kBackground);
    delete item;
}

void TestMarbleFieldItem::vectorsOnlyWhenLegible_data()
{
    QTest::addColumn<double>("scale");
    QTest::addColumn<bool>("drawn");
    // The book's 30 px come to 4.5 device px at 0.15 and 7.5 at 0.25 (the limit is 6).
    QTest::addRow("too small") << 0.15 << false;
    QTest::addRow("legible") << 0.25 << true;
}

void TestMarbleFieldItem::vectorsOnlyWhenLegible()
{
    QFETCH(double, scale);
    QFETCH(bool, drawn);
    QCOMPARE(MarbleFieldItem::vectorsLegibleAt(scale), drawn);
    World w = twoMarbles();
    w.lastHit[0] = HitRecord::of(1, {1, 0}, {0, 1}, {0, -1});
    auto *item = new MarbleFieldItem(&w);
    item->setVectorsVisible(true);
    const QSize size(static_cast<int>(400 * scale), static_cast<int>(200 * scale));
    const QImage image = render(item, size, scale);
    // Just past the rim of marble 0 (radius 30) along the blue vector: 37 stage px from its centre.
    const QColor seen = image.pixelColor(imagePoint({137, 100}, scale));
    if (drawn)
        QCOMPARE_LE(hueDistance(seen, QColor(0x00, 0x55, 0xff)), 5);
    else
        QCOMPARE(seen, kBackground);
    delete item;
}

void TestMarbleFieldItem::manyVectorsAreSharp_data()
{
    QTest::addColumn<int>("side");
    QTest::addColumn<bool>("smooth");
    // side x side marbles, each with its vectors on screen.
    QTest::addRow("few: smooth") << 8 << true;
    QTest::addRow("crowd: sharp") << 32 << false;
}

void TestMarbleFieldItem::manyVectorsAreSharp()
{
    // Up to kMaxSmoothVectors marbles' vectors are antialiased: a slanted red line has pixels
    // part red, part background. Past it they are drawn with sharp pixels: pure red or untouched.
    QFETCH(int, side);
    QFETCH(bool, smooth);
    QCOMPARE_EQ(side * side <= MarbleFieldItem::kMaxSmoothVectors, smooth);
    World w;
    w.stage = {3200, 3200, true};
    // Blue to the left, red down and to the right (and up and to the left), green up.
    const HitRecord hit = HitRecord::of(1, {-1.0, 0.0}, {0.6, 0.8}, {0.0, -1.0});
    for (int row = 0; row < side; ++row) {
        for (int col = 0; col < side; ++col) {
            w.addMarble({50.0 + 100.0 * col, 50.0 + 100.0 * row}, 1.0);
            w.lastHit.back() = hit;
        }
    }
    auto *item = new MarbleFieldItem(&w);
    item->setVectorsVisible(true);
    QVERIFY(item->isAntialiased());
    const double scale = 0.25; // vectors 31 stage px = 7.75 device px: legible, no heads
    const QImage image = render(item, QSize(800, 800), scale);
    // The red line's lower-right half of each marble, where no other vector goes: 2 to 7 px out.
    int red = 0;
    int blended = 0;
    for (int k = 0; k < side * side; ++k) {
        const QPointF c(w.position[static_cast<std::size_t>(k)].x * scale, w.position[static_cast<std::size_t>(k)].y * scale);
        for (int y = static_cast<int>(c.y()) + 2; y <= static_cast<int>(c.y()) + 7; ++y) {
            for (int x = static_cast<int>(c.x()) + 1; x <= static_cast<int>(c.x()) + 6; ++x) {
                const QColor colour = image.pixelColor(x, y);
                if (colour == kBackground)
                    continue;
                if (colour == QColor(0xe0, 0x00, 0x00))
                    ++red;
                else
                    ++blended;
            }
        }
    }
    QCOMPARE_GT(red + blended, 3 * side * side);
    if (smooth)
        QCOMPARE_GT(blended, side * side);
    else
        QCOMPARE(blended, 0);
    delete item;
}

void TestMarbleFieldItem::tinyMarblesAreWholePixelSquares()
{
    // Above the antialias threshold (a large crowd): tiny marbles are squares.
    World w;
    w.stage = {1000, 1000, true};
    w.addMarble({333.3, 517.7}, 30); // 1.5 device px at 0.05: a 3 x 3 square
    w.addMarble({666.6, 250.1}, 20); // 1.0 device px: 2 x 2
    w.addMarble({500.0, 800.0}, 4);  // 0.2 device px: still one pixel
    auto *item = new MarbleFieldItem(&w);
    item->setAntialiasThreshold(2);
    QVERIFY(!item->isAntialiased());
    const QImage image = render(item, QSize(50, 50), 0.05);
    const auto flat = [](const QColor &c) { return c == MarbleItem::defaultColor(); };
    QCOMPARE(pixelsAround(image, w.position[0], 0.05, flat), 9);
    QCOMPARE(pixelsAround(image, w.position[1], 0.05, flat), 4);
    QCOMPARE(pixelsAround(image, w.position[2], 0.05, flat), 1);
    delete item;
}

void TestMarbleFieldItem::smallMarblesAreRoundInSmallCrowds()
{
    // Up to the antialias threshold, marbles of 0.75 device px and more are sprites like the big
    // ones (shaded, with a dark rim), not flat squares; smaller ones are single pixels.
    World w;
    w.stage = {1000, 1000, true};
    w.addMarble({333.3, 517.7}, 30); // 1.5 device px at 0.05
    w.addMarble({666.6, 250.1}, 20); // 1.0 device px
    w.addMarble({500.0, 800.0}, 10); // 0.5 device px: a square of one pixel
    auto *item = new MarbleFieldItem(&w);
    QVERIFY(item->isAntialiased());
    const QImage image = render(item, QSize(50, 50), 0.05);
    const auto flat = [](const QColor &c) { return c == MarbleItem::defaultColor(); };
    const auto dark = [](const QColor &c) { return c.lightness() < MarbleItem::defaultColor().lightness() - 20; };
    for (int i = 0; i < 2; ++i) {
        const Vec2 p = w.position[static_cast<std::size_t>(i)];
        QCOMPARE_LE(pixelsAround(image, p, 0.05, flat), 1);  // not a flat square of the base colour
        QCOMPARE_GE(pixelsAround(image, p, 0.05, dark), 2);  // the rim of a ball
    }
    QCOMPARE(pixelsAround(image, w.position[2], 0.05, flat), 1);
    QCOMPARE(item->cachedSpriteCount(), 2);
    delete item;
}

void TestMarbleFieldItem::selectionAndHeldRings()
{
    const World w = twoMarbles();
    auto *item = new MarbleFieldItem(&w);
    // MarbleItem's rings: 3 px outside the ball, 2 px wide; dashed in the selection's colour (selected),
    // solid green (held).
    const auto ringFraction = [&] { return changedFraction(render(item, QSize(400, 200), 1.0), QPointF(300, 100), 22.0, 24.0); };
    QCOMPARE(ringFraction(), 0.0);
    item->setSelectedMarbles({1, 7});
    QCOMPARE(item->selectedMarbles(), QList<int>({1, 7}));
    const double dashed = ringFraction();
    QCOMPARE_GE(dashed, 0.3);
    // Near-black, like no plotted line (it was orange, like the plot's second line).
    const QImage selected = render(item, QSize(400, 200), 1.0);
    QCOMPARE_GE(annulusFraction(selected, QPointF(300, 100), 22.0, 24.0, [](QColor c) { return c.value() < 110; }), 0.25);
    item->setSelectedMarbles({});
    item->setHeldMarble(1);
    QCOMPARE(item->heldMarble(), 1);
    const QImage held = render(item, QSize(400, 200), 1.0);
    QCOMPARE_GE(changedFraction(held, QPointF(300, 100), 22.0, 24.0), 0.9);
    QCOMPARE_LE(hueDistance(held.pixelColor(323, 100), QColor(0x2e, 0x7d, 0x32)), 10);
    delete item;
}

void TestMarbleFieldItem::boundsCoverMarblesOffTheStage()
{
    World w = twoMarbles();
    w.stage.walls = false;
    w.position[1] = {900, -300};
    MarbleFieldItem item(&w);
    QVERIFY(item.boundingRect().contains(QRectF(0, 0, 400, 200)));
    QVERIFY(item.boundingRect().contains(QRectF(880, -320, 40, 40)));
    w.position[1] = {300, 100};
    item.syncFromWorld();
    QVERIFY(!item.boundingRect().contains(QPointF(900, -300)));
}

void TestMarbleFieldItem::spritesAreSharedBetweenMarbles()
{
    World w;
    w.stage = {400, 400, true};
    for (int k = 0; k < 100; ++k)
        w.addMarble({20.0 + 40.0 * (k % 10), 20.0 + 40.0 * (k / 10)}, 10);
    w.info[0].color = "#e53935";
    auto *item = new MarbleFieldItem(&w);
    render(item, QSize(400, 400), 1.0);
    QCOMPARE(item->cachedSpriteCount(), 2); // one blue, one red: 100 marbles, 2 sprites
    render(item, QSize(200, 200), 0.5);
    QCOMPARE(item->cachedSpriteCount(), 4); // a new zoom needs new sprites
    // Zoomed far in (60-px marbles) the few marbles on screen are painted directly, not cached.
    const QImage close = render(item, QSize(240, 240), 6.0);
    QCOMPARE(item->cachedSpriteCount(), 4);
    QCOMPARE_LE(hueDistance(close.pixelColor(120, 120), item->marbleColor(0)), 12);
    QCOMPARE_GE(close.pixelColor(120, 120).hsvSaturation(), 100);
    delete item;
}

void TestMarbleFieldItem::marbleAtSearchesTheWorld_data()
{
    QTest::addColumn<QPointF>("point");
    QTest::addColumn<int>("marble");
    QTest::addRow("centre of 0") << QPointF(100, 100) << 0;
    QTest::addRow("rim of 0") << QPointF(70, 100) << 0;
    QTest::addRow("just outside 0") << QPointF(69.5, 100) << -1;
    QTest::addRow("inside 1") << QPointF(310, 110) << 1;
    QTest::addRow("overlap: highest index wins") << QPointF(115, 100) << 2;
    QTest::addRow("empty stage") << QPointF(200, 30) << -1;
}

void TestMarbleFieldItem::marbleAtSearchesTheWorld()
{
    QFETCH(QPointF, point);
    QFETCH(int, marble);
    World w = twoMarbles();
    w.addMarble({125, 100}, 12); // overlaps marble 0 (an edited scene may hold overlaps)
    const MarbleFieldItem item(&w);
    QCOMPARE(item.marbleAt(point), marble);
}

void TestMarbleFieldItem::antialiasingStopsAboveTheThreshold()
{
    World w = twoMarbles();
    MarbleFieldItem item(&w);
    QCOMPARE(item.antialiasThreshold(), MarbleFieldItem::kDefaultAntialiasThreshold);
    QVERIFY(item.isAntialiased());
    item.setAntialiasThreshold(1);
    QVERIFY(!item.isAntialiased());
    item.setAntialiasThreshold(2);
    QVERIFY(item.isAntialiased());
    const MarbleFieldItem empty;
    QVERIFY(empty.isAntialiased());
    QCOMPARE(empty.marbleAt(QPointF(0, 0)), -1);
    QVERIFY(empty.boundingRect().isEmpty());
}

void TestMarbleFieldItem::setWorldResyncs()
{
    const World a = twoMarbles();
    World b;
    b.stage = {1000, 50, true};
    b.addMarble({900, 25}, 10);
    b.info[0].color = "#00ff00";
    MarbleFieldItem item(&a);
    QCOMPARE(item.world(), &a);
    item.setWorld(&b);
    QCOMPARE(item.world(), &b);
    QVERIFY(item.boundingRect().contains(QRectF(0, 0, 1000, 50)));
    QCOMPARE(item.marbleColor(0), QColor(0x00, 0xff, 0x00));
    QCOMPARE(item.marbleAt(QPointF(900, 25)), 0);
    QCOMPARE(item.marbleAt(QPointF(100, 100)), -1);
    item.setWorld(nullptr);
    QVERIFY(item.boundingRect().isEmpty());
}

QTEST_MAIN(TestMarbleFieldItem)
#include "tst_marblefielditem.moc"
