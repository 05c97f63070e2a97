#pragma once

#include <QString>

#include <cstdint>

class QUndoCommand;

namespace marbles {

class SceneDocument;

// An edit made mid-run belongs to the frame it was made at: undone or redone at another frame,
// the scene goes to that frame first, as Step Back (or Step) would, where the frame can be
// reached. The marble and pin commands share these.

/// `text`, with the frame a mid-run edit was made at ("Add pin 3 at (40, 560) at frame 25"); as
/// it is at frame 0.
QString atFrame(const QString &text, std::int64_t frame);

/// Back to `frame`, where a structural edit was made, when the scene has run on past it and the
/// frame is kept; otherwise the edit applies where the scene is.
void backToItsFrame(SceneDocument *document, std::int64_t frame);

/// To `frame`, where a structural edit was made, for its redo: back to it when the scene has run
/// on past it and the frame is kept, on to it when the scene was stepped back before it. Where
/// that frame cannot be reached (no longer kept), the edit belongs to the frame it is made at:
/// `frame` becomes it, and `command`'s text (`name` at that frame) says so.
void toItsFrame(SceneDocument *document, std::int64_t &frame, QUndoCommand &command, const QString &name);

} // namespace marbles
