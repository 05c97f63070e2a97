#pragma once

#include "core/world.h"

#include <QString>
#include <QUndoCommand>

#include <cstdint>
#include <string>

namespace marbles {

class SceneDocument;

// A pin edit made mid-run belongs to its frame, as a marble's does (marblecommand.h): undone or
// redone later in the run, it takes the scene back to that frame first, where the frame is kept;
// redone after Step Back went before it, it runs the scene on to that frame first. (It applied
// where the scene was: a pin added at frame 10 and undone at frame 200 left the marbles where
// their bounces off it had sent them, in a run that never had it.)

/// Adds a pin at the end of the pin list.
class AddPinCommand : public QUndoCommand {
public:
    AddPinCommand(SceneDocument *document, Vec2 at);
    void redo() override;
    void undo() override;

private:
    SceneDocument *m_document;
    Vec2 m_at;
    int m_index = -1;
    std::int64_t m_frame = 0; // the frame the pin was added at
    QString m_name;           // its text without the frame
};

/// Removes a pin; undo puts it back at its index.
class RemovePinCommand : public QUndoCommand {
public:
    RemovePinCommand(SceneDocument *document, int pin);
    void redo() override;
    void undo() override;

private:
    SceneDocument *m_document;
    int m_index;
    Vec2 m_at;
    std::string m_extraJson;
    std::int64_t m_frame = 0; // the frame of the delete
    QString m_name;           // its text without the frame
};

/// Moves a pin (a drag: one command pushed on release).
class MovePinCommand : public QUndoCommand {
public:
    MovePinCommand(SceneDocument *document, int pin, Vec2 from, Vec2 to);
    void redo() override;
    void undo() override;

private:
    SceneDocument *m_document;
    int m_index;
    Vec2 m_from;
    Vec2 m_to;
    std::int64_t m_frame = 0; // the frame of the move (the drag's release)
    QString m_name;           // its text without the frame
};

} // namespace marbles
