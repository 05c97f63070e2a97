#include "ui/marblecommand.h"

#include "ui/editframe.h"
#include "ui/scenedocument.h"

#include <QCoreApplication>

#include <cassert>
#include <utility>

namespace marbles {

MarbleState MarbleState::of(const World &world, int i)
{
    MarbleState s;
    s.position = world.position[i];
    s.velocity = world.velocity[i];
    s.acceleration = world.acceleration[i];
    s.radius = world.radius[i];
    s.mass = world.mass[i];
    s.hasMass = world.info[i].hasMass;
    return s;
}

void MarbleState::applyChangesTo(World &world, int i, const MarbleState &other, bool motion) const
{
    if (motion && !(position == other.position))
        world.position[i] = position;
    if (motion && !(velocity == other.velocity))
        world.velocity[i] = velocity;
    if (motion && !(acceleration == other.acceleration))
        world.acceleration[i] = acceleration;
    if (radius != other.radius)
        world.radius[i] = radius;
    if (mass != other.mass || hasMass != other.hasMass) {
        world.mass[i] = mass;
        world.info[i].hasMass = hasMass;
    }
}

void MarbleState::applyTo(World &world, int i) const
{
    world.position[i] = position;
    world.velocity[i] = velocity;
    world.acceleration[i] = acceleration;
    world.radius[i] = radius;
    world.mass[i] = mass;
    world.info[i].hasMass = hasMass;
}

namespace {

// A scripted push is a click at a fixed stage point, and its force grows with the distance from
// the marble's centre (PHYSICS.md, "Push"). When a teacher moves a marble, its clicks still to
// come move with it, so the demonstration pushes it as before instead of flinging it from afar.
void shiftComingPushes(std::vector<Push> &pushes, int marble, std::int64_t frame, Vec2 from, Vec2 to)
{
    const double dx = to.x - from.x;
    const double dy = to.y - from.y;
    if (dx == 0.0 && dy == 0.0)
        return;
    for (Push &push : pushes) {
        if (push.marble == marble && push.frame >= frame) {
            push.at.x += dx;
            push.at.y += dy;
        }
    }
}

// The same bits: an edit that sets -0 where +0 was changes a run (the models tell them apart).
bool sameState(const MarbleState &a, const MarbleState &b)
{
    return sameBits(a.position, b.position) && sameBits(a.velocity, b.velocity) && sameBits(a.acceleration, b.acceleration)
        && sameBits(a.radius, b.radius) && sameBits(a.mass, b.mass) && a.hasMass == b.hasMass;
}

} // namespace

SetMarbleCommand::SetMarbleCommand(SceneDocument *document, int marble, const MarbleState &before,
                                   const MarbleState &after, const QString &text, std::optional<CommandId> mergeId,
                                   std::optional<std::int64_t> frame)
    : m_document(document)
    , m_marble(marble)
    , m_before(before)
    , m_after(after)
    , m_mergeId(mergeId)
    , m_frame(document->world().frame)
    , m_undoFrame(frame.value_or(m_frame))
    , m_frameMoves(document->frameMoves())
    , m_serial(document->newEditSerial())
{
    // Mid-run, the frame the edit belongs to (undone later in the run, it takes the scene back
    // there).
    setText(atFrame(text, m_frame));
    // A radius or a mass: a click's push waiting for the next frame is worked out with the mass
    // it will meet (PHYSICS.md works a push out just before its frame).
    if (!sameBits(m_before.mass, m_after.mass)) {
        const double pushScale = document->world().params.pushScale;
        m_after.acceleration = World::rescaledPush(m_before.acceleration, m_before.mass, pushScale, m_after.mass, pushScale);
    }
}

bool SetMarbleCommand::applyAtItsFrame(std::int64_t frame, const MarbleState &state, const MarbleState &other,
                                       bool mayRunOn, const std::vector<Push> &pushes)
{
    // Undone or redone at another frame, the edit's values belong to its own (applied where the
    // marble is now, they moved it back to where it was at the edit and set it going again, and
    // redoing several edits after undoing them put them all at the first one's frame):
    // - later in the run, the scene goes back there first, as Step Back would;
    // - earlier (stepped back before it), a redo runs the scene on to it, as Step would; an undo
    //   there only takes back the radius or mass it set, the frames kept holding no such thing
    //   (the edit's motion is not in the run shown);
    // - where the frame is no longer kept, only what the edit changed is set on the marble as it is.
    World &world = m_document->editableWorld();
    const std::int64_t now = world.frame;
    const bool there = now == frame || ((now > frame || mayRunOn) && m_document->goToFrame(frame));
    const MarbleState was = MarbleState::of(world, m_marble);
    if (there) {
        state.applyTo(world, m_marble);
        // A radius or a mass: a click's push waiting there is the one the edit left, which gets
        // its own bits back, or one clicked since, which stays, worked out for the mass it now
        // meets (an undo of a radius gave back the push taken back with Esc before, and dropped
        // the click made since; a helper's finding). (A drag's hold zeroes the push it keeps.)
        if (!sameBits(state.mass, other.mass) && !sameBits(was.acceleration, other.acceleration))
            world.acceleration[m_marble] = World::rescaledPush(was.acceleration, was.mass, world.params.pushScale,
                                                               state.mass, world.params.pushScale);
    } else
        state.applyChangesTo(world, m_marble, other, now > frame);
    const bool changed = !sameState(MarbleState::of(world, m_marble), was) || !(world.pushes == pushes);
    world.pushes = pushes;
    return changed;
}

void SetMarbleCommand::redo()
{
    World &world = m_document->editableWorld();
    assert(m_marble >= 0 && m_marble < world.marbleCount());
    if (m_marble < 0 || m_marble >= world.marbleCount())
        return;
    if (!m_pushesKept) {
        m_pushesBefore = world.pushes;
        m_pushesAfter = world.pushes;
        shiftComingPushes(m_pushesAfter, m_marble, m_frame, m_before.position, m_after.position);
        m_pushesKept = true;
    }
    const bool changed = applyAtItsFrame(m_frame, m_after, m_before, true, m_pushesAfter);
    m_document->applyChange(SceneDocument::Change::Marbles, {m_serial, false, !changed});
}

void SetMarbleCommand::undo()
{
    World &world = m_document->editableWorld();
    assert(m_marble >= 0 && m_marble < world.marbleCount());
    if (m_marble < 0 || m_marble >= world.marbleCount())
        return;
    const bool changed = applyAtItsFrame(m_undoFrame, m_before, m_after, false, m_pushesKept ? m_pushesBefore : world.pushes);
    m_document->applyChange(SceneDocument::Change::Marbles, {m_serial, true, !changed});
}

int SetMarbleCommand::id() const
{
    return m_mergeId ? static_cast<int>(*m_mergeId) : -1;
}

bool SetMarbleCommand::mergeWith(const QUndoCommand *other)
{
    // Not across a run, a step or a Home, which may come back to the same frame (SetParamCommand).
    const auto *next = static_cast<const SetMarbleCommand *>(other);
    if (next->m_marble != m_marble || next->m_mergeId != m_mergeId || next->m_frame != m_frame
        || next->m_undoFrame != m_undoFrame || next->m_frameMoves != m_frameMoves)
        return false;
    m_after = next->m_after;
    m_pushesAfter = next->m_pushesAfter;
    setText(next->text()); // the value the edits ended on
    return true;
}

RenameMarbleCommand::RenameMarbleCommand(SceneDocument *document, int marble, const std::string &before,
                                         const std::string &after, const QString &text)
    : QUndoCommand(text)
    , m_document(document)
    , m_marble(marble)
    , m_before(before)
    , m_after(after)
{
}

void RenameMarbleCommand::redo()
{
    apply(m_after);
}

void RenameMarbleCommand::undo()
{
    apply(m_before);
}

void RenameMarbleCommand::apply(const std::string &name)
{
    World &world = m_document->editableWorld();
    if (m_marble < 0 || m_marble >= world.marbleCount())
        return;
    world.info[static_cast<std::size_t>(m_marble)].name = name;
    m_document->applyChange(SceneDocument::Change::Names);
}

AddMarbleCommand::AddMarbleCommand(SceneDocument *document, const MarbleRecord &record)
    : FramedCommand(document)
    , m_record(record)
{
    // Named by the number it will have and where (the Undo History said "Add marble" alone).
    setName(QCoreApplication::translate("marbles", "Add marble %1 at (%2, %3)")
                .arg(document->world().marbleCount())
                .arg(record.position.x, 0, 'f', 0)
                .arg(record.position.y, 0, 'f', 0));
}

void AddMarbleCommand::redo()
{
    toItsFrame();
    World &world = m_document->editableWorld();
    m_index = world.marbleCount();
    insertMarble(world, m_index, m_record);
    // In the timeline's first frame too, where it is added: Home replays the scene with it.
    const auto k = static_cast<std::size_t>(m_index);
    FrameHistory::MarbleTrack track; // the first frame only: earlier frames have no place for it
    track.start = {world.position[k], world.velocity[k], world.acceleration[k], world.lastHit[k]};
    m_setAside = m_document->marbleInserted(m_index, track);
    m_document->applyChange(SceneDocument::Change::Structure);
}

void AddMarbleCommand::undo()
{
    backToItsFrame();
    World &world = m_document->editableWorld();
    assert(m_index == world.marbleCount() - 1);
    if (m_index < 0 || m_index >= world.marbleCount())
        return;
    world.removeMarble(m_index);
    m_document->marbleRemoved(m_index, std::exchange(m_setAside, 0));
    m_document->applyChange(SceneDocument::Change::Structure);
}

RemoveMarbleCommand::RemoveMarbleCommand(SceneDocument *document, int marble)
    : FramedCommand(document)
    , m_index(marble)
{
    // With its name where it has one: after a delete the later marbles are renumbered, and two
    // deletes in a row could both read "Delete marble 3".
    // Without a name, with where it was, as an add says.
    const std::string &name = document->world().info[static_cast<std::size_t>(marble)].name;
    const Vec2 at = document->world().position[static_cast<std::size_t>(marble)];
    setName(name.empty() ? QCoreApplication::translate("marbles", "Delete marble %1 at (%2, %3)")
                               .arg(marble)
                               .arg(at.x, 0, 'f', 0)
                               .arg(at.y, 0, 'f', 0)
                         : QCoreApplication::translate("marbles", "Delete marble %1 (%2)")
                               .arg(marble)
                               .arg(QString::fromStdString(name)));
}

void RemoveMarbleCommand::redo()
{
    toItsFrame();
    World &world = m_document->editableWorld();
    assert(m_index >= 0 && m_index < world.marbleCount());
    if (m_index < 0 || m_index >= world.marbleCount())
        return;
    m_record = marbleRecord(world, m_index);
    m_pushes = world.pushes;
    world.removeMarble(m_index);
    m_track = m_document->marbleRemoved(m_index);
    m_document->applyChange(SceneDocument::Change::Structure);
}

void RemoveMarbleCommand::undo()
{
    backToItsFrame();
    World &world = m_document->editableWorld();
    assert(m_index >= 0 && m_index <= world.marbleCount());
    if (m_index < 0 || m_index > world.marbleCount())
        return;
    // Step Back took the scene back past the delete: the marble comes back as it was at this
    // frame, from its part of the kept frames (it came back as at the delete, frames later in
    // its run than the others, with the delete frame's collision vectors).
    MarbleRecord record = m_record;
    if (world.frame < m_frame) {
        if (const auto state = m_track.stateAt(world.frame, m_document->history().startFrame())) {
            record.position = state->position;
            record.velocity = state->velocity;
            record.acceleration = state->acceleration;
            record.lastHit = state->lastHit;
        }
    }
    insertMarble(world, m_index, record);
    world.pushes = m_pushes;
    m_document->marbleInserted(m_index, m_track); // where it was at the timeline's start and in the kept frames
    m_document->applyChange(SceneDocument::Change::Structure);
}

} // namespace marbles
