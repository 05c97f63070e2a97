#pragma once

#include "core/world.h"

#include <QString>
#include <QUndoCommand>

#include <vector>

namespace marbles {

class SceneDocument;

/// Everything a parameter setting can change: params, the stage, and the masses derived from massScale.
struct ParamState {
    Params params;
    Stage stage;
    std::vector<double> mass;

    /// Reads the state from `world`.
    static ParamState of(const World &world);
    /// Writes it back into `world` (same marbles).
    void applyTo(World &world) const;

    friend bool operator==(const ParamState &, const ParamState &) = default;
};

/// Sets one parameter (a Parameters dock edit). Consecutive edits of the same key merge (a spin
/// box scrubbed), unless the frame shown changed between them.
class SetParamCommand : public QUndoCommand {
public:
    /// `value` is the new value as typed (for the Undo History's "Set friction to 0.2").
    SetParamCommand(SceneDocument *document, const QString &key, const QString &value, const ParamState &before,
                    const ParamState &after);
    void redo() override;
    void undo() override;
    int id() const override;
    bool mergeWith(const QUndoCommand *other) override;

private:
    SceneDocument *m_document;
    QString m_key;
    ParamState m_before;
    ParamState m_after;
    std::uint64_t m_frameMoves; // the document's frameMoves() when the edit was made
    std::uint64_t m_serial; // the document's newEditSerial() for it (CompareRun keeps what its undo gives back)
};

} // namespace marbles
