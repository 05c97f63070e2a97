#pragma once

#include <QString>
#include <QUndoCommand>

#include <cstdint>

namespace marbles {

class SceneDocument;

/// `text`, with the frame a mid-run edit was made at ("Add pin 3 at (40, 560) at frame 25"); as
/// it is at frame 0.
QString atFrame(const QString &text, std::int64_t frame);

/// A structural edit (a marble or pin added or deleted, a pin moved) that belongs to the frame
/// it was made at: undone or redone at another frame, the scene goes to that frame first, as
/// Step Back (or Step) would, where the frame can be reached. Its Undo History text names the
/// frame when it was made mid-run.
class FramedCommand : public QUndoCommand {
protected:
    /// Made at the document's current frame.
    explicit FramedCommand(SceneDocument *document);
    /// Names the edit: `name`, with its frame after it when made mid-run.
    void setName(const QString &name);
    /// For redo: back to the edit's frame when the scene has run on past it and the frame is kept,
    /// on to it when the scene was stepped back before it. Where that frame cannot be reached (no
    /// longer kept), the edit belongs to the frame it is made at, and its text says so. (A delete
    /// redone after Step Back went before it applied at the frame stepped back to, its Undo
    /// History text still naming the other: its undo then went to a frame where the kept frames
    /// had no place for the marble; a regression tester's finding.)
    void toItsFrame();
    /// For undo: back to the edit's frame when the scene has run on past it and the frame is
    /// kept; otherwise the undo applies where the scene is.
    void backToItsFrame();

    SceneDocument *m_document;
    std::int64_t m_frame; // the frame the edit belongs to

private:
    QString m_name; // its text without the frame
};

} // namespace marbles
