#pragma once

#include "core/world.h"

#include <QUndoCommand>

#include <string>

namespace marbles {

class SceneDocument;

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
};

} // namespace marbles
