#include "ui/pincommand.h"

#include "ui/scenedocument.h"
#include "ui/worldedit.h"

#include <QCoreApplication>

#include <cassert>

namespace marbles {

namespace {

bool validPin(const World &world, int j)
{
    return j >= 0 && j < static_cast<int>(world.pins.size());
}

} // namespace

AddPinCommand::AddPinCommand(SceneDocument *document, Vec2 at)
    : FramedCommand(document)
    , m_at(at)
{
    setName(QCoreApplication::translate("marbles", "Add pin %1 at (%2, %3)")
                .arg(document->world().pins.size())
                .arg(at.x, 0, 'f', 0)
                .arg(at.y, 0, 'f', 0));
}

void AddPinCommand::redo()
{
    toItsFrame();
    m_index = m_document->editableWorld().addPin(m_at);
    m_document->applyChange(SceneDocument::Change::Structure);
}

void AddPinCommand::undo()
{
    backToItsFrame();
    World &world = m_document->editableWorld();
    assert(validPin(world, m_index));
    if (!validPin(world, m_index))
        return;
    world.removePin(m_index);
    m_document->applyChange(SceneDocument::Change::Structure);
}

RemovePinCommand::RemovePinCommand(SceneDocument *document, int pin)
    : FramedCommand(document)
    , m_index(pin)
{
    // With where it was, as an add says: pins are renumbered as others go, and "Delete pin 30"
    // did not tell which (a helper's finding).
    const Vec2 at = document->world().pins[static_cast<std::size_t>(pin)];
    setName(QCoreApplication::translate("marbles", "Delete pin %1 at (%2, %3)")
                .arg(pin)
                .arg(at.x, 0, 'f', 0)
                .arg(at.y, 0, 'f', 0));
}

void RemovePinCommand::redo()
{
    toItsFrame();
    World &world = m_document->editableWorld();
    assert(validPin(world, m_index));
    if (!validPin(world, m_index))
        return;
    m_at = world.pins[m_index];
    m_extraJson = world.pinExtraJson[m_index];
    world.removePin(m_index);
    m_document->applyChange(SceneDocument::Change::Structure);
}

void RemovePinCommand::undo()
{
    backToItsFrame();
    insertPin(m_document->editableWorld(), m_index, m_at, m_extraJson);
    m_document->applyChange(SceneDocument::Change::Structure);
}

MovePinCommand::MovePinCommand(SceneDocument *document, int pin, Vec2 from, Vec2 to)
    : FramedCommand(document)
    , m_index(pin)
    , m_from(from)
    , m_to(to)
{
    setName(QCoreApplication::translate("marbles", "Move pin %1 to (%2, %3)").arg(pin).arg(to.x, 0, 'f', 0).arg(to.y, 0, 'f', 0));
}

void MovePinCommand::redo()
{
    toItsFrame();
    World &world = m_document->editableWorld();
    assert(validPin(world, m_index));
    if (!validPin(world, m_index))
        return;
    world.pins[m_index] = m_to;
    m_document->applyChange(SceneDocument::Change::Structure);
}

void MovePinCommand::undo()
{
    backToItsFrame();
    World &world = m_document->editableWorld();
    assert(validPin(world, m_index));
    if (!validPin(world, m_index))
        return;
    world.pins[m_index] = m_from;
    m_document->applyChange(SceneDocument::Change::Structure);
}

} // namespace marbles
