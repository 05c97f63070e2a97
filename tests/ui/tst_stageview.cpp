// StageView: items mirror the world, the mouse edits through the document (drags, holds, drops,
// tools), the wheel zooms about the mouse, and the Figure 11.12 overlay follows World::lastHit.

#include "core/presets.h"
#include "ui/marblefielditem.h"
#include "ui/marbleitem.h"
#include "ui/pinitem.h"
#include "ui/scenedocument.h"
#include "ui/stageview.h"
#include "ui/trailitem.h"
#include "ui/vectoritem.h"
#include "ui/worldedit.h"

#include <QApplication>
#include <QContextMenuEvent>
#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QSignalSpy>
#include <QStyleHints>
#include <QTest>
#include <QTimer>
#include <QToolTip>
#include <QWheelEvent>

#include <cmath>
#include <memory>

using namespace marbles;

namespace {

template<typename Item>
QList<Item *> itemsOf(const StageView &view)
{
    QList<Item *> found;
    for (QGraphicsItem *item : view.scene()->items()) {
        if (item->type() == Item::Type)
            found << static_cast<Item *>(item);
    }
    return found;
}

} // namespace

class TestStageView : public QObject {
    Q_OBJECT

private Q_SLOTS:
    void init();
    void cleanup();

    void itemsMirrorTheWorld();
    void fitShowsTheWholeStage();
    void fitShowsWhatLiesBesideTheStage();
    void wheelZoomsAboutTheMouse_data();
    void wheelZoomsAboutTheMouse();
    void heldMarbleStaysStillWhileRunning();
    void dropOntoPinGoesToNearestFreeSpot();
    void pinDragIsOneUndoStep();
    void keyMidDragDropsFirst();
    void addToolsPlaceOnFreeSpots_data();
    void addToolsPlaceOnFreeSpots();
    void addMarbleWithoutRoomKeepsTheSelection();
    void vectorsFollowLastHit();
    void shortMoveIsStillAClick_data();
    void focusFrameShowsTheKeysGoToTheStage();
    void keyboardMenuIsAboutTheSelection();
    void shortMoveIsStillAClick();
    void pushIsShownUntilItActs();
    void clickIsMeasuredAsTheStageLayAtThePress();
    void clickPushesFromThePointPressed();
    void scriptedPushIsShownWhenDue();
    void pushLabelKeepsOffMarbles();
    void latestClickIsLast();
    void batchedAboveTheThreshold_data();
    void batchedAboveTheThreshold();
    void batchedClickSelectsAndPushes_data();
    void batchedClickSelectsAndPushes();
    void batchedDragHoldsAndDrops();
    void batchedVectorsAndSelection();
    void trailsOffForLargeCrowds();
    void stepBackCutsTrails();
    void selectedMarbleKeepsLongTrail();
    void followedTrailIsDrawnWhole();
    void stillFramesAreNotRedrawn_data();
    void stillFramesAreNotRedrawn();
    void vectorsWaitForALegibleZoom();
    void batchedToolTipNamesTheMarble();
    void tintsColourMarblesWithoutColours();
    void hugeStagesAreDrawn_data();
    void hugeStagesAreDrawn();

private:
    QWidget *viewport() const { return m_view->viewport(); }
    /// Loads a crowd of `n` marbles at rest (seed 7), so that clicks land where the test aims.
    void loadCrowd(int n);
    /// A marble of the loaded scene with at least `minRadius`, well inside the stage.
    int bigMarble(double minRadius) const;
    /// Pixels of the push arrow's ink on the ray from marble i's rim to the right (direction
    /// +1) or to the left (-1), out to 20 px, in a band 7 px high (a click's pixel rounding tilts
    /// the push a little).
    int pushInkOnRay(int i, int direction) const;

    std::unique_ptr<SceneDocument> m_document;
    std::unique_ptr<StageView> m_view;
};

void TestStageView::init()
{
    m_document = std::make_unique<SceneDocument>();
    World w;
    QVERIFY(makePreset("pins", w));
    m_document->resetScene(w);
    m_view = std::make_unique<StageView>(m_document.get());
    m_view->resize(900, 700);
    m_view->show();
    QVERIFY(QTest::qWaitForWindowExposed(m_view.get()));
}

void TestStageView::cleanup()
{
    m_view.reset();
    m_document.reset();
}

void TestStageView::hugeStagesAreDrawn_data()
{
    QTest::addColumn<double>("width");
    QTest::newRow("1e10") << 1e10;
    QTest::newRow("1e308") << 1e308;
}

void TestStageView::hugeStagesAreDrawn()
{
    // Any stage the loader takes is drawn: the background grid drew every 50 px line of the stage
    // (a 1e10 px stage took 6 s a paint) and for 1e308 never ended (x + 50 == x past 6e17).
    QFETCH(double, width);
    World w;
    w.stage = {width, 600, true};
    w.addMarble({100, 300}, 20);
    m_document->resetScene(w);
    m_view->fitToStage();
    const QImage fitted = m_view->grab().toImage();
    QVERIFY(!fitted.isNull());
    // At 1:1 by the marble: the stage's cream, and a grid line every 50 px across the view.
    m_view->setTransform(QTransform());
    m_view->centerOn(400, 300);
    const QImage near = m_view->viewport()->grab().toImage();
    const int row = m_view->mapFromScene(QPointF(0, 340)).y();
    const QColor cream(0xfb, 0xfa, 0xf6);
    QCOMPARE(near.pixelColor(m_view->mapFromScene(QPointF(425, 325))), cream);
    int lines = 0;
    for (int x = 1; x < near.width(); ++x) {
        const bool line = near.pixelColor(x, row) != cream;
        lines += line && near.pixelColor(x - 1, row) == cream ? 1 : 0;
    }
    const int expected = near.width() / 50;
    QVERIFY2(std::abs(lines - expected) <= 2, qPrintable(QStringLiteral("%1 lines").arg(lines)));
}

void TestStageView::tintsColourMarblesWithoutColours()
{
    // The plotted marbles are drawn in their lines' colours (the window hands the plot's colours
    // over); a marble with a colour of its own keeps it, and the others are the stage's blue.
    World w;
    w.addMarble({100, 100}, 10);
    w.addMarble({200, 100}, 10);
    w.addMarble({300, 100}, 10);
    w.info[2].color = "#123456";
    m_document->resetScene(w);
    const QColor orange(0xe6, 0x9f, 0x00);
    m_view->setMarbleTints({{1, orange}, {2, Qt::green}});
    auto colourAt = [&](double x) {
        for (MarbleItem *item : itemsOf<MarbleItem>(*m_view)) {
            if (item->pos().x() == x)
                return item->color();
        }
        return QColor(Qt::black);
    };
    QCOMPARE(colourAt(100), QColor());
    QCOMPARE(colourAt(200), orange);
    QCOMPARE(colourAt(300), QColor(0x12, 0x34, 0x56));
    m_view->setMarbleTints({});
    QCOMPARE(colourAt(200), QColor());

    // Batched (a crowd): the same, through the field item's colours.
    loadCrowd(StageView::kBatchThreshold + 10);
    QVERIFY(m_view->isBatched());
    m_view->setMarbleTints({{1, orange}});
    QCOMPARE(m_view->fieldItem()->marbleColor(1), orange);
    QCOMPARE(m_view->fieldItem()->marbleColor(2), MarbleItem::defaultColor());
    m_view->setMarbleTints({{2, orange}});
    QCOMPARE(m_view->fieldItem()->marbleColor(1), MarbleItem::defaultColor());
    QCOMPARE(m_view->fieldItem()->marbleColor(2), orange);
}

void TestStageView::itemsMirrorTheWorld()
{
    m_document->advance(37);
    const World &w = m_document->world();
    auto marbles = itemsOf<MarbleItem>(*m_view);
    QCOMPARE(marbles.size(), w.marbleCount());
    QCOMPARE(itemsOf<PinItem>(*m_view).size(), static_cast<qsizetype>(w.pins.size()));
    // Each world marble has an item at its position with its radius.
    for (int i = 0; i < w.marbleCount(); ++i) {
        const bool found = std::any_of(marbles.begin(), marbles.end(), [&](MarbleItem *item) {
            return item->pos() == QPointF(w.position[i].x, w.position[i].y) && item->radius() == w.radius[i];
        });
        QVERIFY2(found, qPrintable(QStringLiteral("marble %1").arg(i)));
    }
    QVERIFY(m_document->addMarble({60, 540}, 14).isEmpty());
    QCOMPARE(itemsOf<MarbleItem>(*m_view).size(), w.marbleCount());
    m_document->undoStack()->undo();
    QCOMPARE(itemsOf<MarbleItem>(*m_view).size(), w.marbleCount());
    // Moving items are not indexed (they move every frame).
    QCOMPARE(m_view->scene()->itemIndexMethod(), QGraphicsScene::NoIndex);
}

