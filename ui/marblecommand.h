#pragma once

#include "core/world.h"
#include "ui/commandids.h"
#include "ui/editframe.h"
#include "ui/history.h"
#include "ui/worldedit.h"

#include <QUndoCommand>

#include <optional>
#include <vector>

namespace marbles {

class SceneDocument;

/// The editable properties of one marble, as an edit sets them.
struct MarbleState {
    Vec2 position;
    Vec2 velocity;
    Vec2 acceleration;
    double radius = 0.0;
    double mass = 0.0;
    bool hasMass = false;

    /// Reads marble i of `world`.
    static MarbleState of(const World &world, int i);
    /// Writes this state into marble i of `world`.
    void applyTo(World &world, int i) const;
    /// Writes into marble i of `world` only what this state has that `other` has not (an edit's
    /// change, where the rest of the marble has moved on): its motion too (position, velocity,
    /// acceleration) when `motion`, else only its radius and mass.
    void applyChangesTo(World &world, int i, const MarbleState &other, bool motion) const;
};

/// Changes one marble's properties (a drag, an inspector edit). With a merge id, consecutive
/// edits of the same field of the same marble merge into one undo step.
class SetMarbleCommand : public QUndoCommand {
public:
    /// `mergeId` is a CommandId, or nothing for a command that never merges (a drag). `frame` is
    /// the frame `before` is the state at, when not the current one (a drag during a run: where
    /// the marble was taken hold of).
    SetMarbleCommand(SceneDocument *document, int marble, const MarbleState &before, const MarbleState &after,
                     const QString &text, std::optional<CommandId> mergeId = std::nullopt,
                     std::optional<std::int64_t> frame = std::nullopt);
    void redo() override;
    void undo() override;
    int id() const override;
    bool mergeWith(const QUndoCommand *other) override;

private:
    SceneDocument *m_document;
    int m_marble;
    MarbleState m_before;
    MarbleState m_after;
    std::optional<CommandId> m_mergeId;
    std::int64_t m_frame = 0;     // the frame the edit was made at (redo's)
    std::int64_t m_undoFrame = 0; // the frame `m_before` is the state at (undo's)
    std::uint64_t m_frameMoves = 0; // the document's frameMoves() when the edit was made
    std::uint64_t m_serial; // the document's newEditSerial() for it (CompareRun keeps what its undo gives back)
    /// Writes `state` (whose counterpart is `other`) at the edit's frame, running the scene on to
    /// it when `mayRunOn`; see the .cpp.
    /// Returns whether the marble or the pushes changed (after any move to `frame`).
    bool applyAtItsFrame(std::int64_t frame, const MarbleState &state, const MarbleState &other, bool mayRunOn,
                         const std::vector<Push> &pushes);
    // The scene's scripted pushes before and after the move (filled on the first redo), so
    // that undo puts the click points back bit for bit.
    bool m_pushesKept = false;
    std::vector<Push> m_pushesBefore;
    std::vector<Push> m_pushesAfter;
};

/// Names a marble ("" takes its name away): what the Inspector, the plot's legend and the saved
/// scene call it. Nothing moves, so no frame is returned to, and the run goes on (Change::Names).
class RenameMarbleCommand : public QUndoCommand {
public:
    RenameMarbleCommand(SceneDocument *document, int marble, const std::string &before, const std::string &after,
                        const QString &text);
    void redo() override;
    void undo() override;

private:
    void apply(const std::string &name);
    SceneDocument *m_document;
    int m_marble;
    std::string m_before;
    std::string m_after;
};

/// Adds a marble at the end of the scene order. Undone or redone later in the run, it takes the
/// scene back to the frame it was made at first, where that frame is kept; redone earlier, it
/// runs the scene on to that frame first (as SetMarbleCommand). The frames kept for Step Back
/// before the add, which have no place for the marble, are set aside, and its undo there gives
/// them back.
class AddMarbleCommand : public FramedCommand {
public:
    AddMarbleCommand(SceneDocument *document, const MarbleRecord &record);
    void redo() override;
    void undo() override;

private:
    MarbleRecord m_record;
    int m_index = -1;
    std::uint64_t m_setAside = 0; // the step-back frames set aside there (FrameHistory::insertMarble())
};

/// Removes a marble; undo puts it back at its index, with the scripted pushes that named it.
/// Undone or redone later in the run, it takes the scene back to the frame of the delete first,
/// where that frame is kept: the marble came back where it had been deleted, frames later, among
/// marbles that had moved on without it. Redone earlier (after Step Back past it), it runs the
/// scene on to that frame first.
class RemoveMarbleCommand : public FramedCommand {
public:
    RemoveMarbleCommand(SceneDocument *document, int marble);
    void redo() override;
    void undo() override;

private:
    int m_index;
    MarbleRecord m_record;
    std::vector<Push> m_pushes;
    FrameHistory::MarbleTrack m_track; // its part of the timeline's first frame and step-back frames
};

} // namespace marbles
