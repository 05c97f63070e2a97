#include "ui/paramcommand.h"

#include "ui/commandids.h"
#include "ui/scenedocument.h"

#include <QCoreApplication>

namespace marbles {

ParamState ParamState::of(const World &world)
{
    return ParamState{world.params, world.stage, world.mass};
}

void ParamState::applyTo(World &world) const
{
    world.params = params;
    world.stage = stage;
    if (mass.size() == world.mass.size())
        world.mass = mass;
}

SetParamCommand::SetParamCommand(SceneDocument *document, const QString &key, const ParamState &before,
                                 const ParamState &after)
    : m_document(document)
    , m_key(key)
    , m_before(before)
    , m_after(after)
{
    setText(QCoreApplication::translate("marbles", "Set %1").arg(key));
}

void SetParamCommand::redo()
{
    m_after.applyTo(m_document->editableWorld());
    m_document->applyChange(SceneDocument::Change::Params);
}

void SetParamCommand::undo()
{
    m_before.applyTo(m_document->editableWorld());
    m_document->applyChange(SceneDocument::Change::Params);
}

int SetParamCommand::id() const
{
    return static_cast<int>(CommandId::SetParam);
}

bool SetParamCommand::mergeWith(const QUndoCommand *other)
{
    const auto *next = static_cast<const SetParamCommand *>(other);
    if (next->m_key != m_key)
        return false;
    m_after = next->m_after;
    return true;
}

} // namespace marbles