void TestStageView::fitShowsTheWholeStage()
{
    const Stage &stage = m_document->world().stage;
    const QRect inside = viewport()->rect();
    for (Vec2 corner : {Vec2{0, 0}, Vec2{stage.width, 0}, Vec2{0, stage.height}, Vec2{stage.width, stage.height}})
        QVERIFY(inside.contains(m_view->viewportPoint(corner)));
    m_view->zoomBy(3.0);
    QVERIFY(!inside.contains(m_view->viewportPoint({0, 0})));
    m_view->fitToStage();
    QVERIFY(inside.contains(m_view->viewportPoint({0, 0})));

    // Zoomed in, an edit keeps the zoom; a new scene (here a smaller stage) is shown whole.
    m_view->zoomBy(3.0);
    QVERIFY(m_document->addPin({stage.width / 2 + 7, stage.height / 2 + 7}).isEmpty());
    QVERIFY(!inside.contains(m_view->viewportPoint({0, 0})));
    World small;
    small.stage = {300, 200, true};
    small.addMarble({150, 100}, 10);
    m_document->resetScene(small);
    for (Vec2 corner : {Vec2{0, 0}, Vec2{300, 0}, Vec2{0, 200}, Vec2{300, 200}})
        QVERIFY(inside.contains(m_view->viewportPoint(corner)));
    QCOMPARE_GT(m_view->viewportPoint({300, 0}).x() - m_view->viewportPoint({0, 0}).x(), inside.width() / 2);
}

void TestStageView::fitShowsWhatLiesBesideTheStage()
{
    // A scene may put marbles and pins off its stage: they are shown beside it, and said. (Only the stage was shown, fitted too, while the
    // status bar counted marbles nobody could see.) As far as twice its size beyond each edge.
    QSignalSpy messages(m_view.get(), &StageView::message);
    World w;
    w.stage = {800, 600, true};
    w.addMarble({400, 300}, 20);
    w.addMarble({-500, 300}, 20);
    w.addMarble({2000, -300}, 20);
    w.addMarble({1e7, 300}, 20); // too far out: zoom out to find it
    w.pins.push_back({-100, -100});
    m_document->resetScene(w);
    const QRect inside = viewport()->rect();
    for (Vec2 p : {Vec2{0, 0}, Vec2{800, 600}, Vec2{-520, 300}, Vec2{2020, -320}, Vec2{-100, -100}})
        QVERIFY2(inside.contains(m_view->viewportPoint(p)), qPrintable(QStringLiteral("(%1, %2)").arg(p.x).arg(p.y)));
    QVERIFY(!inside.contains(m_view->viewportPoint({1e7, 300})));
    QTRY_VERIFY(!messages.isEmpty());
    const QString said = messages.last().at(0).toString();
    QVERIFY2(said.startsWith(QStringLiteral("3 marbles and 1 pin of this scene lie outside the stage")), qPrintable(said));

    // The stage alone: fitted as before, and nothing said.
    messages.clear();
    World inner;
    inner.stage = {800, 600, true};
    inner.addMarble({400, 300}, 20);
    m_document->resetScene(inner);
    QCOMPARE(m_view->scene()->sceneRect(), QRectF(0, 0, 800, 600).adjusted(-16, -16, 16, 16));
    QTest::qWait(50);
    QVERIFY(messages.isEmpty());
}

void TestStageView::wheelZoomsAboutTheMouse_data()
{
    QTest::addColumn<QPoint>("mouse");
    QTest::addColumn<int>("clicks"); // wheel clicks, + zooms in
    QTest::addColumn<double>("zoomFirst"); // zoomBy() before the wheel: room to scroll when zooming out
    QTest::addRow("in, upper left") << QPoint(200, 150) << 3 << 1.0;
    QTest::addRow("in, centre") << QPoint(450, 350) << 1 << 1.0;
    QTest::addRow("in, zoomed in, lower left") << QPoint(120, 600) << 2 << 2.0;
    QTest::addRow("out, lower right") << QPoint(700, 520) << -2 << 4.0;
}

void TestStageView::wheelZoomsAboutTheMouse()
{
    QFETCH(QPoint, mouse);
    QFETCH(int, clicks);
    QFETCH(double, zoomFirst);
    if (zoomFirst != 1.0)
        m_view->zoomBy(zoomFirst);
    const Vec2 before = m_view->stagePoint(mouse);
    const double scaleBefore = m_view->transform().m11();
    QWheelEvent wheel(QPointF(mouse), QPointF(viewport()->mapToGlobal(mouse)), QPoint(), QPoint(0, 120 * clicks),
                      Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(viewport(), &wheel);
    const double scaleAfter = m_view->transform().m11();
    QCOMPARE_LE(std::abs(scaleAfter / scaleBefore - std::pow(1.15, clicks)), 1e-9);
    // The stage point under the mouse stays under it (to within a pixel of rounding).
    const Vec2 after = m_view->stagePoint(mouse);
    QCOMPARE_LE(std::abs(after.x - before.x), 1.0 / std::min(scaleBefore, scaleAfter));
    QCOMPARE_LE(std::abs(after.y - before.y), 1.0 / std::min(scaleBefore, scaleAfter));
}

void TestStageView::heldMarbleStaysStillWhileRunning()
{
    const World &w = m_document->world();
    const int marble = 1; // the big one, moving at (-6, -5.5) px/frame
    const QPoint press = m_view->viewportPoint(w.position[marble]);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, press);
    QTest::mouseMove(viewport(), press + QPoint(-20, -10));
    QCOMPARE(m_document->heldMarble(), marble);
    const Vec2 held = w.position[marble];
    m_document->advance(25);
    QCOMPARE(w.position[marble], held);
    QCOMPARE(w.velocity[marble], Vec2{});
    QCOMPARE(w.acceleration[marble], Vec2{});
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, press + QPoint(-20, -10));
    QCOMPARE(m_document->heldMarble(), -1);
    QCOMPARE(m_document->undoStack()->count(), 1);
    // Released, it stays where it was dropped, at rest, and the others went on moving.
    QCOMPARE(w.position[marble], held);
    QCOMPARE(w.velocity[marble], Vec2{});
}

void TestStageView::dropOntoPinGoesToNearestFreeSpot()
{
    const World &w = m_document->world();
    const int marble = 2; // radius 16
    const Vec2 pin = w.pins[7];
    QSignalSpy messages(m_view.get(), &StageView::message);
    const QPoint press = m_view->viewportPoint(w.position[marble]);
    const QPoint target = m_view->viewportPoint(pin);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, press);
    QTest::mouseMove(viewport(), (press + target) / 2);
    QTest::mouseMove(viewport(), target);
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, target);
    QVERIFY(isFreeSpot(w, w.position[marble], w.radius[marble], BodyKind::Marble, marble));
    // The nearest free spot just clears the pin (2 px search rings).
    const double d = distance(w.position[marble], pin);
    QCOMPARE_GT(d, w.radius[marble]);
    QCOMPARE_LE(d, w.radius[marble] + 2.5);
    QCOMPARE(messages.count(), 1);
    QCOMPARE(m_document->undoStack()->count(), 1);
}

void TestStageView::pinDragIsOneUndoStep()
{
    const World &w = m_document->world();
    const Vec2 start = w.pins[0];
    const QPoint press = m_view->viewportPoint(start);
    const QPoint release = press + QPoint(25, 40);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, press);
    QCOMPARE(m_view->selectedPin(), 0);
    for (int k = 1; k <= 5; ++k)
        QTest::mouseMove(viewport(), press + (release - press) * k / 5);
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, release);
    const Vec2 from = m_view->stagePoint(press);
    const Vec2 to = m_view->stagePoint(release);
    QCOMPARE_LE(std::abs(w.pins[0].x - (start.x + to.x - from.x)), 1e-9);
    QCOMPARE_LE(std::abs(w.pins[0].y - (start.y + to.y - from.y)), 1e-9);
    QCOMPARE(m_document->undoStack()->count(), 1);
    m_document->undoStack()->undo();
    QCOMPARE(w.pins[0], start);
    QCOMPARE(itemsOf<PinItem>(*m_view).size(), static_cast<qsizetype>(w.pins.size()));
}

