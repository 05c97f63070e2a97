#pragma once

#include "core/world.h"
#include "ui/history.h"

#include <QElapsedTimer>
#include <QObject>
#include <QString>
#include <QStringList>
#include <QUndoStack>

namespace marbles {

/// The open scene: owns the World, its undo stack and the step-back history, and is the only
/// thing that changes the world. Views and docks mirror it through its signals.
/// Every edit is a QUndoCommand pushed on undoStack(); simulating and pushing marbles are not
/// edits (they are the experiment itself, and stepping back undoes them).
class SceneDocument : public QObject {
    Q_OBJECT

public:
    /// What an applied edit touched, so that listeners rebuild only what they must.
    enum class Change {
        Marbles,   ///< marble properties (position, velocity, radius, mass); same marbles
        Structure, ///< marbles or pins added or removed
        Params,    ///< params or stage
        Scene,     ///< a whole new scene (New, Open, a preset, a recovered autosave)
        Names,     ///< marbles' names only: nothing moves, the run and its timeline go on as they were
    };

    explicit SceneDocument(QObject *parent = nullptr);

    /// The simulated world. Do not store the reference across edits that replace the scene.
    const World &world() const { return m_world; }
    /// The document's undo stack (owned by the document).
    QUndoStack *undoStack() { return &m_undoStack; }

    /// Replaces the scene with `world` (at frame 0), clears undo and history; `fileName` may be empty.
    void resetScene(const World &world, const QString &fileName = {});
    /// What a scene file held that was read without being used.
    struct ReadNotes {
        /// The loader's lines on the keys it does not read ("lesson.marbles.json: params.Friction:
        /// not a key of params, so not used (did you mean friction?)").
        QStringList unusedKeys;
        /// Some of them look like a known key misspelt: the scene most likely meant that key.
        bool misspelt = false;
    };
    /// Reads and checks a scene file without touching any document; on error returns false and sets
    /// `error` to the loader's message, which names the file. On success, `notes` (if given) says
    /// what the file held that is not used.
    static bool readSceneFile(const QString &path, World &out, QString *error, ReadNotes *notes = nullptr);
    /// Loads a scene file; on error returns false, leaves the scene untouched and sets `error`
    /// to the loader's message, which names the file.
    bool openFile(const QString &path, QString *error);
    /// Which frame of the run a save writes: the one shown, or the start of the run (worldAtStart()).
    enum class SavedFrame { Shown, Start };
    /// Writes the scene atomically (QSaveFile); on success the document is clean and named `path`.
    /// The frame shown, saved in the middle of the run, starts the run again there (timelineReset()),
    /// as the file opens there: Home comes back to it, Step Back goes no further, and the edits
    /// before it leave the undo stack.
    bool saveFile(const QString &path, QString *error, SavedFrame which = SavedFrame::Shown);
    /// Why the scene cannot be saved as it is now ("at frame 812, marble 3's place or velocity is
    /// not a finite number, which a scene file cannot hold"), or empty when it can.
    QString unsavableReason() const;
    /// The same for `world`.
    static QString unsavableReasonOf(const World &world);
    /// Path of the scene file, or empty for an unsaved scene.
    QString fileName() const { return m_fileName; }
    /// Name shown to the user: the file's name, or "Untitled".
    QString displayName() const;
    /// True when there are edits not saved yet.
    bool isModified() const { return !m_undoStack.isClean() || m_dirtyWithoutUndo; }
    /// Marks the scene modified without an undo step (a scene recovered from an autosave).
    void markModified();

