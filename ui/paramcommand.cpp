#include "ui/paramcommand.h"

#include "ui/commandids.h"
#include "ui/numbertext.h"
#include "ui/scenedocument.h"

#include <QCoreApplication>

#include <algorithm>
#include <utility>

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

WaitingPushes WaitingPushes::of(const World &world)
{
    WaitingPushes waiting;
    for (int i = 0; i < world.marbleCount(); ++i) {
        if (world.pushPending(i))
            waiting.pushes.emplace_back(i, world.acceleration[static_cast<std::size_t>(i)]);
    }
    return waiting;
}

WaitingPushes WaitingPushes::rescaled(const World &world, const ParamState &to) const
{
    // As ParamState::applyTo() sets the masses.
    const bool massesTo = to.mass.size() == world.mass.size();
    WaitingPushes result;
    for (const auto &[i, a] : pushes) {
        const auto k = static_cast<std::size_t>(i);
        const double mass = massesTo ? to.mass[k] : world.mass[k];
        const Vec2 b = World::rescaledPush(a, world.mass[k], world.params.pushScale, mass, to.params.pushScale);
        result.pushes.emplace_back(i, b);
    }
    return result;
}

void WaitingPushes::writeTo(World &world) const
{
    for (const auto &[i, a] : pushes) {
        if (i < world.marbleCount())
            world.acceleration[static_cast<std::size_t>(i)] = a;
    }
}

bool WaitingPushes::sameAs(const WaitingPushes &other) const
{
    return std::equal(pushes.begin(), pushes.end(), other.pushes.begin(), other.pushes.end(),
                      [](const auto &a, const auto &b) { return a.first == b.first && sameBits(a.second, b.second); });
}

namespace {

// The pushes as World::pushPending() tells them: one rescaled to zero (a push scale of 0) waits no longer.
WaitingPushes stillWaiting(WaitingPushes waiting)
{
    std::erase_if(waiting.pushes, [](const auto &push) { return push.second.x == 0.0 && push.second.y == 0.0; });
    return waiting;
}

// A parameter as the Parameters dock names it ("zero threshold", not the file's zeroThreshold).
QString paramLabel(const QString &key)
{
    static const std::pair<const char *, const char *> labels[] = {
        {"model", QT_TRANSLATE_NOOP("marbles", "model")},
        {"massScale", QT_TRANSLATE_NOOP("marbles", "mass scale")},
        {"friction", QT_TRANSLATE_NOOP("marbles", "friction")},
        {"zeroThreshold", QT_TRANSLATE_NOOP("marbles", "zero threshold")},
        {"pushScale", QT_TRANSLATE_NOOP("marbles", "push scale")},
        {"frameMs", QT_TRANSLATE_NOOP("marbles", "frame interval")},
        {"restitution", QT_TRANSLATE_NOOP("marbles", "restitution")},
        {"gravity", QT_TRANSLATE_NOOP("marbles", "gravity")},
        {"substeps", QT_TRANSLATE_NOOP("marbles", "substeps")},
        {"shortCircuit", QT_TRANSLATE_NOOP("marbles", "short circuit")},
        {"width", QT_TRANSLATE_NOOP("marbles", "stage width")},
        {"height", QT_TRANSLATE_NOOP("marbles", "stage height")},
        {"walls", QT_TRANSLATE_NOOP("marbles", "walls")},
    };
    for (const auto &[name, label] : labels) {
        if (key == QLatin1String(name))
            return QCoreApplication::translate("marbles", label);
    }
    return key;
}

// The value as the Parameters dock shows it, with its unit ("Set frame interval to 1" gave no
// hint that it was 1 ms).
QString shownValue(const QString &key, const QString &text)
{
    // The value comes written as a scene's file writes it ("0.15", gravity "0,0.15"); shown in
    // the desktop's language, as the dock's field beside it ("0,15" in German).
    const auto number = [](const QString &written) {
        bool ok = false;
        const double v = written.toDouble(&ok);
        return ok ? shownNumber(v, 'g', QLocale::FloatingPointShortest) : written;
    };
    if (key == QLatin1String("gravity")) {
        const QStringList xy = text.split(QLatin1Char(','));
        if (xy.size() == 2)
            return shownPair(number(xy[0]), number(xy[1])) + QStringLiteral(" px/frame\u00b2");
        return text + QStringLiteral(" px/frame\u00b2");
    }
    const QString value = number(text);
    if (key == QLatin1String("frameMs"))
        return value + QStringLiteral(" ms");
    if (key == QLatin1String("zeroThreshold"))
        return value + QStringLiteral(" px/frame");
    if (key == QLatin1String("massScale"))
        return QCoreApplication::translate("marbles", "%1 per px").arg(value);
    if (key == QLatin1String("width") || key == QLatin1String("height"))
        return value + QStringLiteral(" px");
    return value;
}

QString describe(const QString &key, const QString &value)
{
    return QCoreApplication::translate("marbles", "Set %1 to %2").arg(paramLabel(key), shownValue(key, value));
}

} // namespace

SetParamCommand::SetParamCommand(SceneDocument *document, const QString &key, const QString &value,
                                 const ParamState &before, const ParamState &after)
    : m_document(document)
    , m_key(key)
    , m_before(before)
    , m_after(after)
    , m_pushesBefore(WaitingPushes::of(document->world()))
    , m_pushesAfter(m_pushesBefore.rescaled(document->world(), after))
    , m_frameMoves(document->frameMoves())
    , m_serial(document->newEditSerial())
{
    setText(describe(key, value));
}

void SetParamCommand::apply(const ParamState &state, const WaitingPushes &pushesFrom, const WaitingPushes &pushesTo,
                            bool undo)
{
    World &world = m_document->editableWorld();
    const bool changed = !(ParamState::of(world) == state);
    // The pushes waiting when the edit was made get their own bits back; others (clicked since,
    // or at another frame) are worked out for the new values.
    const WaitingPushes waiting = WaitingPushes::of(world);
    const WaitingPushes pushes = waiting.sameAs(stillWaiting(pushesFrom)) ? pushesTo : waiting.rescaled(world, state);
    state.applyTo(world);
    pushes.writeTo(world);
    m_document->applyChange(SceneDocument::Change::Params, {m_serial, undo, !changed});
}

void SetParamCommand::redo()
{
    apply(m_after, m_pushesBefore, m_pushesAfter, false);
}

void SetParamCommand::undo()
{
    apply(m_before, m_pushesAfter, m_pushesBefore, true);
}

int SetParamCommand::id() const
{
    return static_cast<int>(CommandId::SetParam);
}

bool SetParamCommand::mergeWith(const QUndoCommand *other)
{
    // Not across a run, a step or a Home: friction 0.5 set at frame 0, the run played to frame
    // 273 and friction 0.3 set there had become one "Set friction to 0.3", undone straight to
    // the friction before 0.5.
    const auto *next = static_cast<const SetParamCommand *>(other);
    // Nor across a click between them, whose push an undo of both would take away.
    if (next->m_key != m_key || next->m_frameMoves != m_frameMoves || !next->m_pushesBefore.sameAs(stillWaiting(m_pushesAfter)))
        return false;
    m_after = next->m_after;
    m_pushesAfter = next->m_pushesAfter;
    setText(next->text()); // the value the edits ended on
    // Edits that came back to where they started (friction 0, 0.01, 0 again) change nothing: the
    // stack drops them, instead of keeping an Undo that does nothing ("Set friction to 0").
    setObsolete(m_after == m_before && m_pushesAfter.sameAs(m_pushesBefore));
    return true;
}

} // namespace marbles