void TestStageView::addToolsPlaceOnFreeSpots_data()
{
    QTest::addColumn<bool>("marbleTool");
    QTest::addColumn<int>("onPin"); // click on this pin, or -1 for open space
    QTest::addRow("marble, open space") << true << -1;
    QTest::addRow("marble, on a pin") << true << 5;
    QTest::addRow("pin, open space") << false << -1;
    QTest::addRow("pin, on a pin") << false << 5;
    QTest::addRow("marble, between pixels") << true << -2;
    QTest::addRow("pin, between pixels") << false << -2;
}

void TestStageView::addToolsPlaceOnFreeSpots()
{
    QFETCH(bool, marbleTool);
    QFETCH(int, onPin);
    const World &w = m_document->world();
    // (-2: a click between pixels, which lands on the whole pixel: a marble sat at (600.25, 301.15).)
    const Vec2 at = onPin >= 0 ? w.pins[static_cast<std::size_t>(onPin)] : onPin == -2 ? Vec2{740.4, 40.6} : Vec2{760, 40};
    const int marbles = w.marbleCount();
    const auto pins = w.pins.size();
    m_view->setTool(marbleTool ? StageView::Tool::AddMarble : StageView::Tool::AddPin);
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, m_view->viewportPoint(at));
    if (onPin == -2) {
        const Vec2 placed = marbleTool ? w.position.back() : w.pins.back();
        QCOMPARE(placed.x, std::round(placed.x));
        QCOMPARE(placed.y, std::round(placed.y));
    }
    if (marbleTool) {
        QCOMPARE(w.marbleCount(), marbles + 1);
        QCOMPARE(w.radius.back(), StageView::kNewMarbleRadius);
        QVERIFY(isFreeSpot(w, w.position.back(), w.radius.back(), BodyKind::Marble, marbles));
        QCOMPARE(m_view->selectedMarble(), marbles);
    } else {
        QCOMPARE(w.pins.size(), pins + 1);
        QVERIFY(isFreeSpot(w, w.pins.back(), 0.0, BodyKind::Pin, -1, static_cast<int>(pins)));
        // Its dot clear of every other pin's (one on a pin had been put on it, then 0.5 px off it).
        for (std::size_t j = 0; j < pins; ++j)
            QCOMPARE_GE(distance(w.pins.back(), w.pins[j]), 2.0 * kPinDotRadiusPx);
    }
    QCOMPARE(m_document->undoStack()->count(), 1);
}

void TestStageView::addMarbleWithoutRoomKeepsTheSelection()
{
    // A stage filled with marbles as wide as a new one: nowhere to put it. The click says so and
    // leaves the scene and the selection as they were.
    World w;
    w.stage = {200.0, 200.0, true};
    for (int row = 0; row < 5; ++row) {
        for (int col = 0; col < 5; ++col)
            w.addMarble({20.0 + 40.0 * col, 20.0 + 40.0 * row}, StageView::kNewMarbleRadius);
    }
    m_document->resetScene(w);
    m_view->selectMarble(12);
    QSignalSpy messages(m_view.get(), &StageView::message);
    m_view->setTool(StageView::Tool::AddMarble);
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, m_view->viewportPoint({100, 100}));
    QCOMPARE(m_document->world().marbleCount(), 25);
    QCOMPARE(m_document->undoStack()->count(), 0);
    QCOMPARE(m_view->selectedMarble(), 12);
    QCOMPARE(messages.size(), 1);
    QVERIFY2(messages.first().first().toString().startsWith(QStringLiteral("No free spot")),
             qPrintable(messages.first().first().toString()));
}

void TestStageView::vectorsFollowLastHit()
{
    m_document->advance(60); // the pins field: every marble hits something early on
    const World &w = m_document->world();
    int hitMarbles = 0;
    for (const HitRecord &hit : w.lastHit)
        hitMarbles += hit.frame >= 0 ? 1 : 0;
    QVERIFY(hitMarbles > 0);
    const auto visibleVectors = [this] {
        int n = 0;
        for (VectorItem *item : itemsOf<VectorItem>(*m_view))
            n += item->isVisible() ? 1 : 0;
        return n;
    };
    QCOMPARE(visibleVectors(), hitMarbles);
    m_view->setVectorsVisible(false);
    QCOMPARE(visibleVectors(), 0);
    m_view->setVectorsVisible(true);
    QCOMPARE(visibleVectors(), hitMarbles);
    // Back to frame 0: nothing has been hit yet.
    QVERIFY(m_document->rewind());
    QCOMPARE(visibleVectors(), 0);
}

void TestStageView::focusFrameShowsTheKeysGoToTheStage()
{
    // A keyboard tester's finding: Tab brought the keys to the stage with nothing on screen to
    // show it. With them, a frame in the highlight colour runs round its edge; without, none.
    m_view->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(m_view.get()));
    m_view->setFocus();
    QTRY_VERIFY(m_view->hasFocus());
    const QColor highlight = m_view->palette().color(QPalette::Highlight);
    const QImage focused = m_view->viewport()->grab().toImage();
    const QPoint middleOfLeftEdge(1, focused.height() / 2);
    const QPoint middleOfTopEdge(focused.width() / 2, 1);
    QCOMPARE(focused.pixelColor(middleOfLeftEdge), highlight);
    QCOMPARE(focused.pixelColor(middleOfTopEdge), highlight);
    QVERIFY(focused.pixelColor(focused.width() / 2, 6) != highlight);
    m_view->clearFocus();
    QTRY_VERIFY(!m_view->hasFocus());
    const QImage unfocused = m_view->viewport()->grab().toImage();
    QVERIFY(unfocused.pixelColor(middleOfLeftEdge) != highlight);
    QVERIFY(unfocused.pixelColor(middleOfTopEdge) != highlight);
}

void TestStageView::keyboardMenuIsAboutTheSelection()
{
    // A keyboard tester's finding: the Menu key opened the stage's menu at the window's corner,
    // and Add Marble Here put the marble in the stage's top left corner. From the keyboard the
    // menu is about the marble selected, or the middle of the view.
    QAction here(QStringLiteral("Here"));
    m_view->setContextActions({&here});
    const auto openByKey = [this] {
        QPoint shownAt(-1, -1);
        QTimer::singleShot(0, this, [&shownAt] {
            if (QWidget *popup = QApplication::activePopupWidget()) {
                shownAt = popup->pos();
                popup->close();
            }
        });
        QContextMenuEvent event(QContextMenuEvent::Keyboard, QPoint(0, 0), m_view->viewport()->mapToGlobal(QPoint(0, 0)));
        QApplication::sendEvent(m_view->viewport(), &event);
        return shownAt;
    };
    const World &w = m_document->world();
    m_view->selectMarble(1);
    const QPoint marble = m_view->viewportPoint(w.position[1]);
    // (Its height only: Qt moves a menu sideways to keep it on the offscreen 800 x 600 screen.)
    QCOMPARE(openByKey().y(), m_view->viewport()->mapToGlobal(marble).y());
    QCOMPARE_LE(distance(m_view->contextPoint(), w.position[1]), 1.0 / m_view->transform().m11());
    QCOMPARE(m_view->selectedMarble(), 1);

    m_view->clearSelection();
    const QPoint middle = m_view->viewport()->rect().center();
    QCOMPARE(openByKey().y(), m_view->viewport()->mapToGlobal(middle).y());
    const QPointF expected = m_view->mapToScene(middle);
    QCOMPARE_LE(distance(m_view->contextPoint(), {expected.x(), expected.y()}), 1.0 / m_view->transform().m11());

    // Shift+F10 as the Menu key (it opened nothing: a re-tester's finding).
    m_view->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(m_view.get()));
    m_view->setFocus();
    m_view->selectMarble(2);
    bool opened = false;
    QTimer::singleShot(0, this, [&opened] {
        if (QWidget *popup = QApplication::activePopupWidget()) {
            opened = true;
            popup->close();
        }
    });
    QTest::keyClick(m_view.get(), Qt::Key_F10, Qt::ShiftModifier);
    QVERIFY(opened);
    QCOMPARE_LE(distance(m_view->contextPoint(), w.position[2]), 1.0 / m_view->transform().m11());
}

