#pragma once

#include "core/world.h"
#include "ui/history.h"
#include "ui/scenedocument.h"

#include <QObject>
#include <QPointer>
#include <QColor>
#include <QList>
#include <QPair>
#include <QString>

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

class QGraphicsScene;

namespace marbles {

class MarbleFieldItem;

/// "Compare in the app": a second model run beside the document's own, on the same scene, so
/// that a class can watch two models drift apart (the book's approximation against the exact
/// physics, say). Off by default; while off it holds no world and does no work.
///
/// The comparison world is a copy of the document's world with only params.model changed. The
/// rule that keeps the two side by side, as a teacher sees it:
/// - **Same start.** Choosing a comparison model copies the scene exactly as it is now, so both
///   models start from the same positions and velocities at the same frame.
/// - **Same frames.** Every frame the document simulates, the comparison simulates one frame of
///   its own model. Scripted pushes are part of the scene and act in both; a click on a marble
///   gives the comparison marble the same push.
/// - **Step back together.** Step Back (and Back to Start) take the comparison back to the same
///   frame as the document, in its own state there (it keeps its own step-back history): its
///   ghosts and plotted lines go on from where they were, and the gaps are those of that frame.
///   When it did not keep that frame (it started later, or the history's budget forgot it), it
///   restarts there instead, as below.
/// - **Restart on anything else.** Opening a file or a preset, and any edit (moving, adding or
///   removing a marble or pin, changing a parameter, undo, redo) restart the comparison from the
///   document's state at that moment: the gap goes back to 0, and "largest gap" counts from that
///   frame (startFrame()). An edit that keeps the marbles (a parameter, a marble's place, speed
///   or size) keeps the comparison's earlier frames: Step Back past it returns to the comparison
///   as it was before it, its gaps and its start with it. So does a marble deleted mid-run (or
///   its delete undone) where the document's frames follow it: the comparison's frames lose the
///   marble (or take it back) as the document's do, and their gaps are measured again; the
///   delete undone gives the comparison back its own state at that frame. A marble added mid-run
///   starts it again there, its frames before set aside, and the add undone where it was made
///   gives them back, with the comparison's own state and start. While a marble is
///   held with the mouse the comparison follows the document every frame, as the hand moves
///   that marble outside either model's physics.
/// - **When the comparison model cannot run.** If the scene's parameters are invalid for the
///   comparison model (friction >= 1 is valid for the book model only), the comparison waits,
///   with the reason in problem(), and starts again at the next restart once they are valid. If
///   the comparison model leaves finite numbers, it stops at that frame with the reason in
///   problem(); the document's run goes on.
///
/// The gap is measured between marbles of the same index at the same frame:
/// gap = max over marbles i of |p_i(document) - p_i(comparison)|, in stage px.
class CompareRun : public QObject {
    Q_OBJECT

public:
    /// Z value of the ghost outlines on the stage: above marbles (0) and pins (1), below the
    /// collision vectors (2), so the solid marbles stay visible through the dashed outlines.
    static constexpr double kGhostZValue = 1.5;

    /// Compares against `document`, which must outlive this object.
    explicit CompareRun(SceneDocument *document, QObject *parent = nullptr);
    ~CompareRun() override;

    /// Starts comparing with `model` from the document's current state (or restarts when it is the
    /// model already compared). Any model may be chosen, the document's own included (its gap is 0).
    void setModel(ModelKind model);
    /// Stops comparing and frees the comparison world.
    void stop();
    /// The ghosts' colours for marbles without one of their own (StageView::setMarbleTints()).
    void setTints(const QList<QPair<int, QColor>> &tints);
    /// True when a comparison model is chosen (even while it waits or has stopped with a problem).
    bool isActive() const { return m_model.has_value(); }
    /// The comparison model; only meaningful while isActive().
    ModelKind model() const { return m_model.value_or(ModelKind::Book); }
    /// True while the comparison world runs in step with the document (active and no problem).
    bool isTracking() const { return m_world != nullptr && m_problem.isEmpty(); }
    /// Why the comparison is not running now ("" when it runs or is off).
    QString problem() const { return m_problem; }

    /// The comparison world while isTracking(), else null. Valid until the next restart or stop().
    const World *world() const { return isTracking() ? m_world.get() : nullptr; }
    /// Frame the comparison last (re)started from.
    std::int64_t startFrame() const { return m_startFrame; }
    /// The frames it started again at, oldest first, since its first start (its kept frames run
    /// through them: edits, and marbles removed or put back, that Step Back can go past).
    std::vector<std::int64_t> restartFrames() const;
    /// The comparison marbles' velocities at `frame` (the current one, or one it keeps for
    /// stepping back), or null when it has no such frame or is not tracking.
    const std::vector<Vec2> *velocitiesAt(std::int64_t frame) const;

