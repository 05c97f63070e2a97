#pragma once

#include "core/world.h"
#include "ui/editframe.h"

#include <string>

namespace marbles {

class SceneDocument;

// A pin edit made mid-run belongs to its frame, as a marble's does (FramedCommand). (It applied
// where the scene was: a pin added at frame 10 and undone at frame 200 left the marbles where
// their bounces off it had sent them, in a run that never had it.)

/// Adds a pin at the end of the pin list.
class AddPinCommand : public FramedCommand {
public:
    AddPinCommand(SceneDocument *document, Vec2 at);
    void redo() override;
    void undo() override;

private:
    Vec2 m_at;
    int m_index = -1;
};

/// Removes a pin; undo puts it back at its index.
class RemovePinCommand : public FramedCommand {
public:
    RemovePinCommand(SceneDocument *document, int pin);
    void redo() override;
    void undo() override;

private:
    int m_index;
    Vec2 m_at;
    std::string m_extraJson;
};

/// Moves a pin (a drag: one command pushed on release).
class MovePinCommand : public FramedCommand {
public:
    MovePinCommand(SceneDocument *document, int pin, Vec2 from, Vec2 to);
    void redo() override;
    void undo() override;

private:
    int m_index;
    Vec2 m_from;
    Vec2 m_to;
};

} // namespace marbles