void TestStageView::keyMidDragDropsFirst()
{
    // Ctrl+Z while a marble was dragged brought a deleted marble back in front of it, and the drag
    // went on with that one (the document held it by its number): the marble brought back was
    // dropped where the hand let go, the one held left moved with no undo step (a re-tester's
    // finding). A key drops the marble first; the undo then takes the move back.
    World scene;
    scene.stage = {800, 600, true};
    scene.addMarble({200, 300}, 30);
    scene.addMarble({500, 300}, 30);
    scene.addPin({350, 150});
    m_document->resetScene(scene);
    const World &w = m_document->world();
    m_document->removeMarble(0);
    QCOMPARE(w.marbleCount(), 1);
    const QPoint grab = m_view->viewportPoint(w.position[0]);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, grab);
    QTest::mouseMove(viewport(), grab + QPoint(20, 0));
    QTest::mouseMove(viewport(), grab + QPoint(60, 40));
    QCOMPARE(m_document->heldMarble(), 0);
    QTest::keyClick(m_view.get(), Qt::Key_Z, Qt::ControlModifier); // the window's Undo takes it then
    QCOMPARE(m_document->heldMarble(), -1);
    QCOMPARE(m_document->undoStack()->count(), 2); // the delete, the move
    m_document->undoStack()->undo();
    QCOMPARE(w.position[0], Vec2(500, 300));
    m_document->undoStack()->undo();
    QCOMPARE(w.marbleCount(), 2);
    QTest::mouseMove(viewport(), grab + QPoint(90, 60));
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, grab + QPoint(90, 60));
    QCOMPARE(w.position[0], Vec2(200, 300));
    QCOMPARE(w.position[1], Vec2(500, 300));
    QCOMPARE(m_document->undoStack()->index(), 0);

    // A pin likewise.
    const QPoint pin = m_view->viewportPoint(w.pins[0]);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, pin);
    QTest::mouseMove(viewport(), pin + QPoint(20, 0));
    QTest::mouseMove(viewport(), pin + QPoint(50, 30));
    QCOMPARE(m_document->draggedPin(), 0);
    QTest::keyClick(m_view.get(), Qt::Key_Z, Qt::ControlModifier);
    QCOMPARE(m_document->draggedPin(), -1);
    m_document->undoStack()->undo();
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, pin + QPoint(80, 30));
    QCOMPARE(w.pins[0], Vec2(350, 150));
}

void TestStageView::shortMoveIsStillAClick_data()
{
    QTest::addColumn<QPoint>("move");
    QTest::addColumn<bool>("isClick");
    // Qt's drag distance, 10 px along x plus along y on the offscreen platform (a helper's
    // finding: a 3 px diagonal jitter dragged the marble under the old 4 px tolerance).
    QCOMPARE(QGuiApplication::styleHints()->startDragDistance(), 10);
    QTest::addRow("still") << QPoint(0, 0) << true;
    QTest::addRow("jitter") << QPoint(2, -2) << true;
    QTest::addRow("diagonal jitter") << QPoint(3, 3) << true;
    QTest::addRow("shake") << QPoint(-4, 5) << true;
    QTest::addRow("drag") << QPoint(8, 4) << false;
    QTest::addRow("drag along x") << QPoint(-10, 0) << false;
}

void TestStageView::shortMoveIsStillAClick()
{
    QFETCH(QPoint, move);
    QFETCH(bool, isClick);
    const World &w = m_document->world();
    const int marble = 0;
    const Vec2 start = w.position[marble];
    const QPoint press = m_view->viewportPoint(start) + QPoint(-8, 0);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, press);
    QTest::mouseMove(viewport(), press + move);
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, press + move);
    if (isClick) {
        QCOMPARE(w.position[marble], start);
        QVERIFY(w.acceleration[marble] != Vec2{});
        QCOMPARE(m_document->undoStack()->count(), 0);
    } else {
        QVERIFY(w.position[marble] != start);
        QCOMPARE(w.acceleration[marble], Vec2{});
        QCOMPARE(m_document->undoStack()->count(), 1);
    }
}

void TestStageView::clickIsMeasuredAsTheStageLayAtThePress()
{
    // A helper's finding: on a projector at a scale of 1.5 the press that selected a marble
    // filled the Inspector, which grew the window and re-fitted the stage under the still mouse;
    // the release, read on the stage as it lay then, pushed a marble clicked on its left edge
    // down and to the left at 29.5 px/frame. The click is where the press was on the stage, and
    // the mouse's travel on the screen from there.
    const World &w = m_document->world();
    const int marble = 0;
    const QPoint press = m_view->viewportPoint(w.position[marble]) + QPoint(-8, 0);
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, press);
    const Vec2 clicked = w.acceleration[marble];
    QVERIFY(clicked.x > 0.0);
    QCOMPARE(m_document->takeBackPushes(), 1);

    QTest::mousePress(viewport(), Qt::LeftButton, {}, press);
    m_view->scale(1.5, 1.5); // the stage re-fitted, the mouse still
    QVERIFY(m_view->viewportPoint(w.position[marble]) != press + QPoint(8, 0));
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, press);
    QVERIFY(sameBits(w.acceleration[marble], clicked));

    // A heavier marble gains less: the status bar gives the push as worked out again, beside
    // the arrow's (it kept the size of the moment of the click; a re-tester's finding).
    QSignalSpy messages(m_view.get(), &StageView::frameMessage);
    const double massScale = w.params.massScale;
    QVERIFY(m_document->setParam(QStringLiteral("massScale"), QString::number(4.0 * massScale)).isEmpty());
    QCOMPARE(messages.count(), 1);
    const Vec2 now = w.acceleration[marble];
    QCOMPARE_LE(std::abs(now.x - clicked.x / 4.0), 1e-12 * std::abs(clicked.x));
    QCOMPARE(messages.last().at(0).toString(),
             QStringLiteral("Marble 0's push waiting is now (%1, %2) px/frame, for the mass and push scale it meets")
                 .arg(now.x, 0, 'f', 2)
                 .arg(now.y, 0, 'f', 2));
    // An edit that leaves it as it is says nothing of it.
    QVERIFY(m_document->setParam(QStringLiteral("friction"), QStringLiteral("0.3")).isEmpty());
    QCOMPARE(messages.count(), 1);
}

void TestStageView::clickPushesFromThePointPressed()
{
    // The point clicked is where the press landed on the marble, carried along with it. Read at
    // the release, it depended on how long the button was held: a marble running on under the
    // mouse was pushed along its way (as if clicked behind its centre), and a hand's shake just
    // off the edge before the release pushed harder than any point on the marble could.
    World scene;
    scene.stage = {800, 600, true};
    scene.params.friction = 0.0;
    scene.params.zeroThreshold = 0.0;
    scene.addMarble({200, 300}, 20);
    scene.velocity[0] = {4.0, 0.0};
    m_document->resetScene(scene);
    const World &w = m_document->world();
    const double perPx = w.params.pushScale / w.mass[0];
    // The push of a press at `press` on the still marble, as PHYSICS.md works it out.
    const auto pushOfPress = [&](QPoint press) {
        const Vec2 at = m_view->stagePoint(press);
        return Vec2{(w.position[0].x - at.x) * perPx, (w.position[0].y - at.y) * perPx};
    };
    // The push waiting is `clicked`'s, to 1e-12 px/frame.
    const auto pushedAsClicked = [&](Vec2 clicked) {
        const Vec2 a = w.acceleration[0];
        const bool near = std::abs(a.x - clicked.x) <= 1e-12 && std::abs(a.y - clicked.y) <= 1e-12;
        if (!near)
            qWarning("push (%g, %g), clicked (%g, %g)", a.x, a.y, clicked.x, clicked.y);
        return near;
    };

    // Held while the marble runs on 20 px (5 frames at 4 px/frame), pressed 12 px behind it.
    const QPoint behind = m_view->viewportPoint(w.position[0]) + QPoint(-12, 0);
    const Vec2 fromBehind = pushOfPress(behind);
    QVERIFY(fromBehind.x > 0.0);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, behind);
    m_document->advance(5);
    QCOMPARE(w.frame, 5);
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, behind);
    QVERIFY(pushedAsClicked(fromBehind));
    QCOMPARE(m_document->takeBackPushes(), 1);

    // Pressed 2 px inside the front edge, released after a shake of 6 px outwards and 3 down
    // (a click still: under the drag distance).
    const QPoint edge = m_view->viewportPoint(w.position[0]) + QPoint(static_cast<int>(18 * m_view->transform().m11()), 0);
    const Vec2 fromEdge = pushOfPress(edge);
    QVERIFY(fromEdge.x < 0.0);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, edge);
    QTest::mouseMove(viewport(), edge + QPoint(6, 3));
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, edge + QPoint(6, 3));
    QCOMPARE(m_document->undoStack()->count(), 0); // not a drag
    QVERIFY(pushedAsClicked(fromEdge));
    QCOMPARE(m_document->takeBackPushes(), 1);

    // The marble pressed deleted (by its key) before the release: no other marble that took its
    // number is pushed (a re-tester's finding: the next marble got the press's push).
    scene.addMarble({600, 300}, 20);
    m_document->resetScene(scene);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, m_view->viewportPoint(w.position[0]) + QPoint(-12, 0));
    m_document->removeMarble(0);
    QCOMPARE(w.marbleCount(), 1);
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, m_view->viewportPoint(w.position[0]) + QPoint(-12, 0));
    QCOMPARE(w.acceleration[0], Vec2{});
    QVERIFY(m_view->pendingPushes().isEmpty());
}