    /// Simulates one frame. Returns the core's result; on a non-finite state emits simulationFailed().
    StepResult step();
    /// Simulates up to `frames` frames, stopping at a failure; returns the frames done.
    int advance(int frames);
    /// True when the frame before the current one is kept.
    bool canStepBack() const { return m_history.canStepBack(m_world); }
    /// Restores the previous frame exactly; false when it is not kept.
    bool stepBack();
    /// Restores the first frame of the timeline (frame 0 unless marbles were added or removed
    /// since), with the edits made while it was shown; an edit at a later frame does not change it.
    /// The clicks' pushes that acted since are not part of it (pushesLeftByRewind()).
    bool rewind();
    /// The frames at which a click's push acted (the step from that frame took it) between the
    /// frame the last rewind() went back to and the frame it left, oldest first: run on from there,
    /// the scene goes without them (a click is not an edit). Step Back keeps a push clicked at the
    /// frame it goes back to, and leaves the one waiting at the frame it left (pendingPushCount()).
    const std::vector<std::int64_t> &pushesLeftByRewind() const { return m_pushesLeftByRewind; }
    /// Takes the scene to `frame`: back through the kept frames, as Step Back does, or on by
    /// simulating, as Step does (the same bits, the physics being deterministic); true when the
    /// scene is at `frame` now, false (nothing changed) when it cannot get there: a frame no
    /// longer kept, or one beyond a run that failed.
    bool goToFrame(std::int64_t frame);
    /// Whether every marble's position and velocity are finite numbers.
    bool allFinite() const { return m_world.firstNonFiniteMarble() < 0; }
    /// Frame number that rewind() returns to.
    std::int64_t startFrame() const { return m_history.startFrame(); }
    /// For the commands that add or remove marbles, after they did it to the world: marble i
    /// joined the scene with `track` as its part of the timeline (or left it, and its part is
    /// returned, for an undo to give back), so that rewind() still reaches frame 0 with the scene
    /// as edited. Step Back's kept frames lose a marble removed, and take it back with its track
    /// when it is put back where it was; a marble added sets them aside (the number returned,
    /// 0 when none were), and its undo takes them back: marbleRemoved() given that number, where
    /// the add was made, so that Step Back goes on past it. Plots start over.
    std::uint64_t marbleInserted(int i, const FrameHistory::MarbleTrack &track);
    FrameHistory::MarbleTrack marbleRemoved(int i, std::uint64_t setAside = 0);
    /// A copy of the world as rewind() would make it: the scene with every edit, at the start of
    /// its timeline (its scripted pushes all to come), what an autosave keeps.
    World worldAtStart() const
    {
        World start = m_world;
        m_history.restoreStart(start);
        return start;
    }
    /// The step-back history (how many frames it keeps and their bytes).
    const FrameHistory &history() const { return m_history; }
    /// Mean time of the model's step per simulated frame over the recent frames (without the
    /// undo history's recording), ms.
    double physicsMsPerFrame() const { return m_physicsMsPerFrame; }
    /// How often the frame shown has changed (a frame run, Step Back, a rewind, a jump): edits of
    /// one field merge into one undo step only with no change between them.
    std::uint64_t frameMoves() const { return m_frameMoves; }
    /// Takes back the clicks' pushes still to act (a click on the wrong marble): they will not
    /// act. Returns how many marbles had one; a click is not an edit, so Ctrl+Z cannot.
    int takeBackPushes();
    /// How many marbles have a click's push waiting for the next frame.
    int pendingPushCount() const;

    /// The chapter's click: World::push on marble i at `at` (stage px); acts on the next frame.
    void pushMarble(int i, Vec2 at);

    /// Starts holding marble i with the mouse: it stays where it is held, at zero velocity, while frames run.
    void beginHold(int i);
    /// Moves the held marble to `p` (stage px).
    void moveHeld(Vec2 p);
    /// Drops the held marble at `p`: moved to the nearest free spot and pushed as one undo step;
    /// at rest if frames ran while it was held, else with the velocity and push it had.
    /// Returns "" when it lands at `p`, else a line for the status bar: that it was moved to the
    /// nearest free spot, or why the drop was refused (the marble then goes back to where it was
    /// picked up, and no undo step is made).
    QString endHold(Vec2 p);
    /// Index of the held marble, or -1.
    int heldMarble() const { return m_held; }

    /// Starts dragging pin j.
    void beginPinDrag(int j);
    /// Moves the dragged pin to `q`.
    void movePinDrag(Vec2 q);
    /// Drops the dragged pin at `q`, or the nearest free spot (one undo step); returns "" when it
    /// lands at `q`, else that it was moved to the nearest free spot or why it was refused.
    QString endPinDrag(Vec2 q);
    /// Index of the dragged pin, or -1.
    int draggedPin() const { return m_draggedPin; }

    /// Adds a marble of radius `r` px at (or nearest free spot to) `p`; returns "", why not, or
    /// that it was placed at the nearest free spot.
    QString addMarble(Vec2 p, double r);
    /// Removes marble i.
    void removeMarble(int i);
    /// Adds a pin at (or nearest free spot to) `q`; returns "", why not, or that it was placed at
    /// the nearest free spot.
    QString addPin(Vec2 q);
    /// Removes pin j.
    void removePin(int j);
    /// Sets marble i's position; refused (with the reason) when it would overlap something.
    QString setMarblePosition(int i, Vec2 p);
    /// Sets marble i's velocity, px/frame.
    QString setMarbleVelocity(int i, Vec2 v);
    /// Sets marble i's radius (> 0 px); its derived mass follows.
    QString setMarbleRadius(int i, double r);
    /// Names marble i (spaces at the ends dropped; "" takes the name away), as one undo step.
    /// Returns "" or why not (no such marble, a name longer than 40 characters).
    QString setMarbleName(int i, const QString &name);
    /// Gives marble i an explicit mass (> 0), or 0 for massScale * radius.
    QString setMarbleMass(int i, double m);
    /// Applies a setting as setParam() takes it ("friction", "0.2"); refused when invalid.
    QString setParam(const QString &key, const QString &value);

    /// For undo commands: the world to change. Call applyChange() afterwards.
    World &editableWorld() { return m_world; }
    /// For undo commands: tells the listeners what an edit changed.
    void applyChange(Change change);

