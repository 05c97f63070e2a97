#pragma once

#include "core/world.h"
#include "ui/scenedocument.h"

#include <QGraphicsView>
#include <QList>
#include <QPoint>
#include <QStringList>
#include <QTransform>

#include <utility>
#include <vector>

class QAction;
class QGraphicsScene;

namespace marbles {

class MarbleFieldItem;
class MarbleItem;
class PinItem;
class TrailItem;
class VectorItem;

/// The stage: a QGraphicsView whose items mirror the document's world. Poses are synced on
/// SceneDocument::stepped(), items are rebuilt on sceneChanged(). The mouse edits through the
/// document: drag marbles and pins, click a marble to push it (the chapter's hitMarble), add
/// marbles or pins with the add tools. Wheel zooms; the view fits the stage until the user zooms.
class StageView : public QGraphicsView {
    Q_OBJECT

public:
    /// What a left click on the stage does.
    enum class Tool { Select, AddMarble, AddPin };
    /// What is selected: nothing, one marble or one pin.
    enum class SelectionKind { None, Marble, Pin };

    /// A press and release closer than the platform's drag distance (QStyleHints::
    /// startDragDistance(), 10 px by default, along x plus along y) is a click, not a drag.
    /// The view's smallest height, px (a screen less tall than 720 px allows less: MainWindow).
    static constexpr int kMinimumHeight = 240;
    /// Radius of a marble made with the add-marble tool, stage px.
    static constexpr double kNewMarbleRadius = 20.0;
    /// Above this many marbles one MarbleFieldItem draws them all (one item per marble and per
    /// vector overlay costs more in the scene than in the drawing); at or below it every marble
    /// is an item of its own. Editing works the same in both modes: the mouse searches the world.
    static constexpr int kBatchThreshold = 400;
    /// Above this many marbles nothing is antialiased but the marble sprites (smooth already)
    /// and the selection rings: grid, walls, pins, vectors and sub-pixel marbles are drawn hard.
    static constexpr int kAntialiasThreshold = 5000;
    /// Above this many marbles trails are not drawn (a status message says so): even at their
    /// shortest, trails of more marbles cost more than the rest of the frame.
    static constexpr int kMaxTrailMarbles = 2000;
    /// Trails are shortened so that all of them together stay within this many segments (each
    /// costs about a microsecond to draw): 90 frames up to 133 marbles, 6 frames at 2,000.
    static constexpr int kTrailSegmentBudget = 12000;
    /// The shortest trail, frames.
    static constexpr int kMinTrailLength = 6;

    /// A view of `document`, which must outlive it.
    explicit StageView(SceneDocument *document, QWidget *parent = nullptr);
    ~StageView() override;

    /// The current tool.
    Tool tool() const { return m_tool; }
    /// Chooses the tool for left clicks.
    void setTool(Tool tool);
    /// Where a marble or pin added at stage point `p` is put: `p` to the whole pixel.
    static Vec2 placeAt(Vec2 p);

    /// Kind of the current selection.
    SelectionKind selectionKind() const { return m_selectionKind; }
    /// Selected marble index, or -1.
    int selectedMarble() const { return m_selectionKind == SelectionKind::Marble ? m_selectionIndex : -1; }
    /// Selected pin index, or -1.
    int selectedPin() const { return m_selectionKind == SelectionKind::Pin ? m_selectionIndex : -1; }
    /// Selects marble i (or nothing with -1).
    void selectMarble(int i);
    /// Selects pin j (or nothing with -1).
    void selectPin(int j);
    /// Selects nothing.
    void clearSelection();
    /// Adds a new marble at stage point `p` (or the nearest free spot) and selects it, as the
    /// Marble tool's click does; where there is no room for one the selection stays. Returns the
    /// document's message.
    QString addMarbleAt(Vec2 p);
    /// Selects the marble `step` after the selected one in scene order (1 next, -1 previous,
    /// round the end; the first or last when none is selected): the keyboard's way to choose.
    void selectNextMarble(int step);
    /// Pushes the selected marble towards `direction` (a unit vector, y down) as a click on its
    /// far edge would; false when no marble is selected.
    bool pushSelected(Vec2 direction);
    /// Draws the marbles of `tints` that have no colour of their own in the colour given (the
    /// plotted marbles in their lines' colours, so that the class sees which line is which);
    /// every other marble without a colour is the stage's blue.
    void setMarbleTints(const QList<QPair<int, QColor>> &tints);
    /// Deletes the selected marble or pin (one undo step).
    void deleteSelection();