void TestStageView::pushIsShownUntilItActs()
{
    // A click while paused changes nothing on the stage by itself: an arrow along the push shows
    // it until the frame that applies it, and the status bar says what it adds to the velocity.
    const World &w = m_document->world();
    const int marble = 0;
    QCOMPARE(w.acceleration[marble], Vec2{});
    const QPoint centre = m_view->viewportPoint(w.position[marble]);
    const auto inkOnRay = [&](int direction) { return pushInkOnRay(marble, direction); };
    QCOMPARE(inkOnRay(+1), 0);
    QSignalSpy messages(m_view.get(), &StageView::frameMessage);
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, centre + QPoint(-8, 0));
    const Vec2 push = w.acceleration[marble];
    QVERIFY(push.x > 0.0);
    QCOMPARE(m_view->pendingPushes(), QList<int>{marble});
    QCOMPARE(messages.count(), 1);
    QCOMPARE(messages.last().at(0).toString(),
             QStringLiteral("Marble 0 pushed: the click's push of (%1, %2) px/frame acts on the next frame; Esc takes the click back")
                 .arg(push.x, 0, 'f', 2)
                 .arg(push.y, 0, 'f', 2));
    QCOMPARE_GE(inkOnRay(+1), 10);
    QCOMPARE(inkOnRay(-1), 0);
    // A second click adds to the first: the message gives this click's part and the earlier one.
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, centre + QPoint(-8, 0));
    const Vec2 both = w.acceleration[marble];
    QCOMPARE(messages.last().at(0).toString(),
             QStringLiteral("Marble 0 pushed: the click's push of (%1, %2) px/frame acts on the next frame, "
                            "with earlier pushes' (%3, %4); Esc takes the click back")
                 .arg(both.x - push.x, 0, 'f', 2)
                 .arg(both.y - push.y, 0, 'f', 2)
                 .arg(push.x, 0, 'f', 2)
                 .arg(push.y, 0, 'f', 2));
    QCOMPARE(m_view->pendingPushes(), QList<int>{marble});

    // The frame applies it: the arrow goes.
    m_document->advance(1);
    QVERIFY(m_view->pendingPushes().isEmpty());
    QCOMPARE(inkOnRay(+1), 0);
    // Stepping back returns to the frame before it, push pending: the arrow is back.
    QVERIFY(m_document->stepBack());
    QCOMPARE(w.acceleration[marble], both);
    QCOMPARE(m_view->pendingPushes(), QList<int>{marble});
    QCOMPARE_GE(inkOnRay(+1), 10);
}

void TestStageView::latestClickIsLast()
{
    // Clicks on A, B, then A again: A's push is the latest, and its arrow carries the label.
    const World &w = m_document->world();
    const auto click = [&](int i) {
        QTest::mouseClick(viewport(), Qt::LeftButton, {}, m_view->viewportPoint(w.position[i]) + QPoint(-6, 0));
    };
    click(0);
    click(1);
    QCOMPARE(m_view->clickedPushes(), (QList<int>{0, 1}));
    click(0);
    QCOMPARE(m_view->clickedPushes(), (QList<int>{1, 0}));
}

void TestStageView::pushLabelKeepsOffMarbles()
{
    // Figure 11.8's scripted push ends at the small marble, and its label was written over it:
    // where the head's side covers a marble, the label goes above the pushed one.
    const Vec2 pinsMarble = m_document->world().position[0];
    QVERIFY(m_view->labelCoversMarble(QRectF(m_view->viewportPoint(pinsMarble), QSizeF(4, 4))));
    QVERIFY(!m_view->labelCoversMarble(QRectF(m_view->viewportPoint({2, 2}), QSizeF(2, 2))));
    World w;
    QVERIFY(makePreset("four-marbles", w));
    m_document->resetScene(w);
    m_view->fitToStage();
    QCOMPARE(m_view->pendingPushes(), QList<int>{0});
    const QImage image = m_view->viewport()->grab().toImage();
    const auto ink = [&](const QRect &area) {
        int count = 0;
        for (int y = area.top(); y <= area.bottom(); ++y) {
            for (int x = area.left(); x <= area.right(); ++x) {
                const QColor c = image.pixelColor(x, y);
                count += c.red() > 140 && c.green() < 110 && c.blue() > 80 && c.blue() < 170 ? 1 : 0;
            }
        }
        return count;
    };
    const double scale = m_view->transform().m11();
    const QPoint large = m_view->viewportPoint(w.position[0]);
    const int above = static_cast<int>(w.radius[0] * scale) + 4;
    QCOMPARE_GE(ink(QRect(large.x() - 60, large.y() - above - 20, 120, 20)), 30); // the label's text
    const QPoint small = m_view->viewportPoint(w.position[1]);
    const int r = static_cast<int>(w.radius[1] * scale);
    QCOMPARE(ink(QRect(small.x() + 4, small.y() - r, r - 4, 2 * r)), 0); // nothing over the small one past the arrow
}

void TestStageView::scriptedPushIsShownWhenDue()
{
    // A scene's scripted push is drawn while it is due (the frame it names is the current one),
    // on a still stage too, so a class sees it coming before the step that applies it.
    World scene;
    scene.addMarble({300, 300}, 20);
    scene.addMarble({500, 300}, 20);
    scene.pushes.push_back({2, 0, {290, 300}, {}}); // from the left: pushes right
    m_document->resetScene(scene);
    QTest::qWait(0);
    const World &w = m_document->world();
    QVERIFY(m_view->pendingPushes().isEmpty());
    QCOMPARE(pushInkOnRay(0, +1), 0);
    const qint64 paints = m_view->paintCount();
    m_document->advance(2); // nothing moves: only the due push changes the picture
    QCOMPARE(w.position[0], (Vec2{300, 300}));
    QTRY_VERIFY(m_view->paintCount() > paints); // before any grab(), which paints by itself
    QCOMPARE(m_view->pendingPushes(), QList<int>{0});
    QVERIFY(m_view->clickedPushes().isEmpty());
    QTRY_COMPARE_GE(pushInkOnRay(0, +1), 10);
    QCOMPARE(pushInkOnRay(0, -1), 0);
    QCOMPARE(w.scriptedPushDue(0).x, 10.0 * 10.0 / w.mass[0]);
    QCOMPARE(w.scriptedPushDue(1), Vec2{});

    // A click on the other marble joins it; the status bar gives the click's own part.
    QSignalSpy messages(m_view.get(), &StageView::frameMessage);
    const QPoint other = m_view->viewportPoint(w.position[1]);
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, other + QPoint(-8, 0));
    QCOMPARE(m_view->pendingPushes(), (QList<int>{1, 0}));
    QCOMPARE(m_view->clickedPushes(), QList<int>{1});
    // A click on the scripted marble names the script's part too.
    const QPoint first = m_view->viewportPoint(w.position[0]);
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, first + QPoint(-8, 0));
    const Vec2 click = w.acceleration[0];
    QCOMPARE(messages.last().at(0).toString(),
             QStringLiteral("Marble 0 pushed: the click's push of (%1, %2) px/frame acts on the next frame, "
                            "with the scene's scripted push (%3, 0.00); Esc takes the click back")
                 .arg(click.x, 0, 'f', 2)
                 .arg(click.y, 0, 'f', 2)
                 .arg(w.scriptedPushDue(0).x, 0, 'f', 2));
    // Its arrow, one for both, says the script's part is in it (the scripted label went, as if
    // the click had replaced the scene's push).
    m_view->viewport()->repaint();
    const double total = std::hypot(click.x + w.scriptedPushDue(0).x, click.y);
    QVERIFY2(m_view->pushLabels().contains(QStringLiteral("+%1 px/frame, scripted %2 in it")
                                               .arg(total, 0, 'f', 2)
                                               .arg(w.scriptedPushDue(0).x, 0, 'f', 2)),
             qPrintable(m_view->pushLabels().join(QStringLiteral(" | "))));

    // The frame applies both: no arrow is left.
    m_document->advance(1);
    QVERIFY(m_view->pendingPushes().isEmpty());
    QTRY_COMPARE(pushInkOnRay(0, +1), 0);
}

