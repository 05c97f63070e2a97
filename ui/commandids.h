#pragma once

namespace marbles {

/// QUndoCommand::id() of the commands that merge with their successor (spin box scrubbing,
/// slider drags): consecutive edits of the same field become one undo step.
enum class CommandId : int {
    EditMarblePosition = 1,
    EditMarbleVelocity,
    EditMarbleRadius,
    EditMarbleMass,
    SetParam,
};

} // namespace marbles
