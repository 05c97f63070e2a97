#pragma once

#include "core/world.h"

#include <QString>
#include <QUndoCommand>

#include <utility>
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

/// The clicks' pushes waiting for the next frame (World::pushPending), by marble.
struct WaitingPushes {
    std::vector<std::pair<int, Vec2>> pushes; ///< marble, pending acceleration (not zero)

    static WaitingPushes of(const World &world);
    /// The same pushes for `to`'s masses and push scale, from `world`'s (World::rescaledPush):
    /// a mass scale, a mass or a push scale set while a push waits changes what it adds.
    WaitingPushes rescaled(const World &world, const ParamState &to) const;
    /// Sets the marbles' pending accelerations to these (the same marbles as waited in `world`).
    void writeTo(World &world) const;

    /// The same bits (a push of -0 is not one of +0 to the models).
    bool sameAs(const WaitingPushes &other) const;
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
    void apply(const ParamState &state, const WaitingPushes &pushesFrom, const WaitingPushes &pushesTo, bool undo);

    SceneDocument *m_document;
    QString m_key;
    ParamState m_before;
    ParamState m_after;
    WaitingPushes m_pushesBefore;
    WaitingPushes m_pushesAfter;
    std::uint64_t m_frameMoves; // the document's frameMoves() when the edit was made
    std::uint64_t m_serial; // the document's newEditSerial() for it (CompareRun keeps what its undo gives back)
};

} // namespace marbles