    /// Shows or hides the Figure 11.12 vectors.
    void setVectorsVisible(bool visible);
    /// Shows or hides the fading trails.
    void setTrailsVisible(bool visible);
    /// True when the vectors overlay is shown.
    bool vectorsVisible() const { return m_vectorsVisible; }
    /// True when trails are asked for (above kMaxTrailMarbles marbles only the selected one's).
    bool trailsVisible() const { return m_trailsVisible; }
    /// True when trails are asked for but the scene has too many marbles to draw them all: only
    /// the selected marble's is drawn.
    bool trailsSuppressed() const { return m_trailsSuppressed; }
    /// Frames a trail keeps for the current marble count (kTrailSegmentBudget shared out).
    int trailLength() const;

    /// True when the vectors are on but the crowd is zoomed out too far to draw them legibly
    /// (MarbleFieldItem::kMinVectorDevicePx); a status message says so once.
    bool vectorsHiddenByZoom() const;

    /// True when the marbles are drawn by one MarbleFieldItem (more than kBatchThreshold marbles).
    bool isBatched() const { return m_field != nullptr; }
    /// The item drawing every marble in batched mode, or null (owned by the scene).
    MarbleFieldItem *fieldItem() const { return m_field; }

    /// Scales the view so that the whole stage fits, and keeps fitting on resize.
    void fitToStage();
    /// Zooms by `factor` (> 1 zooms in) about the viewport centre; stops fitting on resize.
    void zoomBy(double factor);

    /// The viewport pixel that shows stage point `p` (for tests and tools).
    QPoint viewportPoint(Vec2 p) const;
    /// The stage point under viewport pixel `pos`.
    Vec2 stagePoint(QPointF pos) const;
    /// The stage point where the last context menu was opened.
    Vec2 contextPoint() const { return m_contextPoint; }
    /// Actions for the context menu (created once by the main window, shared with menus and toolbars).
    void setContextActions(const QList<QAction *> &actions);
    /// The labels the last paint wrote at the push arrows' heads ("+3.11 px/frame").
    QStringList pushLabels() const { return m_pushLabels; }

    /// Number of times the viewport was painted (for the display fps).
    qint64 paintCount() const { return m_paintCount; }
    /// Marbles with a push to act on the next frame, each drawn with an arrow along all that
    /// frame adds to its velocity: first those clicked since the last frame (their acceleration
    /// is not zero), in click order, then those the scene's scripted pushes for this frame name.
    QList<int> pendingPushes() const;
    /// Of pendingPushes(), those pushed by a click.
    QList<int> clickedPushes() const;
    /// Whether a rectangle of the viewport (a push's label) covers part of a marble.
    bool labelCoversMarble(const QRectF &label) const;

Q_SIGNALS:
    /// The selection changed.
    void selectionChanged();
    /// A note for the status bar (a refused drop, a moved drop).
    void message(const QString &text);
    /// A note about the current frame (a push to act on the next one): stale once the frame changes.
    void frameMessage(const QString &text);

protected:
    void drawBackground(QPainter *painter, const QRectF &rect) override;
    void drawForeground(QPainter *painter, const QRectF &rect) override;
    void mousePressEvent(QMouseEvent *event) override;
    void mouseMoveEvent(QMouseEvent *event) override;
    void mouseReleaseEvent(QMouseEvent *event) override;
    bool event(QEvent *event) override;
    void mouseDoubleClickEvent(QMouseEvent *event) override;
    bool viewportEvent(QEvent *event) override;
    void wheelEvent(QWheelEvent *event) override;
    void resizeEvent(QResizeEvent *event) override;
    void contextMenuEvent(QContextMenuEvent *event) override;
    void paintEvent(QPaintEvent *event) override;
    void focusInEvent(QFocusEvent *event) override;
    void focusOutEvent(QFocusEvent *event) override;

private:
    /// What the left button is doing on the stage.
    enum class Gesture { None, PressMarble, DragMarble, PressPin, DragPin };

