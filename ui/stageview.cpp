#include "ui/stageview.h"

#include "ui/marblefielditem.h"
#include "ui/marbleitem.h"
#include "ui/numbertext.h"
#include "ui/pinitem.h"
#include "ui/trailitem.h"
#include "ui/vectoritem.h"
#include "ui/worldedit.h"

#include <QContextMenuEvent>
#include <QCursor>
#include <QFocusEvent>
#include <QGraphicsScene>
#include <QHelpEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QGuiApplication>
#include <QPainter>
#include <QScrollBar>
#include <QShortcut>
#include <QStyleHints>
#include <QToolTip>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>
#include <utility>

namespace marbles {

namespace {

/// Margin around the stage inside the scene rectangle, stage px.
constexpr double kSceneMarginPx = 16.0;
/// Pins are picked within this many viewport px of the mouse.
constexpr double kPinPickPx = 7.0;
/// Zoom range, view px per stage px.
constexpr double kMinZoom = 0.05;
constexpr double kMaxZoom = 40.0;

QColor colorOf(const MarbleInfo &info)
{
    if (info.color.empty())
        return {};
    QColor c(QString::fromStdString(info.color));
    return c.isValid() ? c : QColor();
}

} // namespace

StageView::StageView(SceneDocument *document, QWidget *parent)
    : QGraphicsView(parent)
    , m_document(document)
    , m_scene(new QGraphicsScene(this))
{
    setObjectName(QStringLiteral("stageView"));
    setAccessibleName(tr("Stage"));
    // Shift+F10 opens the stage's menu as the Menu key does (on X11 Qt gives the Menu key alone a
    // context menu event: a re-tester's finding).
    auto *menuKey = new QShortcut(QKeySequence(Qt::SHIFT | Qt::Key_F10), this);
    menuKey->setContext(Qt::WidgetShortcut);
    connect(menuKey, &QShortcut::activated, this, [this] {
        QContextMenuEvent event(QContextMenuEvent::Keyboard, QPoint(), QCursor::pos());
        contextMenuEvent(&event);
    });
    // Items move every frame: an index would be rebuilt constantly for nothing.
    m_scene->setItemIndexMethod(QGraphicsScene::NoIndex);
    setScene(m_scene);
    setRenderHints(QPainter::Antialiasing | QPainter::SmoothPixmapTransform);
    // While the run goes nearly everything on the stage moves every frame: one full repaint is
    // cheaper than merging hundreds of small dirty rectangles.
    setViewportUpdateMode(QGraphicsView::FullViewportUpdate);
    setTransformationAnchor(QGraphicsView::AnchorViewCenter);
    setResizeAnchor(QGraphicsView::AnchorViewCenter);
    setDragMode(QGraphicsView::NoDrag);
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(false);
    setMinimumSize(320, kMinimumHeight);

    m_trail = new TrailItem();
    m_trail->setZValue(-1.0);
    m_trail->setVisible(m_trailsVisible);
    m_scene->addItem(m_trail);

    connect(m_document, &SceneDocument::stepped, this, &StageView::syncPoses);
    // A frame can bring a scripted push due or apply the pushes drawn: the arrows are redrawn
    // even where no marble moves (a still stage is not repainted otherwise).
    connect(m_document, &SceneDocument::stepped, this, [this] {
        if (m_arrowsShown || !pendingPushes().isEmpty())
            viewport()->update();
    });
    connect(m_document, &SceneDocument::frameAdvanced, this, &StageView::sampleTrail);
    connect(m_document, &SceneDocument::timelineReset, this, &StageView::replayTrail);
    // An edit can renumber the marbles (a removal), and a step back brings back the pushes made
    // at the frame it returns to: the pushes still to come are found again.
    connect(m_document, &SceneDocument::sceneChanged, this, &StageView::findPendingPushes);
    connect(m_document, &SceneDocument::timelineRewound, this, &StageView::findPendingPushes);
    connect(m_document, &SceneDocument::timelineRewound, this, [this](std::int64_t frame) {
        m_trail->cutAfter(frame);
        m_trailsSince = std::min(m_trailsSince, frame);
    });
    // The selection stays on the marble it was on while marbles before it leave or come back
    // (it stayed on the index, another marble). A selected marble that leaves takes the
    // selection with it, and gives it back when it comes back (a delete undone): the marble came
    // back unselected, the Inspector empty (a helper's finding).
    connect(m_document, &SceneDocument::marbleInsertedAt, this, [this](int i) {
        if (m_selectionKind == SelectionKind::Marble && m_selectionIndex >= i)
            selectMarble(m_selectionIndex + 1);
        else if (m_selectionKind == SelectionKind::None && i == m_unselectedByRemoval)
            selectMarble(i);
    });
    connect(m_document, &SceneDocument::marbleRemovedAt, this, [this](int i) {
        if (m_selectionKind != SelectionKind::Marble || m_selectionIndex < i)
            return;
        if (m_selectionIndex > i) {
            selectMarble(m_selectionIndex - 1);
            return;
        }
        clearSelection();
        m_unselectedByRemoval = i;
    });
    connect(m_document, &SceneDocument::sceneChanged, this, [this](SceneDocument::Change change) {
        // A marble or pin pressed and not yet released may be gone, and another have its number
        // (Delete pressed while the button was held pushed the next marble, a re-tester's
        // finding): the press is let go, and its release does nothing.
        if ((change == SceneDocument::Change::Structure || change == SceneDocument::Change::Scene)
            && (m_gesture == Gesture::PressMarble || m_gesture == Gesture::PressPin))
            m_gesture = Gesture::None;
        // A new scene is shown whole, whatever the zoom was on the last one.
        if (change == SceneDocument::Change::Scene) {
            m_autoFit = true;
            m_trailsSince = m_document->world().frame;
            noteOutside();
        }
        // A marble moved or changed by hand may have jumped: the trails start over. A parameter
        // changed mid-run (friction, gravity) keeps them, so that the paths bend from there.
        if (change == SceneDocument::Change::Marbles)
            resetTrail();
        rebuild();
        if (change == SceneDocument::Change::Params || change == SceneDocument::Change::Marbles)
            sayPushRescaled();
    });
    rebuild();
}

StageView::~StageView() = default;

void StageView::setTool(Tool tool)
{
    m_tool = tool;
    viewport()->setCursor(tool == Tool::Select ? Qt::ArrowCursor : Qt::CrossCursor);
}

void StageView::selectMarble(int i)
{
    if (i < 0 || i >= m_document->world().marbleCount()) {
        clearSelection();
        return;
    }
    m_selectionKind = SelectionKind::Marble;
    m_selectionIndex = i;
    m_unselectedByRemoval = -1;
    updateHighlights();
    Q_EMIT selectionChanged();
}

void StageView::pushAt(int i, Vec2 p, bool byKey)
{
    const Vec2 before = m_document->world().acceleration[static_cast<std::size_t>(i)];
    m_document->pushMarble(i, p);
    const Vec2 after = m_document->world().acceleration[static_cast<std::size_t>(i)];
    const Vec2 a{after.x - before.x, after.y - before.y};
    // Last in the list, as the latest click: its arrow carries the label (a marble clicked again
    // after another kept its first place, and the other marble kept the label).
    m_pushed.removeAll(i);
    m_pushed.append(i);
    const Vec2 scripted = m_document->world().scriptedPushDue(i);
    const auto pair = [](Vec2 u) { return shownPair(shownNumber(u.x, 'f', 2), shownNumber(u.y, 'f', 2)); };
    QString text = (byKey ? tr("Marble %1 pushed: the key's push of %2 px/frame acts on the next frame")
                          : tr("Marble %1 pushed: the click's push of %2 px/frame acts on the next frame"))
                       .arg(i)
                       .arg(pair(a));
    if (before.x != 0.0 || before.y != 0.0)
        text += tr(", with earlier pushes' %1").arg(pair(before));
    if (scripted.x != 0.0 || scripted.y != 0.0)
        text += tr(", with the scene's scripted push %1").arg(pair(scripted));
    // A click is not an edit: Ctrl+Z cannot take it back. A key's push is no click.
    text += byKey ? tr("; Esc takes the push back") : tr("; Esc takes the click back");
    m_saidPush = {i, after};
    Q_EMIT frameMessage(text);
    viewport()->update();
}

void StageView::sayPushRescaled()
{
    // The push the status bar gave, worked out again for a new mass or push scale (PHYSICS.md
    // works it out just before its frame): the status bar had kept the old size beside the
    // arrow's new one (a re-tester's finding).
    const World &world = m_document->world();
    const auto [i, said] = m_saidPush;
    if (i < 0 || i >= world.marbleCount() || !m_pushed.contains(i))
        return;
    const Vec2 a = world.acceleration[static_cast<std::size_t>(i)];
    if (sameBits(a, said) || !world.pushPending(i))
        return;
    m_saidPush = {i, a};
    Q_EMIT frameMessage(tr("Marble %1's push waiting is now %2 px/frame, for the mass and push scale it meets")
                            .arg(i)
                            .arg(shownPair(shownNumber(a.x, 'f', 2), shownNumber(a.y, 'f', 2))));
}

void StageView::selectNextMarble(int step)
{
    const int n = m_document->world().marbleCount();
    if (n == 0)
        return;
    const int current = selectedMarble();
    const int next = current < 0 ? (step > 0 ? 0 : n - 1) : ((current + step) % n + n) % n;
    selectMarble(next); // the ring, the Inspector and the plot say which
}

bool StageView::pushSelected(Vec2 direction)
{
    const int i = selectedMarble();
    if (i < 0)
        return false;
    // As a click on the marble's far side would: the push points from the click to the centre.
    const World &world = m_document->world();
    const Vec2 c = world.position[static_cast<std::size_t>(i)];
    const double r = world.radius[static_cast<std::size_t>(i)];
    pushAt(i, {c.x - direction.x * r, c.y - direction.y * r}, true);
    return true;
}

void StageView::selectPin(int j)
{
    if (j < 0 || j >= static_cast<int>(m_document->world().pins.size())) {
        clearSelection();
        return;
    }
    m_selectionKind = SelectionKind::Pin;
    m_selectionIndex = j;
    m_unselectedByRemoval = -1;
    updateHighlights();
    Q_EMIT selectionChanged();
}

void StageView::clearSelection()
{
    m_unselectedByRemoval = -1;
    if (m_selectionKind == SelectionKind::None)
        return;
    m_selectionKind = SelectionKind::None;
    m_selectionIndex = -1;
    updateHighlights();
    Q_EMIT selectionChanged();
}

void StageView::deleteSelection()
{
    const SelectionKind kind = m_selectionKind;
    const int index = m_selectionIndex;
    if (kind == SelectionKind::Marble) {
        m_document->removeMarble(index); // takes the selection with it (and gives it back on undo)
        return;
    }
    clearSelection();
    if (kind == SelectionKind::Pin)
        m_document->removePin(index);
}

void StageView::setVectorsVisible(bool visible)
{
    m_vectorsVisible = visible;
    if (!visible) {
        for (VectorItem *item : m_vectors)
            item->setVisible(false);
    }
    if (m_field)
        m_field->setVectorsVisible(visible);
    syncPoses();
    updateVectorNote();
}

bool StageView::vectorsHiddenByZoom() const
{
    return m_field && m_vectorsVisible && !MarbleFieldItem::vectorsLegibleAt(transform().m11());
}

void StageView::updateVectorNote()
{
    const bool hidden = vectorsHiddenByZoom();
    if (hidden && !m_vectorNoteShown)
        noteLater(tr("The collision vectors are too small to read at this zoom: zoom in to see them."));
    m_vectorNoteShown = hidden;
}

void StageView::setTrailsVisible(bool visible)
{
    m_trailsVisible = visible;
    updateTrailSuppression();
    resetTrail();
}

int StageView::trailLength() const
{
    const int n = std::max(1, m_document->world().marbleCount());
    return std::clamp(kTrailSegmentBudget / n, kMinTrailLength, TrailItem::kMaxLength);
}

void StageView::updateTrailSuppression()
{
    // Above kMaxTrailMarbles only the selected marble's trail is kept and drawn.
    const bool crowd = m_document->world().marbleCount() > kMaxTrailMarbles;
    const bool suppressed = m_trailsVisible && crowd;
    const bool announce = suppressed && !m_trailsSuppressed;
    m_trailsSuppressed = suppressed;
    m_trail->setFollowedOnly(crowd);
    m_trail->setVisible(m_trailsVisible);
    m_trail->setLength(trailLength());
    m_trail->setAntialiased(m_document->world().marbleCount() <= kBatchThreshold);
    if (announce)
        noteLater(tr("Above %L1 marbles only the selected marble has a trail: every marble's would slow the stage down.")
                      .arg(kMaxTrailMarbles));
}

void StageView::fitToStage()
{
    m_autoFit = true;
    // The whole scene rectangle (stage and margin) fits, so no scroll bar is needed.
    fitInView(m_scene->sceneRect(), Qt::KeepAspectRatio);
    updateVectorNote();
}

void StageView::zoomBy(double factor)
{
    const double current = transform().m11();
    const double target = std::clamp(current * factor, kMinZoom, kMaxZoom);
    if (target == current)
        return;
    m_autoFit = false;
    scale(target / current, target / current); // about the viewport centre (the view's anchor)
    updateVectorNote();
}

QPoint StageView::viewportPoint(Vec2 p) const
{
    return viewportTransform().map(QPointF(p.x, p.y)).toPoint();
}

Vec2 StageView::stagePoint(QPointF pos) const
{
    const QPointF s = viewportTransform().inverted().map(pos);
    return {s.x(), s.y()};
}

void StageView::setContextActions(const QList<QAction *> &actions)
{
    m_contextActions = actions;
}

void StageView::rebuild()
{
    const World &world = m_document->world();
    const int n = world.marbleCount();
    if (n > kBatchThreshold) {
        // Batched: one item draws every marble (and the vectors); no item per marble.
        rebuildMarbleItems(world, 0);
        if (!m_field) {
            m_field = new MarbleFieldItem(&world);
            m_field->setAntialiasThreshold(kAntialiasThreshold);
            m_scene->addItem(m_field);
        }
        m_field->setVectorsVisible(m_vectorsVisible);
        m_field->setWorld(&world);
        applyTintsToField();
    } else {
        delete m_field;
        m_field = nullptr;
        rebuildMarbleItems(world, n);
    }
    // Lines and pins drawn hard past the threshold; the field item follows the same count.
    setRenderHint(QPainter::Antialiasing, n <= kAntialiasThreshold);

    const int pinCount = static_cast<int>(world.pins.size());
    while (static_cast<int>(m_pins.size()) > pinCount) {
        delete m_pins.back();
        m_pins.pop_back();
    }
    while (static_cast<int>(m_pins.size()) < pinCount) {
        auto *pin = new PinItem();
        pin->setZValue(1.0);
        m_scene->addItem(pin);
        m_pins.push_back(pin);
    }
    for (int j = 0; j < pinCount; ++j)
        m_pins[j]->setPos(world.pins[j].x, world.pins[j].y);

    const QRectF stageRect(0, 0, world.stage.width, world.stage.height);
    const QRectF shown = shownArea(world, stageRect);
    m_scene->setSceneRect(shown.adjusted(-kSceneMarginPx, -kSceneMarginPx, kSceneMarginPx, kSceneMarginPx));
    m_trail->setArea(stageRect);
    updateTrailSuppression();
    if (m_selectionKind == SelectionKind::Marble && m_selectionIndex >= n)
        clearSelection();
    if (m_selectionKind == SelectionKind::Pin && m_selectionIndex >= pinCount)
        clearSelection();
    updateHighlights();
    syncPoses();
    if (m_autoFit)
        fitToStage();
    updateVectorNote();
    m_scene->update();
}

void StageView::rebuildMarbleItems(const World &world, int n)
{
    while (static_cast<int>(m_marbles.size()) > n) {
        delete m_marbles.back();
        m_marbles.pop_back();
        delete m_vectors.back();
        m_vectors.pop_back();
    }
    while (static_cast<int>(m_marbles.size()) < n) {
        auto *marble = new MarbleItem();
        m_scene->addItem(marble);
        m_marbles.push_back(marble);
        auto *vectors = new VectorItem();
        vectors->setZValue(2.0);
        vectors->setVisible(false);
        m_scene->addItem(vectors);
        m_vectors.push_back(vectors);
    }
    for (int i = 0; i < n; ++i) {
        m_marbles[i]->setRadius(world.radius[i]);
        m_marbles[i]->setColor(drawnColor(world, i));
        m_marbles[i]->setToolTip(QString::fromStdString(world.info[i].name));
    }
}

QColor StageView::drawnColor(const World &world, int i) const
{
    if (const QColor own = colorOf(world.info[static_cast<std::size_t>(i)]); own.isValid())
        return own;
    for (const auto &[marble, colour] : m_tints) {
        if (marble == i)
            return colour;
    }
    return {};
}

void StageView::applyTintsToField()
{
    if (!m_field)
        return;
    m_field->setTints(m_tints);
}

void StageView::setMarbleTints(const QList<QPair<int, QColor>> &tints)
{
    if (tints == m_tints)
        return;
    m_tints = tints;
    const World &world = m_document->world();
    for (int i = 0; i < static_cast<int>(m_marbles.size()) && i < world.marbleCount(); ++i)
        m_marbles[static_cast<std::size_t>(i)]->setColor(drawnColor(world, i));
    applyTintsToField();
}

void StageView::syncPoses()
{
    const World &world = m_document->world();
    const int held = m_document->heldMarble();
    if (m_field) {
        m_field->setHeldMarble(held);
        m_field->syncFromWorld();
        return;
    }
    const int n = std::min(world.marbleCount(), static_cast<int>(m_marbles.size()));
    for (int i = 0; i < n; ++i) {
        const QPointF p(world.position[i].x, world.position[i].y);
        m_marbles[i]->setPos(p);
        m_marbles[i]->setHeld(i == held);
        if (m_vectorsVisible) {
            m_vectors[i]->setPos(p);
            m_vectors[i]->setHit(world.lastHit[i], world.radius[i]);
            m_vectors[i]->setVisible(world.lastHit[i].frame >= 0);
        }
    }
}

void StageView::sampleTrail()
{
    if (m_trailsVisible)
        m_trail->sample(m_document->world());
}

void StageView::resetTrail()
{
    // Started from where the marbles are: sampled only after each frame, a trail began a frame
    // late, without its first segment.
    m_trail->clear();
    m_trailsSince = m_document->world().frame;
    sampleTrail();
}

void StageView::replayTrail()
{
    m_trail->clear();
    if (m_trailsVisible) {
        // The trails run on through the frames Step Back can still go to: after a marble left
        // mid-run or came back, the kept frames followed it (the trails had started again
        // there), and an add undone gives back the frames before it; a new timeline keeps none.
        // (Not further back than they went: a trail starts again where a marble was moved by
        // hand.)
        const World &world = m_document->world();
        const FrameHistory &history = m_document->history();
        const std::int64_t first = std::max(history.firstUnbrokenFrame(world.frame), m_trailsSince);
        std::optional<World> at; // the marbles of now at each kept frame (copied only if there is one)
        for (std::int64_t f = first; f < world.frame; ++f) {
            const std::vector<Vec2> *positions = history.positionsAt(f);
            if (!positions || positions->size() != world.position.size())
                continue;
            if (!at)
                at = world;
            at->position = *positions;
            at->frame = f;
            m_trail->sample(*at);
        }
    }
    sampleTrail();
}

void StageView::updateHighlights()
{
    m_trail->setFollowed(selectedMarble()); // the selected marble's trail is kept long
    if (m_field)
        m_field->setSelectedMarbles(m_selectionKind == SelectionKind::Marble ? QList<int>{m_selectionIndex} : QList<int>{});
    for (int i = 0; i < static_cast<int>(m_marbles.size()); ++i)
        m_marbles[i]->setHighlighted(m_selectionKind == SelectionKind::Marble && i == m_selectionIndex);
    for (int j = 0; j < static_cast<int>(m_pins.size()); ++j)
        m_pins[j]->setHighlighted(m_selectionKind == SelectionKind::Pin && j == m_selectionIndex);
}

void StageView::pickAt(Vec2 p)
{
    const World &world = m_document->world();
    const int pin = pinAt(world, p, kPinPickPx / transform().m11());
    if (pin >= 0) {
        selectPin(pin);
        return;
    }
    const int marble = marbleAt(world, p);
    if (marble >= 0)
        selectMarble(marble);
    else
        clearSelection();
}

QRectF StageView::shownArea(const World &world, const QRectF &stageRect) const
{
    // The stage, and what a scene puts beside it (its file may place marbles and pins anywhere),
    // up to twice the stage's size beyond each edge (the stage stays a fifth of the view at least):
    // a scene with marbles at x = -500 had shown only the stage, fitted too, and the status bar
    // counted marbles nobody could see.
    QRectF shown = stageRect;
    const double w = 2.0 * stageRect.width();
    const double h = 2.0 * stageRect.height();
    const QRectF reach = stageRect.adjusted(-w, -h, w, h);
    for (int i = 0; i < world.marbleCount(); ++i) {
        const Vec2 p = world.position[i];
        const double r = world.radius[i];
        const QRectF disc(p.x - r, p.y - r, 2.0 * r, 2.0 * r);
        if (!stageRect.contains(disc) && disc.isValid())
            shown |= disc & reach;
    }
    for (const Vec2 q : world.pins) {
        if (!stageRect.contains(QPointF(q.x, q.y)) && reach.contains(QPointF(q.x, q.y)))
            shown |= QRectF(q.x - 1.0, q.y - 1.0, 2.0, 2.0);
    }
    return shown;
}

void StageView::noteOutside()
{
    // Said when a scene opens with marbles or pins off the stage (shown beside it: shownArea()).
    const World &world = m_document->world();
    const QRectF stageRect(0, 0, world.stage.width, world.stage.height);
    int marbles = 0;
    for (int i = 0; i < world.marbleCount(); ++i)
        marbles += !stageRect.contains(QPointF(world.position[i].x, world.position[i].y));
    int pins = 0;
    for (const Vec2 q : world.pins)
        pins += !stageRect.contains(QPointF(q.x, q.y));
    if (marbles == 0 && pins == 0)
        return;
    const QString someMarbles = counted(marbles, tr("marble"), tr("marbles"));
    const QString somePins = counted(pins, tr("pin"), tr("pins"));
    const QString what = marbles > 0 && pins > 0 ? someMarbles + tr(" and ") + somePins : marbles > 0 ? someMarbles : somePins;
    noteLater((marbles + pins == 1 ? tr("%1 of this scene lies outside the stage, shown beside it as far as twice its size "
                                        "beyond each edge (zoom out for any further away).")
                                   : tr("%1 of this scene lie outside the stage, shown beside it as far as twice its size "
                                        "beyond each edge (zoom out for any further away)."))
                  .arg(what));
}

void StageView::noteLater(const QString &text)
{
    // Queued: a note raised while a file opens would otherwise be replaced at once by the
    // window's own "Opened ..." message.
    QMetaObject::invokeMethod(
        this, [this, text] { Q_EMIT message(text); }, Qt::QueuedConnection);
}

Vec2 StageView::placeAt(Vec2 p)
{
    // Whole pixels: a marble added where clicked sat at (600.25, 301.15), and a class's scene
    // needed its numbers typed in again to be read (the Inspector still takes any place).
    return {std::round(p.x), std::round(p.y)};
}

QString StageView::addMarbleAt(Vec2 p)
{
    const int before = m_document->world().marbleCount();
    const QString text = m_document->addMarble(placeAt(p), kNewMarbleRadius);
    if (m_document->world().marbleCount() > before)
        selectMarble(before);
    return text;
}

void StageView::report(const QString &text)
{
    if (!text.isEmpty())
        Q_EMIT message(text);
}

void StageView::drawBackground(QPainter *painter, const QRectF &rect)
{
    const bool antialias = painter->testRenderHint(QPainter::Antialiasing);
    // Around the stage, filled in device pixels: a scene rectangle near 1e308 px was not filled.
    painter->save();
    painter->resetTransform();
    painter->fillRect(viewport()->rect(), palette().color(QPalette::Window).darker(112)); // within the clip
    painter->restore();
    const Stage &stage = m_document->world().stage;
    const QRectF stageRect(0, 0, stage.width, stage.height);
    const QRectF area = rect.intersected(stageRect); // what is drawn of the stage (no overflow)
    painter->fillRect(area, QColor(0xfb, 0xfa, 0xf6));

    // A faint 50 px grid: positions and speeds can be read off the screen. Only its lines within
    // the area being drawn, and 10 or 100 ... times as far apart where 50 px would be less than
    // 4 screen pixels: a stage 1e10 px wide took 6 s a paint (every line of it), and one of 1e308
    // never finished (past 6e17, x + 50 is x).
    QPen grid(QColor(0xe6, 0xe3, 0xda));
    grid.setCosmetic(true);
    painter->setPen(grid);
    double spacing = 50.0;
    const double zoom = std::abs(painter->worldTransform().m11());
    while (spacing * zoom < 4.0 && spacing < 1e300)
        spacing *= 10.0;
    const auto lines = [spacing](double from, double to, auto &&draw) {
        // Lines k * spacing strictly inside (0, side), from `from` to `to`, counted by k.
        const double first = std::max(1.0, std::ceil(from / spacing));
        const double count = std::min(std::floor(to / spacing) - first + 1.0, 100000.0);
        for (int n = 0; n < count; ++n)
            draw((first + n) * spacing);
    };
    if (!area.isEmpty()) {
        lines(area.left(), area.right(), [&](double x) {
            if (x < stage.width)
                painter->drawLine(QPointF(x, area.top()), QPointF(x, area.bottom()));
        });
        lines(area.top(), area.bottom(), [&](double y) {
            if (y < stage.height)
                painter->drawLine(QPointF(area.left(), y), QPointF(area.right(), y));
        });
    }

    painter->setRenderHint(QPainter::Antialiasing, false);
    if (stage.walls) {
        QPen wall(QColor(0x37, 0x47, 0x4f));
        wall.setWidthF(6.0);
        wall.setCosmetic(true);
        wall.setJoinStyle(Qt::MiterJoin);
        painter->setPen(wall);
        const double half = 3.0 / transform().m11();
        painter->drawRect(stageRect.adjusted(-half, -half, half, half));
    } else {
        QPen edge(QColor(0x90, 0x90, 0x90));
        edge.setCosmetic(true);
        edge.setStyle(Qt::DashLine);
        painter->setPen(edge);
        painter->drawRect(stageRect);
    }
    painter->setRenderHint(QPainter::Antialiasing, antialias);
}

void StageView::mousePressEvent(QMouseEvent *event)
{
    if (event->button() != Qt::LeftButton) {
        QGraphicsView::mousePressEvent(event);
        return;
    }
    setFocus(Qt::MouseFocusReason);
    const Vec2 p = stagePoint(event->position());
    m_pressGlobal = viewport()->mapToGlobal(event->position());
    m_gesture = Gesture::None;
    switch (m_tool) {
    case Tool::AddMarble:
        report(addMarbleAt(p));
        return;
    case Tool::AddPin:
        report(m_document->addPin(placeAt(p)));
        return;
    case Tool::Select:
        break;
    }
    pickAt(p);
    const World &world = m_document->world();
    if (m_selectionKind == SelectionKind::Marble) {
        m_gesture = Gesture::PressMarble;
        m_gestureIndex = m_selectionIndex;
        const Vec2 c = world.position[m_gestureIndex];
        m_grabOffset = {c.x - p.x, c.y - p.y};
    } else if (m_selectionKind == SelectionKind::Pin) {
        m_gesture = Gesture::PressPin;
        m_gestureIndex = m_selectionIndex;
        const Vec2 q = world.pins[m_gestureIndex];
        m_grabOffset = {q.x - p.x, q.y - p.y};
    }
    event->accept();
}

void StageView::mouseMoveEvent(QMouseEvent *event)
{
    if (m_gesture == Gesture::None) {
        QGraphicsView::mouseMoveEvent(event);
        return;
    }
    const QPointF moved = viewport()->mapToGlobal(event->position()) - m_pressGlobal;
    // As Qt's own views tell a drag from a click: a hand on a touchpad or a presenter's mouse
    // shakes by a few pixels while it clicks (a helper's 3 px diagonal jitter dragged the marble
    // where a 4 px tolerance held).
    const bool beyondClick = moved.manhattanLength() >= QGuiApplication::styleHints()->startDragDistance();
    const Vec2 p = stagePoint(event->position());
    const Vec2 target{p.x + m_grabOffset.x, p.y + m_grabOffset.y};
    if (m_gesture == Gesture::PressMarble && beyondClick) {
        m_gesture = Gesture::DragMarble;
        m_document->beginHold(m_gestureIndex);
    } else if (m_gesture == Gesture::PressPin && beyondClick) {
        m_gesture = Gesture::DragPin;
        m_document->beginPinDrag(m_gestureIndex);
    }
    m_dragTarget = target;
    if (m_gesture == Gesture::DragMarble)
        m_document->moveHeld(target);
    else if (m_gesture == Gesture::DragPin)
        m_document->movePinDrag(target);
    event->accept();
}

void StageView::dropDragged(Gesture gesture, Vec2 target)
{
    if (gesture == Gesture::DragMarble)
        report(m_document->endHold(target));
    else if (gesture == Gesture::DragPin)
        report(m_document->endPinDrag(target));
}

bool StageView::event(QEvent *event)
{
    // A key pressed while a marble or pin is dragged drops it where it is first, then does what it
    // does. The document held it by its number: Ctrl+Z mid-drag brought a deleted marble back in
    // front of it, and the drag went on with that one, dropped where the hand let go while the
    // marble held stayed where it was, moved with no undo step (a re-tester's finding; a pin
    // likewise). Dropped first, Ctrl+Z takes the move back.
    if ((event->type() == QEvent::ShortcutOverride || event->type() == QEvent::KeyPress)
        && (m_gesture == Gesture::DragMarble || m_gesture == Gesture::DragPin))
        dropDragged(std::exchange(m_gesture, Gesture::None), m_dragTarget);
    return QGraphicsView::event(event);
}

void StageView::mouseReleaseEvent(QMouseEvent *event)
{
    if (event->button() != Qt::LeftButton || m_gesture == Gesture::None) {
        QGraphicsView::mouseReleaseEvent(event);
        return;
    }
    const Vec2 p = stagePoint(event->position());
    const Vec2 target{p.x + m_grabOffset.x, p.y + m_grabOffset.y};
    const Gesture gesture = m_gesture;
    m_gesture = Gesture::None;
    switch (gesture) {
    case Gesture::PressMarble: {
        // The chapter's hitMarble runs on release. The push acts on the next frame; until then an
        // arrow shows it (a click while paused would otherwise change nothing on screen, and a
        // second click add to it unseen).
        // The point clicked is where the press landed on the marble, carried along with the
        // marble: read at the release (hitMarble's own mouse position) it depended on how long
        // the button was held. A moving marble had run on under the mouse, and a click anywhere
        // on one at 4 px/frame, held for a tenth of a second, pushed it on along its way as
        // hard as a click 20 px behind its centre; a hand's shake of up to the drag distance
        // (10 px) before the release, just off a marble's edge, pushed harder than any point on
        // the marble could. Measured on the stage as it lay at the press, too (the selection it
        // makes fills the Inspector: on a projector at a scale of 1.5 that grew the window and
        // re-fitted the stage before the release).
        const int i = m_gestureIndex;
        if (i >= m_document->world().marbleCount())
            break; // (the press was let go when the marbles changed: see the constructor)
        const Vec2 centre = m_document->world().position[static_cast<std::size_t>(i)];
        pushAt(i, {centre.x - m_grabOffset.x, centre.y - m_grabOffset.y}, false);
        break;
    }
    case Gesture::DragMarble:
    case Gesture::DragPin:
        dropDragged(gesture, target);
        break;
    case Gesture::PressPin:
    case Gesture::None:
        break;
    }
    event->accept();
}

void StageView::mouseDoubleClickEvent(QMouseEvent *event)
{
    // A second click on a marble is a second push, as in the chapter (no special double-click).
    mousePressEvent(event);
}

bool StageView::viewportEvent(QEvent *event)
{
    // Per-marble items carry their own tool tips; in batched mode the world is searched instead.
    if (m_field && event->type() == QEvent::ToolTip) {
        const auto *help = static_cast<QHelpEvent *>(event);
        const int i = m_field->marbleAt(viewportTransform().inverted().map(QPointF(help->pos())));
        const QString name = i >= 0 ? QString::fromStdString(m_document->world().info[i].name) : QString();
        if (name.isEmpty())
            QToolTip::hideText();
        else
            QToolTip::showText(help->globalPos(), name, viewport());
        return true;
    }
    return QGraphicsView::viewportEvent(event);
}

void StageView::wheelEvent(QWheelEvent *event)
{
    const double steps = event->angleDelta().y() / 120.0;
    if (steps == 0.0) {
        QGraphicsView::wheelEvent(event);
        return;
    }
    const double current = transform().m11();
    const double target = std::clamp(current * std::pow(1.15, steps), kMinZoom, kMaxZoom);
    m_autoFit = false;
    // Zoom about the mouse: scale, then scroll the stage point that was under the mouse back
    // under it. (AnchorUnderMouse would need a hover position the view only has with mouse
    // tracking, which the stage leaves off.) Where the zoomed stage is smaller than the viewport
    // it is centred instead, and cannot follow the mouse.
    const QPointF mouse = event->position();
    const QPointF anchor = viewportTransform().inverted().map(mouse);
    scale(target / current, target / current);
    const QPointF drift = viewportTransform().map(anchor) - mouse;
    horizontalScrollBar()->setValue(horizontalScrollBar()->value() + static_cast<int>(std::lround(drift.x())));
    verticalScrollBar()->setValue(verticalScrollBar()->value() + static_cast<int>(std::lround(drift.y())));
    updateVectorNote();
    event->accept();
}

void StageView::resizeEvent(QResizeEvent *event)
{
    QGraphicsView::resizeEvent(event);
    if (m_autoFit)
        fitToStage();
}

void StageView::contextMenuEvent(QContextMenuEvent *event)
{
    // From the keyboard (the Menu key, Shift+F10) the menu is about the marble or pin selected,
    // where it is in sight, or else the middle of the view: it opened at the window's corner,
    // and Add Marble Here put a marble in the stage's top left corner (a helper's finding).
    QPoint at = event->pos();
    if (event->reason() == QContextMenuEvent::Keyboard) {
        const World &world = m_document->world();
        at = viewport()->rect().center();
        std::optional<Vec2> selected;
        if (m_selectionKind == SelectionKind::Marble && m_selectionIndex < world.marbleCount())
            selected = world.position[static_cast<std::size_t>(m_selectionIndex)];
        else if (m_selectionKind == SelectionKind::Pin && m_selectionIndex < static_cast<int>(world.pins.size()))
            selected = world.pins[static_cast<std::size_t>(m_selectionIndex)];
        if (selected && isFinite(*selected)) {
            const QPoint there = viewportPoint(*selected);
            if (viewport()->rect().contains(there))
                at = there;
        }
    }
    m_contextPoint = stagePoint(at);
    pickAt(m_contextPoint);
    if (m_contextActions.isEmpty())
        return;
    QMenu menu(this);
    for (QAction *action : std::as_const(m_contextActions)) {
        if (action)
            menu.addAction(action);
        else
            menu.addSeparator();
    }
    menu.exec(event->reason() == QContextMenuEvent::Keyboard ? viewport()->mapToGlobal(at) : event->globalPos());
}

void StageView::findPendingPushes()
{
    m_pushed.clear();
    const World &world = m_document->world();
    for (int i = 0; i < world.marbleCount(); ++i) {
        if (world.pushPending(i))
            m_pushed.append(i);
    }
}

QList<int> StageView::clickedPushes() const
{
    const World &world = m_document->world();
    QList<int> pending;
    for (int i : m_pushed) {
        if (i < world.marbleCount() && world.pushPending(i))
            pending.append(i);
    }
    return pending;
}

QList<int> StageView::pendingPushes() const
{
    const World &world = m_document->world();
    QList<int> pending = clickedPushes();
    for (const Push &push : world.pushes) {
        if (world.appliesNow(push) && !pending.contains(push.marble))
            pending.append(push.marble);
    }
    return pending;
}

void StageView::drawForeground(QPainter *painter, const QRectF &rect)
{
    Q_UNUSED(rect);
    const QList<int> clicked = clickedPushes();
    if (clicked.isEmpty())
        m_pushed.clear(); // every click's push has acted (a frame ran) or its marble is gone
    const QList<int> pending = pendingPushes();
    m_arrowsShown = !pending.isEmpty();
    m_pushLabels.clear();
    if (pending.isEmpty())
        return;
    // Drawn in viewport pixels, so that the arrow reads the same at any zoom: from the marble's
    // rim along the push, longer for a harder push (10 frames of the velocity it adds, within
    // 24 to 160 px). The latest click has the velocity the frame adds written at its head (one
    // label: several would overlap where marbles are close, and the status bar gave each); a
    // scripted push no click joined is labelled as the scene's (a scene scripts a few).
    const World &world = m_document->world();
    const double scale = transform().m11();
    const QColor ink(190, 40, 120);
    painter->save();
    painter->resetTransform();
    painter->setRenderHint(QPainter::Antialiasing, true);
    QFont font = painter->font();
    font.setBold(true);
    painter->setFont(font);
    for (int i : pending) {
        const auto k = static_cast<std::size_t>(i);
        const Vec2 scripted = world.scriptedPushDue(i);
        const Vec2 a{world.acceleration[k].x + scripted.x, world.acceleration[k].y + scripted.y};
        const double size = std::hypot(a.x, a.y);
        const QPointF u(a.x / size, a.y / size);
        // Pushes that cancel out (Shift+Up, then Shift+Down) leave rounding behind: no arrow
        // labelled "+0.00".
        if (!std::isfinite(u.x()) || !std::isfinite(u.y()) || size < 0.005)
            continue;
        const QPointF centre = mapFromScene(QPointF(world.position[k].x, world.position[k].y));
        const double rim = world.radius[k] * scale;
        const double length = std::clamp(10.0 * size * scale, 24.0, 160.0);
        const QPointF tail = centre + u * rim;
        const QPointF head = tail + u * length;
        const QPointF across(-u.y(), u.x());
        painter->setPen(QPen(ink, 3.0, Qt::SolidLine, Qt::RoundCap));
        painter->drawLine(tail, head - u * 6.0);
        painter->setPen(Qt::NoPen);
        painter->setBrush(ink);
        painter->drawPolygon(QPolygonF{head, head - u * 12.0 + across * 6.0, head - u * 12.0 - across * 6.0});
        const bool byClick = clicked.contains(i);
        if (byClick && i != clicked.back())
            continue;
        painter->setPen(ink);
        // A click on a marble with a scripted push due: one arrow for both, whose label says the
        // scene's part is in it (the "scripted" label went, as if the click had replaced it).
        const bool both = byClick && (scripted.x != 0.0 || scripted.y != 0.0);
        const QString label = both ? tr("+%1 px/frame, scripted %2 in it")
                                         .arg(shownNumber(size, 'f', 2), shownNumber(std::hypot(scripted.x, scripted.y), 'f', 2))
                              : byClick ? tr("+%1 px/frame").arg(shownNumber(size, 'f', 2))
                                        : tr("scripted +%1 px/frame").arg(shownNumber(size, 'f', 2));
        m_pushLabels.append(label);
        const QPointF at = head + u * 8.0;
        const QRectF box = painter->fontMetrics().boundingRect(label);
        // Left of the head when the arrow points left, right of it otherwise; centred vertically.
        double x = u.x() < -0.3 ? at.x() - box.width() : (std::abs(u.x()) <= 0.3 ? at.x() - box.width() / 2 : at.x());
        double y = at.y() + (u.y() > 0.3 ? box.height() * 0.8 : (u.y() < -0.3 ? -box.height() * 0.2 : box.height() * 0.3));
        // Kept inside the view: a marble pushed towards the window's edge still shows its label.
        const QRectF inside = QRectF(viewport()->rect()).adjusted(4, 4, -4, -4);
        const double free = x;
        x = std::clamp(x, inside.left() - box.left(), std::max(inside.left() - box.left(), inside.right() - box.right()));
        if (x != free)
            y += u.y() > 0.0 ? box.height() + 6 : -(box.height() + 6); // beside the arrow's head, not over it
        y = std::clamp(y, inside.top() - box.top(), std::max(inside.top() - box.top(), inside.bottom() - box.bottom()));
        // Where the head's side covers a marble (Figure 11.8's push ends at the small marble, and
        // its label sat on it): above the pushed marble, below it, or beside the arrow's middle,
        // whichever is clear first.
        if (labelCoversMarble(box.translated(x, y))) {
            const QPointF middle = (tail + head) / 2.0;
            const auto offLine = [&](double side) {
                // The box's nearer edge 8 px off the arrow, on that side of it.
                return middle + across * side * (8.0 + std::abs(across.x()) * box.width() / 2.0
                                                  + std::abs(across.y()) * box.height() / 2.0);
            };
            const QPointF centres[] = {centre - QPointF(0, rim + 6.0 + box.height() / 2.0),
                                       centre + QPointF(0, rim + 6.0 + box.height() / 2.0), offLine(-1.0), offLine(1.0)};
            for (const QPointF &boxCentre : centres) {
                const double cx = boxCentre.x() - box.width() / 2.0 - box.left();
                const double cy = boxCentre.y() - box.height() / 2.0 - box.top();
                if (inside.contains(box.translated(cx, cy)) && !labelCoversMarble(box.translated(cx, cy))) {
                    x = cx;
                    y = cy;
                    break;
                }
            }
        }
        // On a light backing: over a crowd the label would cross marbles.
        const QRectF backing = box.translated(x, y).adjusted(-3, -1, 3, 1);
        painter->setPen(Qt::NoPen);
        painter->setBrush(QColor(255, 255, 255, 210));
        painter->drawRoundedRect(backing, 3, 3);
        painter->setPen(ink);
        painter->drawText(QPointF(x, y), label);
    }
    painter->restore();
}

bool StageView::labelCoversMarble(const QRectF &label) const
{
    // In viewport pixels; a marble's disc against the rectangle (nearest point within its radius).
    const World &world = m_document->world();
    const double scale = transform().m11();
    const QRectF area = mapToScene(label.toAlignedRect()).boundingRect();
    for (int i = 0; i < world.marbleCount(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const double r = world.radius[k];
        const Vec2 p = world.position[k];
        if (p.x + r < area.left() || p.x - r > area.right() || p.y + r < area.top() || p.y - r > area.bottom())
            continue;
        const QPointF c = mapFromScene(QPointF(p.x, p.y));
        const double nx = std::clamp(c.x(), label.left(), label.right());
        const double ny = std::clamp(c.y(), label.top(), label.bottom());
        if (std::hypot(c.x() - nx, c.y() - ny) < r * scale)
            return true;
    }
    return false;
}

void StageView::paintEvent(QPaintEvent *event)
{
    ++m_paintCount;
    QGraphicsView::paintEvent(event);
    if (!hasFocus())
        return;
    // The keys (Space, the arrows, Delete) work the stage: a frame in the highlight colour round
    // its edge says so, as a field's focus frame does (from the keyboard the stage took the keys
    // with nothing on screen to show it: a helper's finding).
    QPainter painter(viewport());
    QPen pen(palette().color(QPalette::Highlight), 2.0);
    pen.setJoinStyle(Qt::MiterJoin);
    painter.setPen(pen);
    painter.drawRect(QRectF(viewport()->rect()).adjusted(1.0, 1.0, -1.0, -1.0));
}

void StageView::focusInEvent(QFocusEvent *event)
{
    QGraphicsView::focusInEvent(event);
    viewport()->update();
}

void StageView::focusOutEvent(QFocusEvent *event)
{
    QGraphicsView::focusOutEvent(event);
    viewport()->update();
}

} // namespace marbles