int TestStageView::pushInkOnRay(int i, int direction) const
{
    const World &w = m_document->world();
    const QPoint centre = m_view->viewportPoint(w.position[i]);
    const int rim = static_cast<int>(w.radius[i] * m_view->transform().m11());
    const QImage image = m_view->viewport()->grab().toImage();
    int ink = 0;
    for (int d = rim + 3; d < rim + 20; ++d) {
        bool hit = false;
        for (int dy = -3; dy <= 3; ++dy) {
            const QColor c = image.pixelColor(centre + QPoint(direction * d, dy));
            hit = hit || (c.red() > 140 && c.green() < 100 && c.blue() > 70 && c.blue() < c.red());
        }
        ink += hit ? 1 : 0;
    }
    return ink;
}

void TestStageView::loadCrowd(int n)
{
    m_document->resetScene(makeCrowd(n, 7, 0.0));
    QTest::qWait(0);
}

int TestStageView::bigMarble(double minRadius) const
{
    const World &w = m_document->world();
    for (int i = w.marbleCount() / 2; i < w.marbleCount(); ++i) {
        if (w.radius[i] >= minRadius)
            return i;
    }
    return -1;
}

void TestStageView::batchedAboveTheThreshold_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addColumn<bool>("batched");
    QTest::addColumn<bool>("antialiased");
    QTest::addRow("at the threshold") << StageView::kBatchThreshold << false << true;
    QTest::addRow("one above") << StageView::kBatchThreshold + 1 << true << true;
    QTest::addRow("past the antialias threshold") << StageView::kAntialiasThreshold + 1 << true << false;
}

void TestStageView::batchedAboveTheThreshold()
{
    QFETCH(int, marbles);
    QFETCH(bool, batched);
    QFETCH(bool, antialiased);
    loadCrowd(marbles);
    const World &w = m_document->world();
    QCOMPARE(m_view->isBatched(), batched);
    QCOMPARE(itemsOf<MarbleItem>(*m_view).size(), batched ? 0 : marbles);
    QCOMPARE(itemsOf<VectorItem>(*m_view).size(), batched ? 0 : marbles);
    QCOMPARE(itemsOf<MarbleFieldItem>(*m_view).size(), batched ? 1 : 0);
    QCOMPARE(m_view->renderHints().testFlag(QPainter::Antialiasing), antialiased);
    QCOMPARE(m_view->scene()->itemIndexMethod(), QGraphicsScene::NoIndex);
    if (batched) {
        QCOMPARE(m_view->fieldItem()->world(), &w);
        QCOMPARE(m_view->fieldItem()->isAntialiased(), antialiased);
    }
    // Across the threshold and back by editing: one marble less, then undo.
    const bool atThreshold = marbles == StageView::kBatchThreshold;
    if (atThreshold) // placed at the nearest free spot to the corner
        QCOMPARE(m_document->addMarble({1, 1}, 3), QStringLiteral("The marble was placed at the nearest free spot."));
    else
        m_document->removeMarble(0);
    const bool crossed = atThreshold || marbles == StageView::kBatchThreshold + 1;
    QCOMPARE(m_view->isBatched(), crossed ? !batched : batched);
    QCOMPARE(itemsOf<MarbleItem>(*m_view).size(), m_view->isBatched() ? 0 : w.marbleCount());
    m_document->undoStack()->undo();
    QCOMPARE(w.marbleCount(), marbles);
    QCOMPARE(m_view->isBatched(), batched);
    QCOMPARE(itemsOf<MarbleItem>(*m_view).size(), batched ? 0 : marbles);
    QCOMPARE(itemsOf<MarbleFieldItem>(*m_view).size(), batched ? 1 : 0);
}

void TestStageView::batchedClickSelectsAndPushes_data()
{
    QTest::addColumn<QPoint>("offset"); // from the marble's centre, viewport px
    QTest::addRow("left of centre") << QPoint(-3, 0);
    QTest::addRow("below right") << QPoint(2, 3);
    QTest::addRow("dead centre") << QPoint(0, 0);
}

void TestStageView::batchedClickSelectsAndPushes()
{
    QFETCH(QPoint, offset);
    loadCrowd(1000);
    QVERIFY(m_view->isBatched());
    const World &w = m_document->world();
    const int marble = bigMarble(10.0);
    QVERIFY(marble >= 0);
    QCOMPARE_GE(w.radius[marble] * m_view->transform().m11(), 5.0); // the offsets stay on the marble
    QSignalSpy selection(m_view.get(), &StageView::selectionChanged);
    const QPoint click = m_view->viewportPoint(w.position[marble]) + offset;
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, click);
    QCOMPARE(m_view->selectedMarble(), marble);
    QCOMPARE(selection.count(), 1);
    QCOMPARE(m_view->fieldItem()->selectedMarbles(), QList<int>({marble}));
    // The chapter's hitMarble: a = (p - c) * pushScale / m, from the click point c on release.
    const Vec2 c = m_view->stagePoint(click);
    const Vec2 p = w.position[marble];
    const double k = w.params.pushScale / w.mass[marble];
    QCOMPARE_LE(std::abs(w.acceleration[marble].x - (p.x - c.x) * k), 1e-12);
    QCOMPARE_LE(std::abs(w.acceleration[marble].y - (p.y - c.y) * k), 1e-12);
    for (int i = 0; i < w.marbleCount(); ++i) {
        if (i != marble)
            QCOMPARE(w.acceleration[i], Vec2{});
    }
    QCOMPARE(m_document->undoStack()->count(), 0);
    // A click on empty stage (a wall corner) selects nothing.
    QTest::mouseClick(viewport(), Qt::LeftButton, {}, m_view->viewportPoint({0.5, 0.5}));
    QCOMPARE(m_view->selectedMarble(), -1);
    QVERIFY(m_view->fieldItem()->selectedMarbles().isEmpty());
}

void TestStageView::batchedDragHoldsAndDrops()
{
    loadCrowd(1000);
    const World &w = m_document->world();
    const int marble = bigMarble(10.0);
    QVERIFY(marble >= 0);
    const Vec2 start = w.position[marble];
    const QPoint press = m_view->viewportPoint(start);
    QTest::mousePress(viewport(), Qt::LeftButton, {}, press);
    QTest::mouseMove(viewport(), press + QPoint(10, 0));
    QCOMPARE(m_document->heldMarble(), marble);
    QCOMPARE(m_view->fieldItem()->heldMarble(), marble);
    QVERIFY(w.position[marble] != start);
    // Drop it back where it came from (a free spot): one undo step.
    QTest::mouseMove(viewport(), press);
    QTest::mouseRelease(viewport(), Qt::LeftButton, {}, press);
    QCOMPARE(m_document->heldMarble(), -1);
    QCOMPARE(m_view->fieldItem()->heldMarble(), -1);
    QCOMPARE_LE(distance(w.position[marble], start), 1.0 / m_view->transform().m11());
    QCOMPARE(m_document->undoStack()->count(), 1);
    m_document->undoStack()->undo();
    QCOMPARE(w.position[marble], start);
}

void TestStageView::batchedVectorsAndSelection()
{
    loadCrowd(1000);
    MarbleFieldItem *field = m_view->fieldItem();
    QVERIFY(field);
    QCOMPARE(field->vectorsVisible(), m_view->vectorsVisible());
    m_view->setVectorsVisible(false);
    QVERIFY(!field->vectorsVisible());
    m_view->setVectorsVisible(true);
    QVERIFY(field->vectorsVisible());
    m_view->selectMarble(17);
    QCOMPARE(field->selectedMarbles(), QList<int>({17}));
    m_view->selectPin(0); // the crowd has no pins: selects nothing
    QVERIFY(field->selectedMarbles().isEmpty());
    m_view->selectMarble(3);
    m_view->deleteSelection();
    QCOMPARE(m_document->world().marbleCount(), 999);
    QCOMPARE(m_view->selectedMarble(), -1);
    QVERIFY(field == m_view->fieldItem());
}