    /// Which edit a change comes from, for the listeners that keep something for its undo
    /// (CompareRun): the edit's serial (0: not told) and whether it is being undone.
    struct EditCause {
        std::uint64_t serial = 0;
        bool undoing = false;
        /// The edit left the scene as it was (undone where the run shown never had it: stepped
        /// back before its frame, or past it and on again).
        bool changedNothing = false;
    };
    /// A serial for a new edit command (never 0).
    std::uint64_t newEditSerial() { return ++m_editSerials; }
    /// applyChange(), its listeners told that it is `cause`'s (currentEdit()).
    void applyChange(Change change, EditCause cause);
    /// While an edit's change is told (sceneChanged()), the edit; else {0, false}.
    EditCause currentEdit() const { return m_currentEdit; }

Q_SIGNALS:
    /// One frame was simulated (emitted once per frame, before stepped()).
    void frameAdvanced();
    /// The dynamic state changed (frames ran, a jump, a push, a held marble moved): re-sync poses.
    void stepped();
    /// The scene changed beyond the dynamic state (new scene, edit, undo): rebuild.
    void sceneChanged(marbles::SceneDocument::Change change);
    /// The sequence of frames restarted (a new scene, or an edit or undo that added or removed
    /// marbles): plots and trails start over.
    void timelineReset();
    /// An edit or undo that kept the marbles (a parameter, a marble's place, speed or size, a
    /// pin): the frames recorded so far still hold (Step Back goes back through them), the
    /// current frame's state changed.
    void timelineEdited();
    /// The timeline went back to `frame` (Step Back, Rewind): what was recorded of later frames
    /// is void, what was recorded of `frame` and earlier still holds.
    void timelineRewound(std::int64_t frame);
    /// Marble i left the scene (deleted, or an add undone): the later marbles are renumbered.
    /// Emitted before the edit's sceneChanged(Structure).
    void marbleRemovedAt(int i);
    /// A marble joined the scene at index i (added, or a delete undone): the marbles from i on
    /// are renumbered. Emitted before the edit's sceneChanged(Structure).
    void marbleInsertedAt(int i);
    /// Marble i left the scene (deleted, or an add undone) and the step-back frames lost it: Step
    /// Back still goes back through them, without it. Emitted before the sceneChanged(Structure)
    /// and timelineReset() of the edit.
    void timelineMarbleRemoved(int i);
    /// Marble i came back (a delete undone) and the step-back frames took it back: Step Back goes
    /// back through them with it. Emitted before the edit's sceneChanged(Structure) and
    /// timelineReset().
    void timelineMarbleInserted(int i);
    /// Marble i was added mid-run, and the step-back frames before it, which have no place for
    /// it, were set aside for its undo (Step Back stops at the add). Emitted before the edit's
    /// sceneChanged(Structure) and timelineReset().
    void timelineMarbleAdded(int i);
    /// The add of marble i undone where it was made: it left the scene, and the frames set aside
    /// at the add came back (Step Back goes on past it). Emitted where timelineMarbleRemoved()
    /// would be, in its place.
    void timelineAddUndone(int i);
    /// The simulation left finite numbers; `message` names the frame and the marble.
    void simulationFailed(const QString &message);
    /// The exact model held marbles at rest to finish a frame where energy should have been
    /// kept (heldMarblesBreakEnergy()); `message` says which frame and how many.
    void marblesHeld(const QString &message);
    /// The file name changed (open, save as, new).
    void fileNameChanged(const QString &fileName);
    /// Whether there are unsaved edits changed.
    void modificationChanged(bool modified);

private:
    void applyHold();
    /// After the world went back to an earlier frame (Step Back, Home, an undo's return): the
    /// held marble stays held, and the views hear of it.
    void announceRewound();
    void setFileName(const QString &fileName);
    void emitModification();

    World m_world;
    QUndoStack m_undoStack;
    FrameHistory m_history;
    QString m_fileName;
    bool m_dirtyWithoutUndo = false;
    bool m_marblesRenumbered = false; // marbleInserted() or marbleRemoved() since the last applyChange()
    bool m_lastModified = false;

    int m_held = -1;
    Vec2 m_heldAt;
    Vec2 m_holdStartPosition;
    Vec2 m_holdStartVelocity;
    Vec2 m_holdStartAcceleration;
    std::int64_t m_holdStartFrame = 0; ///< the frame the hold began at (paused: the same at the drop)

    int m_draggedPin = -1;
    Vec2 m_pinStart;

    double m_physicsMsPerFrame = 0.0;
    std::uint64_t m_frameMoves = 0;
    /// The frames of this run at which a click's push acted, oldest first (dropped from a frame on
    /// when the scene goes back to it, where a push clicked is pending again or gone).
    std::vector<std::int64_t> m_pushFrames;
    std::vector<std::int64_t> m_pushesLeftByRewind;
    std::uint64_t m_editSerials = 0;
    EditCause m_currentEdit;
};

} // namespace marbles