    /// Position gap at the latest frame, px: max over marbles of |p_document - p_comparison|.
    double currentGapPx() const { return m_currentGap; }
    /// Marble with the gap at the latest frame, or -1 when every gap is 0.
    int currentGapMarble() const { return m_currentGapMarble; }
    /// Largest gap since startFrame(), px.
    double largestGapPx() const { return m_largestGap; }
    /// Marble that had the largest gap, or -1 while the largest gap is 0.
    int largestGapMarble() const { return m_largestGapMarble; }
    /// Frame at which the largest gap happened (startFrame() while it is 0).
    std::int64_t largestGapFrame() const { return m_largestGapFrame; }
    /// Frames whose own gap is kept for stepping back: those its history can return to (the
    /// gaps of older frames leave only their largest).
    std::size_t keptGapCount() const { return m_gaps.size(); }

    /// One line for the status bar: "Compare: exact - largest gap 12.3 px (marble 2, frame 57)",
    /// ending " since frame S" after a restart at frame S > 0; "" while off.
    QString summary() const;

    /// Draws the comparison marbles as dashed ghost outlines in `scene` (the stage's scene; null
    /// removes them). The ghosts exist only while isTracking(). The scene may be destroyed first.
    void setStage(QGraphicsScene *scene);
    /// The ghost item in the stage, or null while there are no ghosts (for tests).
    const MarbleFieldItem *ghostItem() const { return m_ghost; }

Q_SIGNALS:
    /// The comparison was switched on, switched off, or changed model.
    void modelChanged();
    /// The comparison world was copied afresh from the document (the gap is 0 again), or it
    /// stopped or started waiting (problem() changed).
    void restarted();
    /// The comparison simulated one frame beside the document's (emitted once per frame).
    void advanced();
    /// The undo of an edit at `frame` gave the comparison back its own state there: it no
    /// longer starts again at that frame (startFrame() and restartFrames() are as before the edit).
    void restartTakenBack(std::int64_t frame);

private:
    /// The largest position gap at one frame, and the marble that had it (-1: none).
    struct Gap {
        double px = 0.0;
        int marble = -1;
    };

    struct BeforeEdit; // below
    struct Removed;

    /// The largest distance between the marbles of the same index in `a` and `b`.
    static Gap largestGap(const std::vector<Vec2> &a, const std::vector<Vec2> &b);
    void restart();
    /// An edit that keeps the marbles, at the current frame, or one that removed or put back a
    /// marble the kept frames followed: the comparison starts again from the scene as it is, but
    /// keeps its frames before it (restart() otherwise).
    void onSceneChanged(SceneDocument::Change change);
    /// The document's kept frames lost marble i (a delete): the comparison's lose it too, so that
    /// Step Back past the delete returns to the comparison as it was; its part is kept for an undo.
    void onMarbleRemoved(int i);
    /// The document's kept frames took marble i back (a delete undone): the comparison's take
    /// back the part its own frames lost.
    void onMarbleInserted(int i);
    /// The document's kept frames before a marble added mid-run were set aside: the comparison's
    /// are too, and it takes the marble and starts again there (as after any edit), so that the
    /// add's undo can give back its frames and its state before it.
    void onMarbleAdded(int i);
    /// The add of marble i undone where it was made, the document's frames before it back: the
    /// comparison's come back too, with its own state and start before the add.
    void onAddUndone(int i);
    /// A new timeline restarts the comparison, except after a marble its kept frames followed.
    void onTimelineReset();
    /// Measures again the gaps of the kept frames, from both histories (a marble removed or put
    /// back changes them).
    void remeasureKeptGaps();
    /// The current and largest gaps taken again from the gaps kept up to the current frame (and
    /// the largest of those forgotten), since the current start.
    void retakeGaps();
    /// Marble i put back at the current frame: the comparison takes the state it had (at the
    /// removal's frame, or at an earlier one its kept frames hold); false when it has none.
    bool restoreOwnState(int i, const Removed &removed);
    /// The comparison as it is now, where marble i is about to be removed or added.
    BeforeEdit beforeEdit(int i) const;
    /// True when the comparison started again at `edit`'s frame since (the edit's own restart).
    bool startedAgainAt(const BeforeEdit &edit) const;
    /// Its start and earlier starts back to what they were before `edit`.
    void takeBackStart(const BeforeEdit &edit);
    /// The comparison's own state `own` at the current frame, where an edit is undone (with the
    /// document's clicks still to act): the gap of this frame measured again, the gaps retaken.
    void takeOwnState(World own);
    void rewindTo(std::int64_t frame);
    void onFrameAdvanced();
    void onStepped();
    void measureGap();
    /// No gap yet: the current and the largest are 0, the largest "at" `frame`.
    void resetGaps(std::int64_t frame);
    /// No gap kept: the next one measured is that of frame start + 1.
    void clearGapList(std::int64_t start);
    /// `gap` is the gap at `frame` (the newest so far): the current one, and the largest if larger.
    void takeGap(const Gap &gap, std::int64_t frame);
    void updateGhost();
    void removeGhost();