void TestStageView::stepBackCutsTrails()
{
    // Stepping back shortens every trail to the frame it returns to, and stepping on grows it
    // again from there.
    m_view->setTrailsVisible(true);
    const QList<TrailItem *> trails = itemsOf<TrailItem>(*m_view);
    QCOMPARE(trails.size(), 1);
    const TrailItem *trail = trails.front();
    std::vector<Vec2> atFrame[13];
    atFrame[0] = m_document->world().position; // the trails start where the marbles are
    for (int f = 1; f <= 12; ++f) {
        m_document->advance(1);
        atFrame[f] = m_document->world().position;
    }
    const int marbles = m_document->world().marbleCount();
    QCOMPARE(static_cast<int>(trail->points(0).size()), 13);
    for (int k = 0; k < 3; ++k)
        QVERIFY(m_document->stepBack());
    QCOMPARE(m_document->world().frame, std::int64_t(9));
    for (int i = 0; i < marbles; ++i) {
        const std::vector<QPointF> points = trail->points(i);
        QCOMPARE(static_cast<int>(points.size()), 10);
        for (int f = 0; f <= 9; ++f) {
            const Vec2 p = atFrame[f][static_cast<std::size_t>(i)];
            const QPointF q = points[static_cast<std::size_t>(f)];
            QVERIFY(q.x() == p.x && q.y() == p.y); // copies of the positions: the same bits
        }
    }
    m_document->advance(2);
    QCOMPARE(static_cast<int>(trail->points(0).size()), 12);
    const Vec2 newest = m_document->world().position[0];
    QVERIFY(trail->points(0).back().x() == newest.x && trail->points(0).back().y() == newest.y);
    QVERIFY(m_document->rewind());
    QCOMPARE(static_cast<int>(trail->points(0).size()), 1); // frame 0's place
    m_document->advance(3);
    QCOMPARE(static_cast<int>(trail->points(0).size()), 4);
    // A parameter changed mid-run keeps the trails (the path bends from there, as the plot's
    // lines do); a marble moved or changed starts them over (it may have jumped), from where
    // the marbles are.
    QVERIFY(m_document->setParam(QStringLiteral("friction"), QStringLiteral("0.3")).isEmpty());
    QCOMPARE(static_cast<int>(trail->points(0).size()), 4);
    m_document->advance(1);
    QCOMPARE(static_cast<int>(trail->points(0).size()), 5);
    QVERIFY(m_document->setMarbleVelocity(1, {1.0, 0.0}).isEmpty());
    QCOMPARE(static_cast<int>(trail->points(0).size()), 1);
    const Vec2 now = m_document->world().position[0];
    QVERIFY(trail->points(0).front().x() == now.x && trail->points(0).front().y() == now.y);

    // A marble deleted mid-run: the others' trails run on through the frames Step Back goes to
    // (they had started again at the delete), and so do they once it is undone, its own too.
    std::vector<Vec2> since[7];
    since[0] = m_document->world().position;
    for (int f = 1; f <= 6; ++f) {
        m_document->advance(1);
        since[f] = m_document->world().position;
    }
    m_document->removeMarble(1);
    QCOMPARE(m_document->world().marbleCount(), marbles - 1);
    const auto followsRun = [&](int trailIndex, int marble, int frames) {
        const std::vector<QPointF> points = trail->points(trailIndex);
        if (static_cast<int>(points.size()) != frames + 1)
            return false;
        for (int f = 0; f <= frames; ++f) {
            const Vec2 p = since[f][static_cast<std::size_t>(marble)];
            if (points[static_cast<std::size_t>(f)] != QPointF(p.x, p.y))
                return false;
        }
        return true;
    };
    QVERIFY(followsRun(0, 0, 6));
    QVERIFY(followsRun(1, 2, 6)); // marble 2, now 1
    m_document->undoStack()->undo();
    QCOMPARE(m_document->world().marbleCount(), marbles);
    for (int i = 0; i < marbles; ++i)
        QVERIFY2(followsRun(i, i, 6), qPrintable(QString::number(i)));

    // A marble added mid-run: the trails start again there (the frames before have no place
    // for it); the add undone, they run through the frames before it again (they stayed started
    // at the add: the frames Step Back went to, without their trails).
    QVERIFY(m_document->addMarble({60.0, 60.0}, 8.0).isEmpty());
    QCOMPARE(static_cast<int>(trail->points(0).size()), 1);
    m_document->advance(3);
    m_document->undoStack()->undo();
    QCOMPARE(m_document->world().marbleCount(), marbles);
    QCOMPARE(m_document->world().frame, std::int64_t(10));
    for (int i = 0; i < marbles; ++i)
        QVERIFY2(followsRun(i, i, 6), qPrintable(QString::number(i)));
}

void TestStageView::selectedMarbleKeepsLongTrail()
{
    // In a crowd every trail is short (the segment budget shared out); the selected marble's is
    // kept up to kFollowedLength frames, so that a slow wander shows as a path. It starts from
    // the short trail it had, steps back with the others, and follows the selection.
    m_document->resetScene(makeCrowd(400, 3, 1.0));
    m_view->setTrailsVisible(true);
    const TrailItem *trail = itemsOf<TrailItem>(*m_view).front();
    const int shortLength = m_view->trailLength();
    QCOMPARE(shortLength, StageView::kTrailSegmentBudget / 400);
    QCOMPARE(trail->followed(), -1);
    // From where the marbles are when the trails are turned on (frame 0 was left out).
    std::vector<Vec2> seen{m_document->world().position[5]};
    for (int f = 1; f <= 10; ++f) {
        m_document->advance(1);
        seen.push_back(m_document->world().position[5]);
    }
    m_view->selectMarble(5);
    QCOMPARE(trail->followed(), 5);
    QCOMPARE(static_cast<int>(trail->followedPoints().size()), 11); // its trail so far, frames 0 to 10
    for (int f = 11; f <= 100; ++f) {
        m_document->advance(1);
        seen.push_back(m_document->world().position[5]);
    }
    QCOMPARE(static_cast<int>(trail->points(5).size()), shortLength);
    std::vector<QPointF> path = trail->followedPoints();
    QCOMPARE(static_cast<int>(path.size()), 101);
    for (std::size_t k = 0; k < path.size(); ++k)
        QVERIFY(path[k].x() == seen[k].x && path[k].y() == seen[k].y); // copies: the same bits
    for (int k = 0; k < 4; ++k)
        QVERIFY(m_document->stepBack());
    QCOMPARE(static_cast<int>(trail->followedPoints().size()), 97);
    QCOMPARE(static_cast<int>(trail->points(5).size()), shortLength - 4);
    // Another marble: its own trail so far, as long as the others'.
    m_view->selectMarble(7);
    QCOMPARE(trail->followed(), 7);
    path = trail->followedPoints();
    const std::vector<QPointF> shortPath = trail->points(7);
    QCOMPARE(path.size(), shortPath.size());
    QVERIFY(path == shortPath);
    m_view->clearSelection();
    QCOMPARE(trail->followed(), -1);
    QVERIFY(trail->followedPoints().empty());
    // A marble edited starts every trail over, the followed one too.
    m_view->selectMarble(7);
    m_document->advance(3);
    QCOMPARE(static_cast<int>(trail->followedPoints().size()), shortLength - 4 + 3);
    QVERIFY(m_document->setMarbleRadius(7, m_document->world().radius[7] * 0.9).isEmpty());
    QCOMPARE(static_cast<int>(trail->followedPoints().size()), 1); // from where it is now
    m_document->advance(2);
    QCOMPARE(static_cast<int>(trail->followedPoints().size()), 3);
    QCOMPARE(trail->followed(), 7);
    // At most kFollowedLength frames.
    m_document->advance(TrailItem::kFollowedLength + 5);
    QCOMPARE(static_cast<int>(trail->followedPoints().size()), TrailItem::kFollowedLength);
    const Vec2 newest = m_document->world().position[7];
    QVERIFY(trail->followedPoints().back().x() == newest.x && trail->followedPoints().back().y() == newest.y);
}

