#include "ui/marblecommand.h"

#include "ui/scenedocument.h"

#include <QCoreApplication>

#include <cassert>

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

void MarbleState::applyTo(World &world, int i) const
{
    world.position[i] = position;
    world.velocity[i] = velocity;
    world.acceleration[i] = acceleration;
    world.radius[i] = radius;
    world.mass[i] = mass;
    world.info[i].hasMass = hasMass;
}

SetMarbleCommand::SetMarbleCommand(SceneDocument *document, int marble, const MarbleState &before,
                                   const MarbleState &after, const QString &text, std::optional<CommandId> mergeId)
    : m_document(document)
    , m_marble(marble)
    , m_before(before)
    , m_after(after)
    , m_mergeId(mergeId)
{
    setText(text);
}

void SetMarbleCommand::redo()
{
    World &world = m_document->editableWorld();
    assert(m_marble >= 0 && m_marble < world.marbleCount());
    if (m_marble < 0 || m_marble >= world.marbleCount())
        return;
    m_after.applyTo(world, m_marble);
    m_document->applyChange(SceneDocument::Change::Marbles);
}

void SetMarbleCommand::undo()
{
    World &world = m_document->editableWorld();
    assert(m_marble >= 0 && m_marble < world.marbleCount());
    if (m_marble < 0 || m_marble >= world.marbleCount())
        return;
    m_before.applyTo(world, m_marble);
    m_document->applyChange(SceneDocument::Change::Marbles);
}

int SetMarbleCommand::id() const
{
    return m_mergeId ? static_cast<int>(*m_mergeId) : -1;
}

bool SetMarbleCommand::mergeWith(const QUndoCommand *other)
{
    const auto *next = static_cast<const SetMarbleCommand *>(other);
    if (next->m_marble != m_marble || next->m_mergeId != m_mergeId)
        return false;
    m_after = next->m_after;
    return true;
}

AddMarbleCommand::AddMarbleCommand(SceneDocument *document, const MarbleRecord &record)
    : m_document(document)
    , m_record(record)
{
    setText(QCoreApplication::translate("marbles", "Add marble"));
}

void AddMarbleCommand::redo()
{
    World &world = m_document->editableWorld();
    m_index = world.marbleCount();
    insertMarble(world, m_index, m_record);
    m_document->applyChange(SceneDocument::Change::Structure);
}

void AddMarbleCommand::undo()
{
    World &world = m_document->editableWorld();
    assert(m_index == world.marbleCount() - 1);
    if (m_index < 0 || m_index >= world.marbleCount())
        return;
    world.removeMarble(m_index);
    m_document->applyChange(SceneDocument::Change::Structure);
}

RemoveMarbleCommand::RemoveMarbleCommand(SceneDocument *document, int marble)
    : m_document(document)
    , m_index(marble)
{
    setText(QCoreApplication::translate("marbles", "Delete marble"));
}

void RemoveMarbleCommand::redo()
{
    World &world = m_document->editableWorld();
    assert(m_index >= 0 && m_index < world.marbleCount());
    if (m_index < 0 || m_index >= world.marbleCount())
        return;
    m_record = marbleRecord(world, m_index);
    m_pushes = world.pushes;
    world.removeMarble(m_index);
    m_document->applyChange(SceneDocument::Change::Structure);
}

void RemoveMarbleCommand::undo()
{
    World &world = m_document->editableWorld();
    assert(m_index >= 0 && m_index <= world.marbleCount());
    if (m_index < 0 || m_index > world.marbleCount())
        return;
    insertMarble(world, m_index, m_record);
    world.pushes = m_pushes;
    m_document->applyChange(SceneDocument::Change::Structure);
}

} // namespace marbles
