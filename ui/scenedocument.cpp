#include "ui/scenedocument.h"

#include "core/sceneio.h"
#include "ui/marblecommand.h"
#include "ui/numbertext.h"
#include "ui/paramcommand.h"
#include "ui/pincommand.h"
#include "ui/wholefile.h"
#include "ui/worldedit.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>

namespace marbles {

namespace {

bool validMarble(const World &world, int i)
{
    return i >= 0 && i < world.marbleCount();
}

} // namespace

SceneDocument::SceneDocument(QObject *parent)
    : QObject(parent)
{
    m_history.reset(m_world);
    connect(&m_undoStack, &QUndoStack::cleanChanged, this, &SceneDocument::emitModification);
}

void SceneDocument::resetScene(const World &world, const QString &fileName)
{
    m_held = -1;
    m_draggedPin = -1;
    m_world = world;
    m_history.reset(m_world);
    m_pushFrames.clear();
    m_physicsMsPerFrame = 0.0; // the last scene's figure is not this one's
    m_undoStack.clear();
    m_undoStack.setClean();
    m_dirtyWithoutUndo = false;
    setFileName(fileName);
    emitModification();
    Q_EMIT sceneChanged(Change::Scene);
    Q_EMIT timelineReset();
    Q_EMIT stepped();
}

bool SceneDocument::readSceneFile(const QString &path, World &out, QString *error, ReadNotes *notes)
{
    // The core's reader: a device or pipe is read only up to the size limit, and a named pipe
    // nothing writes to does not hang the window. Messages name the file without its folder.
    const QByteArray name = QFileInfo(path).fileName().toUtf8();
    SceneLoad load = loadSceneFile(QFile::encodeName(path).toStdString(),
                                   std::string_view(name.constData(), static_cast<std::size_t>(name.size())));
    if (!load.ok) {
        if (error)
            *error = QString::fromStdString(load.error);
        return false;
    }
    if (notes) {
        notes->unusedKeys.clear();
        for (const std::string &line : load.notes)
            notes->unusedKeys << QString::fromStdString(line);
        notes->misspelt = load.misspeltKeys;
    }
    out = std::move(load.world);
    return true;
}

bool SceneDocument::openFile(const QString &path, QString *error)
{
    World world;
    if (!readSceneFile(path, world, error))
        return false;
    resetScene(world, QFileInfo(path).absoluteFilePath());
    return true;
}

bool SceneDocument::saveFile(const QString &path, QString *error, SavedFrame which)
{
    std::optional<World> start;
    if (which == SavedFrame::Start)
        start = worldAtStart();
    const World &saved = start ? *start : m_world;
    // The whole path, as the plot's exports give it: "lesson.marbles.json: cannot write: No such
    // file or directory" had not said it was /proc that took no file.
    const QString name = QDir::toNativeSeparators(QFileInfo(path).absoluteFilePath());
    // Never a file this program would refuse to open: saved after the book model's blow-up (a
    // velocity past the doubles), the scene was written with "vx": null, and Ctrl+S put that over
    // the teacher's lesson (a helper's finding). Nothing is written then, and the file stays.
    if (const QString reason = unsavableReasonOf(saved); !reason.isEmpty()) {
        if (error)
            *error = tr("%1: not saved: %2. Step back to a frame before that (or go back to the start) and save "
                        "there.")
                         .arg(name, reason);
        return false;
    }
    std::string json;
    if (const std::string rule = sceneTextLoadingBack(saved, json); !rule.empty()) {
        if (error) // "<file>: <place>: <rule>", as a file that will not open says it
            *error = tr("%1: %2 (not saved: the scene would not load back)").arg(name, QString::fromStdString(rule));
        return false;
    }
    if (const QString failure = writeWholeFile(path, QByteArray::fromStdString(json)); !failure.isEmpty()) {
        if (error)
            *error = tr("%1: %2").arg(name, failure);
        return false;
    }
    // The frame shown saved in the middle of the run: the file starts there, and so does the run,
    // as when the file is opened. (Home went on to the run's old start, under the file's name and
    // with nothing to save, and a save of the start then wrote it over the file; a helper's
    // finding.) The edits made before it go from the Undo History with the frames they belong to:
    // undone there, a velocity set at frame 20 was put back on the marble at frame 50 (another's).
    const bool restart = which == SavedFrame::Shown && m_world.frame != m_history.startFrame();
    if (restart)
        m_undoStack.clear();
    m_dirtyWithoutUndo = false;
    m_undoStack.setClean();
    setFileName(QFileInfo(path).absoluteFilePath());
    emitModification();
    if (restart) {
        m_history.reset(m_world);
        Q_EMIT timelineReset();
        Q_EMIT stepped();
    }
    return true;
}

QString SceneDocument::unsavableReason() const
{
    return unsavableReasonOf(m_world);
}

QString SceneDocument::unsavableReasonOf(const World &world)
{
    const int marble = world.firstNonFiniteMarble();
    if (marble < 0)
        return {};
    return tr("at frame %1, marble %2's place or velocity is not a finite number, which a scene file cannot hold")
        .arg(world.frame)
        .arg(marble);
}

QString SceneDocument::displayName() const
{
    return m_fileName.isEmpty() ? tr("Untitled") : QFileInfo(m_fileName).fileName();
}

void SceneDocument::markModified()
{
    m_dirtyWithoutUndo = true;
    emitModification();
}

void SceneDocument::setFileName(const QString &fileName)
{
    if (fileName == m_fileName)
        return;
    m_fileName = fileName;
    Q_EMIT fileNameChanged(m_fileName);
}

void SceneDocument::emitModification()
{
    const bool modified = isModified();
    if (modified == m_lastModified)
        return;
    m_lastModified = modified;
    Q_EMIT modificationChanged(modified);
}

void SceneDocument::applyHold()
{
    if (!validMarble(m_world, m_held))
        return;
    // A marble in the hand does not move: the others bounce off it as off a marble at rest.
    m_world.position[m_held] = m_heldAt;
    m_world.velocity[m_held] = {};
    m_world.acceleration[m_held] = {};
}

StepResult SceneDocument::step()
{
    applyHold();
    m_history.record(m_world);
    if (pendingPushCount() > 0) // a scene's scripted pushes are added by the step itself
        m_pushFrames.push_back(m_world.frame);
    // The model's own time for the frame (recording it for stepping back is not physics).
    QElapsedTimer clock;
    clock.start();
    const StepResult result = m_world.step();
    const double ms = static_cast<double>(clock.nsecsElapsed()) / 1.0e6;
    applyHold();
    // Exponential moving average over about 30 frames: steady enough to read in the status bar.
    m_physicsMsPerFrame = m_physicsMsPerFrame == 0.0 ? ms : m_physicsMsPerFrame + (ms - m_physicsMsPerFrame) / 30.0;
    ++m_frameMoves;
    Q_EMIT frameAdvanced();
    if (result.heldMarbles > 0 && heldMarblesBreakEnergy(m_world.params)) {
        Q_EMIT marblesHeld(tr("Frame %1: the exact model held %2 to finish the frame: at rest where a "
                              "marble has more collisions in one frame than it can follow (at speeds far beyond a "
                              "classroom's), between two walls where one is wider than the stage. Kinetic energy was "
                              "not conserved there.")
                               .arg(m_world.frame)
                               .arg(counted(result.heldMarbles, tr("marble"), tr("marbles"))));
    }
    if (!result.finite) {
        const QString name = QString::fromStdString(m_world.info[result.badMarble].name);
        Q_EMIT simulationFailed(
            tr("The simulation stopped at frame %1: marble %2%3 left finite numbers (its position or velocity "
               "became infinite or NaN). Step back, or lower the friction to 2 or less for the book model.")
                .arg(m_world.frame)
                .arg(result.badMarble)
                .arg(name.isEmpty() ? QString() : QStringLiteral(" (\"%1\")").arg(name)));
    }
    return result;
}

int SceneDocument::advance(int frames)
{
    int done = 0;
    while (done < frames) {
        const StepResult result = step();
        ++done;
        if (!result.finite)
            break;
    }
    if (done > 0)
        Q_EMIT stepped();
    return done;
}

bool SceneDocument::stepBack()
{
    if (!m_history.stepBack(m_world))
        return false;
    announceRewound();
    return true;
}

bool SceneDocument::rewind()
{
    if (!m_history.rewind(m_world))
        return false;
    // Its first frame has the pushes of the scene only: every click's push since is left.
    m_pushesLeftByRewind.clear();
    std::copy_if(m_pushFrames.begin(), m_pushFrames.end(), std::back_inserter(m_pushesLeftByRewind),
                 [this](std::int64_t f) { return f >= m_world.frame; });
    announceRewound();
    return true;
}

void SceneDocument::announceRewound()
{
    // A push of a frame from here on acts again only if it is pending here (Step Back's frame).
    std::erase_if(m_pushFrames, [this](std::int64_t f) { return f >= m_world.frame; });
    ++m_frameMoves;
    applyHold();
    Q_EMIT timelineRewound(m_world.frame);
    Q_EMIT stepped();
}

bool SceneDocument::goToFrame(std::int64_t frame)
{
    if (m_world.frame == frame)
        return true;
    if (m_world.frame < frame) {
        const std::int64_t ahead = frame - m_world.frame;
        if (ahead > std::numeric_limits<int>::max())
            return false;
        advance(static_cast<int>(ahead));
        return m_world.frame == frame;
    }
    if (!m_history.velocitiesAt(frame, m_world))
        return false;
    while (m_world.frame > frame && m_history.stepBack(m_world)) {
    }
    if (m_world.frame > frame && frame == m_history.startFrame())
        m_history.rewind(m_world);
    announceRewound();
    return m_world.frame == frame;
}

int SceneDocument::pendingPushCount() const
{
    int pending = 0;
    for (int i = 0; i < m_world.marbleCount(); ++i)
        pending += m_world.pushPending(i) ? 1 : 0;
    return pending;
}

int SceneDocument::takeBackPushes()
{
    // What is pending between frames is the clicks' pushes alone (a scene's scripted pushes are
    // added as their frame is stepped).
    int taken = 0;
    for (int i = 0; i < m_world.marbleCount(); ++i) {
        if (m_world.pushPending(i)) {
            m_world.acceleration[static_cast<std::size_t>(i)] = {};
            ++taken;
        }
    }
    if (taken > 0)
        Q_EMIT stepped();
    return taken;
}

void SceneDocument::pushMarble(int i, Vec2 at)
{
    if (!validMarble(m_world, i))
        return;
    m_world.push(i, at);
    Q_EMIT stepped();
}

void SceneDocument::beginHold(int i)
{
    if (!validMarble(m_world, i))
        return;
    m_held = i;
    m_heldAt = m_world.position[i];
    m_holdStartPosition = m_world.position[i];
    m_holdStartVelocity = m_world.velocity[i];
    m_holdStartAcceleration = m_world.acceleration[i];
    m_holdStartFrame = m_world.frame;
    applyHold();
    Q_EMIT stepped();
}

void SceneDocument::moveHeld(Vec2 p)
{
    if (!validMarble(m_world, m_held) || !isFinite(p))
        return;
    m_heldAt = p;
    applyHold();
    Q_EMIT stepped();
}

QString SceneDocument::endHold(Vec2 p)
{
    const int i = m_held;
    m_held = -1;
    if (!validMarble(m_world, i))
        return {};
    const std::optional<Vec2> spot = nearestFreeSpot(m_world, p, m_world.radius[i], BodyKind::Marble, i);
    MarbleState before = MarbleState::of(m_world, i);
    before.position = m_holdStartPosition;
    before.velocity = m_holdStartVelocity;
    before.acceleration = m_holdStartAcceleration;
    if (!spot) {
        before.applyTo(m_world, i);
        Q_EMIT stepped();
        return tr("No free spot for the marble near (%1, %2): it went back.").arg(p.x, 0, 'f', 0).arg(p.y, 0, 'f', 0);
    }
    // Held while the run went on, it was caught: let go at rest. Moved while paused, no time
    // passed in the hand: it keeps its velocity and any push still to come (a teacher who set
    // velocities and then tidied the places lost them; the drop said so, but the setting-up of
    // a scene is moving marbles about).
    const bool caught = m_world.frame != m_holdStartFrame;
    MarbleState after = MarbleState::of(m_world, i);
    after.position = *spot;
    after.velocity = caught ? Vec2{} : m_holdStartVelocity;
    after.acceleration = caught ? Vec2{} : m_holdStartAcceleration;
    // The drag belongs to the frame it began at: undone, the frames the marble was held for go
    // (they were kept, the marble held in them, while the undo set it going from where it was
    // taken hold of at the frame of the drop).
    m_undoStack.push(new SetMarbleCommand(this, i, before, after,
                                          tr("Move marble %1 to (%2, %3)").arg(i).arg(spot->x, 0, 'f', 0).arg(spot->y, 0, 'f', 0),
                                          std::nullopt, m_holdStartFrame));
    if (spot->x != p.x || spot->y != p.y)
        return tr("The marble was moved to the nearest free spot.");
    return {};
}

void SceneDocument::beginPinDrag(int j)
{
    if (j < 0 || j >= static_cast<int>(m_world.pins.size()))
        return;
    m_draggedPin = j;
    m_pinStart = m_world.pins[j];
}

void SceneDocument::movePinDrag(Vec2 q)
{
    if (m_draggedPin < 0 || m_draggedPin >= static_cast<int>(m_world.pins.size()) || !isFinite(q))
        return;
    m_world.pins[m_draggedPin] = q;
    Q_EMIT sceneChanged(Change::Structure);
}

QString SceneDocument::endPinDrag(Vec2 q)
{
    const int j = m_draggedPin;
    m_draggedPin = -1;
    if (j < 0 || j >= static_cast<int>(m_world.pins.size()))
        return {};
    const std::optional<Vec2> spot = nearestFreeSpot(m_world, q, 0.0, BodyKind::Pin, -1, j);
    if (!spot) {
        m_world.pins[j] = m_pinStart;
        Q_EMIT sceneChanged(Change::Structure);
        return tr("No free spot for the pin near (%1, %2): it went back.").arg(q.x, 0, 'f', 0).arg(q.y, 0, 'f', 0);
    }
    m_world.pins[j] = m_pinStart;
    m_undoStack.push(new MovePinCommand(this, j, m_pinStart, *spot));
    if (spot->x != q.x || spot->y != q.y)
        return tr("The pin was moved to the nearest free spot.");
    return {};
}

QString SceneDocument::addMarble(Vec2 p, double r)
{
    if (!(r > 0.0) || !std::isfinite(r))
        return tr("A marble's radius must be > 0.");
    const std::optional<Vec2> spot = nearestFreeSpot(m_world, p, r, BodyKind::Marble);
    if (!spot)
        return tr("No free spot for a marble of radius %1 near (%2, %3).").arg(r).arg(p.x, 0, 'f', 0).arg(p.y, 0, 'f', 0);
    MarbleRecord record;
    record.position = *spot;
    record.radius = r;
    record.mass = m_world.params.massScale * r;
    m_undoStack.push(new AddMarbleCommand(this, record));
    // Said, as a drop there is (the marble appeared beside the one clicked on, without a word).
    if (spot->x != p.x || spot->y != p.y)
        return tr("The marble was placed at the nearest free spot.");
    return {};
}

void SceneDocument::removeMarble(int i)
{
    if (!validMarble(m_world, i))
        return;
    m_undoStack.push(new RemoveMarbleCommand(this, i));
}

QString SceneDocument::addPin(Vec2 q)
{
    const std::optional<Vec2> spot = nearestFreeSpot(m_world, q, 0.0, BodyKind::Pin);
    if (!spot)
        return tr("No free spot for a pin near (%1, %2).").arg(q.x, 0, 'f', 0).arg(q.y, 0, 'f', 0);
    m_undoStack.push(new AddPinCommand(this, *spot));
    if (spot->x != q.x || spot->y != q.y)
        return tr("The pin was placed at the nearest free spot.");
    return {};
}

void SceneDocument::removePin(int j)
{
    if (j < 0 || j >= static_cast<int>(m_world.pins.size()))
        return;
    m_undoStack.push(new RemovePinCommand(this, j));
}

QString SceneDocument::setMarblePosition(int i, Vec2 p)
{
    if (!validMarble(m_world, i))
        return tr("No such marble.");
    if (!isFreeSpot(m_world, p, m_world.radius[i], BodyKind::Marble, i))
        return tr("The marble would overlap the stage edge, a pin or another marble there.");
    const MarbleState before = MarbleState::of(m_world, i);
    MarbleState after = before;
    after.position = p;
    m_undoStack.push(new SetMarbleCommand(this, i, before, after, tr("Set marble %1's position to %2").arg(i).arg(shownPair(shownNumber(p.x), shownNumber(p.y))),
                                          CommandId::EditMarblePosition));
    return {};
}

QString SceneDocument::setMarbleVelocity(int i, Vec2 v)
{
    if (!validMarble(m_world, i))
        return tr("No such marble.");
    if (!isFinite(v))
        return tr("A velocity must be finite.");
    const MarbleState before = MarbleState::of(m_world, i);
    MarbleState after = before;
    after.velocity = v;
    // As the Inspector shows a velocity, to its decimals (the other component, not typed, read
    // "0.574696" beside the field's 0.575; then "1.235" beside its 1.2346).
    const int decimals = velocityDecimals(m_world.params.zeroThreshold);
    const auto shown = [decimals](double x) { return fixedTrimmed(x, decimals); };
    m_undoStack.push(new SetMarbleCommand(this, i, before, after,
                                          tr("Set marble %1's velocity to %2 px/frame").arg(i).arg(shownPair(shown(v.x), shown(v.y))),
                                          CommandId::EditMarbleVelocity));
    return {};
}

QString SceneDocument::setMarbleRadius(int i, double r)
{
    if (!validMarble(m_world, i))
        return tr("No such marble.");
    if (!(r > 0.0) || !std::isfinite(r))
        return tr("A marble's radius must be > 0.");
    // Grown into a wall, a pin or a marble, as a move there is refused (it was taken: a radius of
    // 240 swallowed a pin and two marbles, which then stuck inside each other). A marble that
    // overlaps already (a file may place it so) may still shrink.
    if (r > m_world.radius[i] && !isFreeSpot(m_world, m_world.position[i], r, BodyKind::Marble, i))
        return tr("A radius of %1 px would make the marble overlap the stage edge, a pin or another marble.")
            .arg(shownNumber(r));
    const MarbleState before = MarbleState::of(m_world, i);
    MarbleState after = before;
    after.radius = r;
    if (!after.hasMass)
        after.mass = m_world.params.massScale * r;
    m_undoStack.push(new SetMarbleCommand(this, i, before, after, tr("Set marble %1's radius to %2 px").arg(i).arg(shownNumber(r)),
                                          CommandId::EditMarbleRadius));
    return {};
}

QString SceneDocument::setMarbleName(int i, const QString &name)
{
    if (!validMarble(m_world, i))
        return tr("No such marble.");
    const QString trimmed = name.trimmed();
    // A legend entry has room for about this much.
    constexpr int kMaxNameLength = 40;
    if (trimmed.size() > kMaxNameLength)
        return tr("A marble's name may be %1 characters at most; \"%2\" has %3.")
            .arg(kMaxNameLength)
            .arg(trimmed)
            .arg(trimmed.size());
    const std::string before = m_world.info[static_cast<std::size_t>(i)].name;
    const std::string after = trimmed.toStdString();
    if (before == after)
        return {};
    const QString text = trimmed.isEmpty() ? tr("Take marble %1's name away").arg(i)
                                           : tr("Name marble %1 \"%2\"").arg(i).arg(trimmed);
    m_undoStack.push(new RenameMarbleCommand(this, i, before, after, text));
    return {};
}

QString SceneDocument::setMarbleMass(int i, double m)
{
    if (!validMarble(m_world, i))
        return tr("No such marble.");
    if (!(m >= 0.0) || !std::isfinite(m))
        return tr("A marble's mass must be > 0 (or 0 for mass scale \u00d7 radius).");
    const MarbleState before = MarbleState::of(m_world, i);
    MarbleState after = before;
    after.hasMass = m > 0.0;
    after.mass = after.hasMass ? m : m_world.params.massScale * before.radius;
    // Masses typed or scrubbed one after another are one undo step; a switch between the marble's
    // own mass and massScale x radius is a step of its own (untick, type 80, tick had been one
    // step, and Ctrl+Z went past "80" to the mass before it all, a re-tester's finding).
    const std::optional<CommandId> merge =
        before.hasMass && after.hasMass ? std::optional(CommandId::EditMarbleMass) : std::nullopt;
    m_undoStack.push(
        new SetMarbleCommand(this, i, before, after, after.hasMass ? tr("Set marble %1's mass to %2").arg(i).arg(shownNumber(m))
                                                     : tr("Set marble %1's mass to mass scale \u00d7 radius").arg(i),
                             merge));
    return {};
}

QString SceneDocument::setParam(const QString &key, const QString &value)
{
    World trial = m_world;
    const QByteArray k = key.toUtf8();
    const QByteArray v = value.toUtf8();
    std::string error = marbles::setParam(trial, std::string_view(k.constData(), static_cast<std::size_t>(k.size())),
                                          std::string_view(v.constData(), static_cast<std::size_t>(v.size())));
    if (error.empty())
        error = validateParams(trial.params);
    if (!error.empty())
        return QString::fromStdString(error);
    const ParamState before = ParamState::of(m_world);
    const ParamState after = ParamState::of(trial);
    if (before == after)
        return {};
    m_undoStack.push(new SetParamCommand(this, key, value, before, after));
    return {};
}

std::uint64_t SceneDocument::marbleInserted(int i, const FrameHistory::MarbleTrack &track)
{
    Q_EMIT marbleInsertedAt(i);
    std::uint64_t setAside = 0;
    // Only while the first frame follows the world (one marble fewer there than here now).
    if (m_history.startSize() + 1 == m_world.marbleCount()) {
        setAside = m_history.insertMarble(i, track);
        if (setAside != 0)
            Q_EMIT timelineMarbleAdded(i);
        else if (m_history.size() > 0)
            Q_EMIT timelineMarbleInserted(i);
    }
    m_marblesRenumbered = true;
    return setAside;
}

FrameHistory::MarbleTrack SceneDocument::marbleRemoved(int i, std::uint64_t setAside)
{
    Q_EMIT marbleRemovedAt(i);
    FrameHistory::MarbleTrack track;
    if (m_history.startSize() == m_world.marbleCount() + 1) {
        track = m_history.removeMarble(i);
        if (setAside != 0 && m_history.takeBackSetAside(setAside, m_world))
            Q_EMIT timelineAddUndone(i);
        else
            Q_EMIT timelineMarbleRemoved(i);
    }
    m_marblesRenumbered = true;
    return track;
}

void SceneDocument::applyChange(Change change, EditCause cause)
{
    const EditCause outer = std::exchange(m_currentEdit, cause);
    applyChange(change);
    m_currentEdit = outer;
}

void SceneDocument::applyChange(Change change)
{
    if (change == Change::Names) {
        // Nothing of the run changed: its kept frames, the comparison and the trails stay.
        emitModification();
        Q_EMIT sceneChanged(change);
        return;
    }
    // The first frame follows marbles added or removed (marbleInserted(), marbleRemoved()); if it
    // did not, the timeline starts again here.
    const bool restart = !m_history.fits(m_world);
    if (restart)
        m_history.reset(m_world);
    else if (m_world.frame == m_history.startFrame())
        m_history.reset(m_world); // an edit of the timeline's first frame is what rewind() returns to
                                  // (no later frame is kept while that frame is shown)
    if (!validMarble(m_world, m_held))
        m_held = -1;
    emitModification();
    Q_EMIT sceneChanged(change);
    // Marbles renumbered: what the plots and trails hold of each index is another marble's.
    if (restart || std::exchange(m_marblesRenumbered, false))
        Q_EMIT timelineReset();
    else
        Q_EMIT timelineEdited();
    Q_EMIT stepped();
}

} // namespace marbles