    void rebuild();
    void rebuildMarbleItems(const World &world, int n);
    /// The chapter's click on marble i at p (or the keys' stand-in for one): the push, its arrow
    /// and its status message.
    void pushAt(int i, Vec2 p, bool byKey);
    /// Drops the marble or pin a drag `gesture` held at `target` (the drag has ended); does nothing
    /// for another gesture.
    void dropDragged(Gesture gesture, Vec2 target);
    /// Marble i's colour as drawn: its own, else its tint, else none (the stage's blue).
    QColor drawnColor(const World &world, int i) const;
    /// Hands the tints to the field item (batched marbles).
    void applyTintsToField();
    void updateTrailSuppression();
    void updateVectorNote();
    void syncPoses();
    void sampleTrail();
    void resetTrail();
    /// A new timeline: the trails start again, through the frames Step Back can still go to.
    void replayTrail();
    void updateHighlights();
    void pickAt(Vec2 p);
    void findPendingPushes();
    /// Says the push the status bar gave again where an edit worked it out anew.
    void sayPushRescaled();
    void report(const QString &text);
    void noteLater(const QString &text);
    /// The stage, and the marbles and pins beside it up to twice its size beyond each edge.
    QRectF shownArea(const World &world, const QRectF &stageRect) const;
    /// Says, on a scene opened, how many marbles and pins lie outside the stage (if any).
    void noteOutside();

    SceneDocument *m_document;
    QGraphicsScene *m_scene;
    std::vector<MarbleItem *> m_marbles;
    std::vector<VectorItem *> m_vectors;
    std::vector<PinItem *> m_pins;
    TrailItem *m_trail = nullptr;
    /// The frame the trails were last started over at (shown, or a marble moved by hand), or
    /// stepped back to before it: a new timeline replays them no further back.
    std::int64_t m_trailsSince = 0;
    MarbleFieldItem *m_field = nullptr;
    QList<QPair<int, QColor>> m_tints; // setMarbleTints()

    Tool m_tool = Tool::Select;
    SelectionKind m_selectionKind = SelectionKind::None;
    int m_selectionIndex = -1;
    /// The marble whose leaving took the selection with it, while nothing has been selected
    /// since (its coming back selects it again); -1 when none.
    int m_unselectedByRemoval = -1;
    bool m_vectorsVisible = true;
    bool m_trailsVisible = false;
    bool m_trailsSuppressed = false;
    bool m_vectorNoteShown = false;
    bool m_autoFit = true;

    // Mouse gesture in progress.
    Gesture m_gesture = Gesture::None;
    int m_gestureIndex = -1;
    // The press, where it was on the screen (a drag is told from a click by the mouse's travel on
    // the screen, so a stage that moved or re-fitted under a still mouse does not make one), and
    // the centre of the marble or pin pressed less the point pressed, both on the stage as it lay
    // then: a drag keeps the body at that offset from the mouse, and a click pushes from the point
    // pressed, carried along with the marble.
    QPointF m_pressGlobal;
    Vec2 m_grabOffset;
    Vec2 m_dragTarget; // where the body dragged is (the mouse plus the grab offset)

    Vec2 m_contextPoint;
    QList<int> m_pushed; // marbles clicked since the last frame (pendingPushes() filters them)
    std::pair<int, Vec2> m_saidPush{-1, {}}; // the marble and push the status bar last gave
    bool m_arrowsShown = false; // the last paint drew push arrows
    QStringList m_pushLabels;   // the labels the last paint wrote at the arrows' heads
    QList<QAction *> m_contextActions;
    qint64 m_paintCount = 0;
};

} // namespace marbles