    SceneDocument *m_document;
    std::optional<ModelKind> m_model;
    std::unique_ptr<World> m_world;
    FrameHistory m_history;    ///< the comparison's own frames since startFrame(), for stepping back
    /// The gap at each frame it can still step back to (m_firstGapFrame on), oldest first; the
    /// frames the history forgot leave only their largest gap, in m_earlierLargest.
    std::deque<Gap> m_gaps;
    std::int64_t m_firstGapFrame = 1;
    Gap m_earlierLargest;
    std::int64_t m_earlierLargestFrame = 0;
    QString m_problem;
    /// The comparison where a marble was removed or added mid-run, for the edit's undo.
    struct BeforeEdit {
        int marble = -1;
        std::int64_t frame = 0;        ///< the frame of the edit
        World before;                  ///< the comparison at that frame, before the edit
        std::int64_t startFrame = 0;   ///< its start then
        std::size_t earlierStarts = 0; ///< and how many earlier starts it had
    };
    /// The comparison's part of the kept frames of each marble they lost, newest last, for an undo
    /// that puts the marble back (onMarbleRemoved(), onMarbleInserted()).
    struct Removed : BeforeEdit {
        FrameHistory::MarbleTrack track; ///< its part of the comparison's kept frames
    };
    std::vector<Removed> m_removed;
    /// For each marble added mid-run, newest last, what its undo gives back (onMarbleAdded(),
    /// onAddUndone()).
    struct Added : BeforeEdit {
        std::uint64_t setAside = 0; ///< the comparison's frames set aside there
    };
    std::vector<Added> m_added;
    /// For each edit of the marbles or parameters that started the comparison again where it was
    /// (onSceneChanged()), newest last, what its undo there gives back (the oldest forgotten past
    /// 64 MiB of worlds). An edit that follows
    /// another at the same frame, with the comparison still on the first one's start, keeps no
    /// world: the comparison before it was the scene itself.
    struct EditRestart : BeforeEdit {
        std::uint64_t serial = 0; ///< the edit's (SceneDocument::EditCause)
        bool copyOfScene = false; ///< `before` is left empty: the scene's own state, in the model
    };
    std::vector<EditRestart> m_editRestarts;
    /// Notes, before the comparison starts again from the scene at this frame, what `serial`'s
    /// undo gives back.
    void rememberEditRestart(std::uint64_t serial);
    /// True when `edit`'s start is still among the comparison's starts.
    bool keepsStartOf(const EditRestart &edit) const;
    /// The undo of edit `serial` at the frame it was made, the comparison still on the start it
    /// made: the comparison as it was before it. False (nothing changed) otherwise.
    bool takeBackEditRestart(std::uint64_t serial);
    /// The kept frames followed a marble removed or put back: the edit's sceneChanged() keeps them,
    /// and its timelineReset() does not restart.
    bool m_followedStructure = false;
    /// A marble put back where the comparison has its own state for it (onMarbleInserted()): the
    /// edit's sceneChanged() keeps that state rather than starting again from the scene.
    bool m_restoredOwnState = false;

    std::int64_t m_startFrame = 0;
    /// The frames earlier starts were made at, oldest first: after an edit the comparison starts
    /// again, and stepping back past it goes back to the comparison before it, as it was.
    std::vector<std::int64_t> m_earlierStarts;
    double m_currentGap = 0.0;
    int m_currentGapMarble = -1;
    double m_largestGap = 0.0;
    int m_largestGapMarble = -1;
    std::int64_t m_largestGapFrame = 0;

    QPointer<QGraphicsScene> m_stage;
    MarbleFieldItem *m_ghost = nullptr;
    QList<QPair<int, QColor>> m_tints; // setTints()
};

} // namespace marbles