void TestStageView::followedTrailIsDrawnWhole()
{
    // Two marbles move side by side along x, 1 px a frame, for 150 frames, with trails of 4
    // frames: the followed one's whole path is drawn, in the selection's dark colour (over
    // the white, opacity at least 0.3); the other keeps a short blue trail.
    TrailItem item(4);
    World w;
    w.stage = {200, 100, true};
    w.addMarble({10, 60}, 2);
    w.addMarble({10, 20}, 2);
    item.setArea(QRectF(0, 0, 200, 100));
    item.setFollowed(0);
    for (int f = 0; f <= 150; ++f) {
        w.frame = f;
        w.position[0].x = 10.0 + f;
        w.position[1].x = 10.0 + f;
        item.sample(w);
    }
    QImage image(200, 100, QImage::Format_ARGB32_Premultiplied);
    image.fill(Qt::white);
    {
        QPainter painter(&image);
        item.paint(&painter, nullptr, nullptr);
    }
    // Dark and grey: the selection's colour over white at 0.3 or more, never the blue trails'.
    auto dark = [](QColor c) {
        return c.value() < 200 && std::abs(c.red() - c.blue()) < 12 && std::abs(c.green() - c.blue()) < 12;
    };
    auto blue = [](QColor c) { return c.blue() > c.red() + 20; };
    int darkAlong = 0;
    int blueAlongOther = 0;
    for (int x = 0; x < 200; ++x) {
        darkAlong += dark(image.pixelColor(x, 60)) ? 1 : 0;
        blueAlongOther += blue(image.pixelColor(x, 20)) ? 1 : 0;
        QVERIFY(!dark(image.pixelColor(x, 20)));
    }
    QCOMPARE_GE(darkAlong, 145); // the whole path (x = 10 to 160), its oldest part too
    QCOMPARE_GE(blueAlongOther, 2); // the last three frames' segments of the other
    QCOMPARE_LE(blueAlongOther, 4);
    item.setFollowed(-1);
    image.fill(Qt::white);
    {
        QPainter painter(&image);
        item.paint(&painter, nullptr, nullptr);
    }
    for (int x = 12; x < 158; ++x)
        QVERIFY(!dark(image.pixelColor(x, 60)));
}

void TestStageView::stillFramesAreNotRedrawn_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addRow("one item per marble") << 40;
    QTest::addRow("batched") << 1000;
}

void TestStageView::stillFramesAreNotRedrawn()
{
    // Frames in which nothing moves leave the picture as it was, so the stage is not redrawn
    // (vectors and trails on). A marble that moved and stopped keeps it redrawn while its trail
    // fades, and not after.
    QFETCH(int, marbles);
    World w = makeCrowd(marbles, 7, 0.0);
    w.params.friction = 0.5;
    w.params.zeroThreshold = 0.5;
    w.velocity[static_cast<std::size_t>(marbles / 2)] = {3.0, 0.0};
    m_document->resetScene(w);
    m_view->setVectorsVisible(true);
    m_view->setTrailsVisible(true);
    QCOMPARE(m_view->isBatched(), marbles > StageView::kBatchThreshold);
    QVERIFY(!m_view->trailsSuppressed());
    const auto allStill = [&] {
        const std::vector<Vec2> &v = m_document->world().velocity;
        return std::all_of(v.begin(), v.end(), [](Vec2 u) { return u.x == 0.0 && u.y == 0.0; });
    };
    QTest::qWait(20);
    qint64 painted = m_view->paintCount();
    for (int frames = 1; !allStill(); ++frames) {
        QVERIFY(frames < 20);
        m_document->advance(1);
        QTRY_VERIFY(m_view->paintCount() > painted); // it moved: drawn again
        painted = m_view->paintCount();
    }
    m_document->advance(1);
    QTRY_VERIFY(m_view->paintCount() > painted); // still, but its trail fades
    for (int f = 0; f < m_view->trailLength(); ++f) {
        m_document->advance(1);
        QTest::qWait(2);
    }
    QTest::qWait(20);
    const qint64 settled = m_view->paintCount();
    for (int f = 0; f < 5; ++f) {
        m_document->advance(1);
        QTest::qWait(5);
    }
    QCOMPARE(m_view->paintCount(), settled);
}

void TestStageView::trailsOffForLargeCrowds()
{
    QSignalSpy messages(m_view.get(), &StageView::message);
    m_view->setTrailsVisible(true);
    QVERIFY(!m_view->trailsSuppressed());
    QTest::qWait(0);
    QCOMPARE(messages.count(), 0);
    // A few marbles: full-length trails. A crowd shares out the segment budget.
    QCOMPARE(m_view->trailLength(), TrailItem::kMaxLength);
    loadCrowd(400);
    QCOMPARE(m_view->trailLength(), StageView::kTrailSegmentBudget / 400);
    QVERIFY(!m_view->trailsSuppressed());
    loadCrowd(StageView::kMaxTrailMarbles + 1);
    QVERIFY(m_view->trailsVisible());
    QVERIFY(m_view->trailsSuppressed());
    QTRY_COMPARE(messages.count(), 1); // queued, so that it follows the window's own messages
    QVERIFY(messages.front().front().toString().contains(QStringLiteral("only the selected marble has a trail")));
    m_document->advance(3);
    QTest::qWait(0);
    QCOMPARE(messages.count(), 1); // said once, not every frame
    // The selected marble's trail is still kept and drawn; no other is.
    const TrailItem *trail = itemsOf<TrailItem>(*m_view).front();
    QVERIFY(trail->isVisible());
    QVERIFY(trail->followedOnly());
    QVERIFY(trail->points(0).empty());
    m_view->selectMarble(3);
    m_document->advance(4);
    QCOMPARE(trail->followedPoints().size(), std::size_t(4));
    QVERIFY(trail->points(3).empty());
    QVERIFY(m_document->stepBack());
    QCOMPARE(trail->followedPoints().size(), std::size_t(3));
    const Vec2 now = m_document->world().position[3];
    QVERIFY(trail->followedPoints().back().x() == now.x && trail->followedPoints().back().y() == now.y);
    m_view->clearSelection();
    loadCrowd(StageView::kMaxTrailMarbles);
    QVERIFY(!m_view->trailsSuppressed());
    QVERIFY(!trail->followedOnly());
    QCOMPARE(m_view->trailLength(), StageView::kMinTrailLength);
    m_view->setTrailsVisible(false);
    loadCrowd(StageView::kMaxTrailMarbles + 1);
    QVERIFY(!m_view->trailsSuppressed());
    QTest::qWait(0);
    QCOMPARE(messages.count(), 1);
}

void TestStageView::vectorsWaitForALegibleZoom()
{
    QSignalSpy messages(m_view.get(), &StageView::message);
    loadCrowd(20000); // a 4,260-px stage in a 900 x 700 view: the 30-px vectors come to 5 px
    QVERIFY(m_view->vectorsVisible());
    QVERIFY(m_view->fieldItem()->vectorsVisible());
    QVERIFY(m_view->vectorsHiddenByZoom());
    QTRY_COMPARE(messages.count(), 1);
    QVERIFY(messages.front().front().toString().contains(QStringLiteral("zoom in")));
    m_view->zoomBy(2.0);
    QVERIFY(!m_view->vectorsHiddenByZoom());
    m_view->fitToStage();
    QVERIFY(m_view->vectorsHiddenByZoom());
    QTRY_COMPARE(messages.count(), 2); // said again after zooming back out, not on every check
    m_view->setVectorsVisible(false);
    QVERIFY(!m_view->vectorsHiddenByZoom());
    QTest::qWait(0);
    QCOMPARE(messages.count(), 2);
}

void TestStageView::batchedToolTipNamesTheMarble()
{
    World crowd = makeCrowd(1000, 7, 0.0);
    const int marble = 640;
    crowd.info[marble].name = "Alice";
    m_document->resetScene(crowd);
    QVERIFY(m_view->isBatched());
    const QPoint at = m_view->viewportPoint(m_document->world().position[marble]);
    QHelpEvent help(QEvent::ToolTip, at, viewport()->mapToGlobal(at));
    QApplication::sendEvent(viewport(), &help);
    QCOMPARE(QToolTip::text(), QStringLiteral("Alice"));
}

QTEST_MAIN(TestStageView)
#include "tst_stageview.moc"
