#include "ui/comparerun.h"

#include "core/sceneio.h"
#include "ui/marblefielditem.h"
#include "ui/numbertext.h"
#include "ui/scenedocument.h"

#include <QGraphicsScene>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

namespace marbles {

CompareRun::CompareRun(SceneDocument *document, QObject *parent)
    : QObject(parent)
    , m_document(document)
{
    // Connected once; every handler returns at once while the comparison is off. These
    // connections are made before the main window connects its plot, so the comparison has
    // simulated its frame by the time the plot samples both worlds.
    connect(m_document, &SceneDocument::frameAdvanced, this, &CompareRun::onFrameAdvanced);
    connect(m_document, &SceneDocument::stepped, this, &CompareRun::onStepped);
    connect(m_document, &SceneDocument::sceneChanged, this, &CompareRun::onSceneChanged);
    connect(m_document, &SceneDocument::timelineReset, this, &CompareRun::onTimelineReset);
    connect(m_document, &SceneDocument::timelineRewound, this, &CompareRun::rewindTo);
    connect(m_document, &SceneDocument::timelineMarbleRemoved, this, &CompareRun::onMarbleRemoved);
    connect(m_document, &SceneDocument::timelineMarbleInserted, this, &CompareRun::onMarbleInserted);
    connect(m_document, &SceneDocument::timelineMarbleAdded, this, &CompareRun::onMarbleAdded);
    connect(m_document, &SceneDocument::timelineAddUndone, this, &CompareRun::onAddUndone);
}

CompareRun::~CompareRun()
{
    removeGhost();
}

void CompareRun::setModel(ModelKind model)
{
    const bool changed = !m_model || *m_model != model;
    m_model = model;
    if (!m_world)
        m_world = std::make_unique<World>();
    restart();
    if (changed)
        Q_EMIT modelChanged();
}

void CompareRun::stop()
{
    if (!m_model)
        return;
    m_model.reset();
    m_world.reset();
    m_history = FrameHistory(); // its frames can hold a few hundred MiB
    m_removed.clear();
    m_added.clear();
    clearGapList(m_startFrame);
    m_gaps.shrink_to_fit();
    m_problem.clear();
    resetGaps(m_startFrame);
    removeGhost();
    Q_EMIT modelChanged();
}

void CompareRun::restart()
{
    m_editRestarts.clear();
    if (!m_model)
        return;
    const World &source = m_document->world();
    *m_world = source;
    m_world->params.model = *m_model;
    m_startFrame = source.frame;
    m_earlierStarts.clear();
    resetGaps(source.frame);
    clearGapList(source.frame);
    m_history.reset(*m_world);
    m_removed.clear();
    m_added.clear();
    // The scene's parameters were checked for the document's model only: friction >= 1, say, is
    // the book model's instability on show, but the exact and impulse models cannot run with it.
    m_problem = QString::fromStdString(validateParams(m_world->params));
    if (!m_problem.isEmpty() && m_world->params.friction >= 1.0)
        m_problem = tr("it needs a friction below 1 (the scene's is %1)").arg(shownNumber(m_world->params.friction));
    updateGhost();
    Q_EMIT restarted();
}

void CompareRun::onSceneChanged(SceneDocument::Change change)
{
    const World &source = m_document->world();
    if (change == SceneDocument::Change::Names) {
        // A marble renamed: the comparison runs on (it started over, its gap back to 0, and the
        // plot marked a restart).
        if (m_world && m_world->info.size() == source.info.size())
            m_world->info = source.info;
        return;
    }
    const bool keepsMarbles = change == SceneDocument::Change::Params || change == SceneDocument::Change::Marbles;
    // An edit undone where it was made: the comparison as it was before it. It had started again
    // from the scene at the edit, and the undo started it once more: the exact model's ghosts then
    // carried the book's energy (Example 3 at frame 37, a velocity set and undone: "KE 1110.3
    // (book), 1110.3 (exact)", where it had read 388.51 for exact).
    const SceneDocument::EditCause cause = m_document->currentEdit();
    if (keepsMarbles && cause.undoing && takeBackEditRestart(cause.serial))
        return;
    // An edit undone or redone where the run shown never had it (stepped back before its frame,
    // or past it and on again) leaves the scene as it was: the comparison runs on as it was (it
    // started again from the scene, its own run before lost).
    if (keepsMarbles && cause.changedNothing)
        return;
    // A marble removed or put back, which the kept frames followed: they now have the marbles the
    // scene has (the world still has its old ones).
    const bool followed = change == SceneDocument::Change::Structure && m_followedStructure;
    if (followed && std::exchange(m_restoredOwnState, false)) {
        // A marble put back, the comparison's own state with it (onMarbleInserted()).
        updateGhost();
        return;
    }
    World next = source;
    next.params.model = m_model.value_or(ModelKind::Book);
    // Anything but an edit of this frame's marbles or parameters (or marbles the frames
    // followed), or one the model cannot run with, starts the comparison over.
    if (!(keepsMarbles || followed) || !isTracking() || m_world->frame != source.frame
        || (followed ? m_history.startSize() : m_world->marbleCount()) != source.marbleCount()
        || !validateParams(next.params).empty()) {
        restart();
        return;
    }
    // The comparison starts again from the scene as edited (the gap is 0 at this frame), and
    // keeps the frames it ran before: stepping back past the edit shows them as they were (a
    // tester's ghosts sat on the marbles at a frame where the models had been 241 px apart).
    if (keepsMarbles && !cause.undoing)
        rememberEditRestart(cause.serial);
    m_earlierStarts.push_back(m_startFrame);
    *m_world = std::move(next);
    m_startFrame = source.frame;
    if (!m_gaps.empty() && m_firstGapFrame + static_cast<std::int64_t>(m_gaps.size()) - 1 == source.frame)
        m_gaps.back() = Gap{};
    resetGaps(source.frame);
    updateGhost();
    Q_EMIT restarted();
}

bool CompareRun::keepsStartOf(const EditRestart &edit) const
{
    // Its start pushed the one before it at index edit.earlierStarts (rewindTo() takes it away).
    return m_earlierStarts.size() > edit.earlierStarts && m_earlierStarts[edit.earlierStarts] == edit.startFrame;
}

void CompareRun::rememberEditRestart(std::uint64_t serial)
{
    // Edits whose start was stepped back past are gone for good.
    std::erase_if(m_editRestarts, [this](const EditRestart &edit) { return !keepsStartOf(edit); });
    if (serial == 0)
        return;
    EditRestart edit{{-1, m_world->frame, World(), m_startFrame, m_earlierStarts.size()}, serial};
    // A spin box scrubbed is one edit per value: after the first, the comparison is the scene
    // itself at this frame, and the undo of a later one gives it from the scene.
    edit.copyOfScene = m_startFrame == m_world->frame && !m_editRestarts.empty()
        && m_editRestarts.back().frame == m_world->frame && m_editRestarts.back().earlierStarts + 1 == m_earlierStarts.size();
    if (!edit.copyOfScene) {
        edit.before = *m_world;
        // The worlds kept stay within 64 MiB (a 20,000-marble crowd's is about 5 MB, one of
        // the book's figures a few kB): the oldest edits' undos start the comparison again instead.
        constexpr std::size_t budget = std::size_t{64} << 20;
        std::size_t kept = edit.before.approximateBytes();
        for (auto k = m_editRestarts.size(); k-- > 0;) {
            kept += m_editRestarts[k].copyOfScene ? 0 : m_editRestarts[k].before.approximateBytes();
            if (kept > budget) {
                m_editRestarts.erase(m_editRestarts.begin(), m_editRestarts.begin() + static_cast<std::ptrdiff_t>(k) + 1);
                break;
            }
        }
    }
    m_editRestarts.push_back(std::move(edit));
}

bool CompareRun::takeBackEditRestart(std::uint64_t serial)
{
    const World &source = m_document->world();
    auto found = std::find_if(m_editRestarts.rbegin(), m_editRestarts.rend(),
                              [serial](const EditRestart &edit) { return edit.serial == serial; });
    if (found == m_editRestarts.rend())
        return false;
    const auto at = std::prev(found.base());
    EditRestart edit = std::move(*at);
    m_editRestarts.erase(at, m_editRestarts.end());
    // Still at the edit's frame, on its start or on later ones made there (the comparison's own
    // frames since were stepped back through, or none were run).
    const auto frame = edit.frame;
    if (!isTracking() || m_world->frame != frame || source.frame != frame || !keepsStartOf(edit) || m_startFrame != frame
        || !std::all_of(m_earlierStarts.begin() + static_cast<std::ptrdiff_t>(edit.earlierStarts) + 1,
                        m_earlierStarts.end(), [frame](std::int64_t start) { return start == frame; })
        || (!edit.copyOfScene && edit.before.marbleCount() != source.marbleCount()))
        return false;
    World own = edit.copyOfScene ? source : std::move(edit.before);
    own.params = source.params; // the undo gave the scene back its own
    own.params.model = *m_model;
    takeBackStart(edit);
    takeOwnState(std::move(own));
    updateGhost();
    Q_EMIT restartTakenBack(frame);
    return true;
}

std::vector<std::int64_t> CompareRun::restartFrames() const
{
    if (m_earlierStarts.empty())
        return {};
    std::vector<std::int64_t> frames(m_earlierStarts.begin() + 1, m_earlierStarts.end());
    frames.push_back(m_startFrame);
    return frames;
}

void CompareRun::onMarbleRemoved(int i)
{
    // The comparison's frames lose the marble as the document's did, so that Step Back past the
    // delete goes back to the comparison there: it had started again from the document's state
    // at each such frame ("gap 0", both models' totals alike), its own frames unused.
    const World &source = m_document->world();
    if (!isTracking() || m_world->frame != source.frame || m_history.startSize() != source.marbleCount() + 1)
        return;
    m_removed.push_back({beforeEdit(i), m_history.removeMarble(i)});
    // The largest gap of the frames forgotten is renumbered, or goes with its marble.
    if (m_earlierLargest.marble == i)
        m_earlierLargest = {};
    else if (m_earlierLargest.marble > i)
        --m_earlierLargest.marble;
    remeasureKeptGaps();
    m_followedStructure = true;
}

void CompareRun::onMarbleInserted(int i)
{
    // Put back by an undo: the comparison's frames take back the part their delete took out.
    if (m_removed.empty() || m_removed.back().marble != i)
        return;
    const Removed removed = std::move(m_removed.back());
    m_removed.pop_back();
    const World &source = m_document->world();
    if (!isTracking() || m_world->frame != source.frame || m_history.startSize() + 1 != source.marbleCount())
        return;
    m_history.insertMarble(i, removed.track);
    if (m_earlierLargest.marble >= i)
        ++m_earlierLargest.marble;
    remeasureKeptGaps();
    m_followedStructure = true;
    m_restoredOwnState = restoreOwnState(i, removed);
}

bool CompareRun::restoreOwnState(int i, const Removed &removed)
{
    // The undo gives the comparison back what the delete took: its own state (it had started
    // again from the scene's, "gap 0", and a teacher's mistaken delete lost the comparison's
    // state until Step Back went past it).
    const World &source = m_document->world();
    const std::int64_t frame = source.frame;
    World own = source;
    own.params.model = *m_model;
    own.frame = frame;
    const auto copyFrom = [&own, i](const World &from, bool withMarble) {
        for (int k = 0, j = 0; k < own.marbleCount(); ++k) {
            if (!withMarble && k == i)
                continue;
            const auto to = static_cast<std::size_t>(k);
            const auto at = static_cast<std::size_t>(j++);
            own.position[to] = from.position[at];
            own.velocity[to] = from.velocity[at];
            own.lastHit[to] = from.lastHit[at];
        }
    };
    if (frame == removed.frame && startedAgainAt(removed) && removed.before.marbleCount() == own.marbleCount()) {
        // Where it was removed, the comparison started again there: back to its state and start then.
        copyFrom(removed.before, true);
        takeBackStart(removed);
    } else if (frame < removed.frame && m_world->frame == frame && m_world->marbleCount() + 1 == own.marbleCount()) {
        // Stepped back past the removal: its state here, and the marble's from its kept frames.
        const std::optional<FrameHistory::MarbleStart> state = removed.track.stateAt(frame, m_history.startFrame());
        if (!state)
            return false;
        copyFrom(*m_world, false);
        const auto k = static_cast<std::size_t>(i);
        own.position[k] = state->position;
        own.velocity[k] = state->velocity;
        own.lastHit[k] = state->lastHit;
    } else {
        return false;
    }
    takeOwnState(std::move(own));
    return true;
}

CompareRun::BeforeEdit CompareRun::beforeEdit(int i) const
{
    return {i, m_world->frame, *m_world, m_startFrame, m_earlierStarts.size()};
}

bool CompareRun::startedAgainAt(const BeforeEdit &edit) const
{
    return m_startFrame == edit.frame && m_earlierStarts.size() > edit.earlierStarts;
}

void CompareRun::takeBackStart(const BeforeEdit &edit)
{
    m_startFrame = edit.startFrame;
    m_earlierStarts.resize(edit.earlierStarts);
}

void CompareRun::takeOwnState(World own)
{
    const World &source = m_document->world();
    // The pushes still to act are the document's (a click gives both the same).
    own.acceleration = source.acceleration;
    *m_world = std::move(own);
    const std::int64_t kept = source.frame - m_firstGapFrame + 1;
    if (kept >= 1 && kept <= static_cast<std::int64_t>(m_gaps.size())) {
        m_gaps.resize(static_cast<std::size_t>(kept));
        m_gaps.back() = largestGap(source.position, m_world->position);
    }
    retakeGaps();
}

void CompareRun::onMarbleAdded(int i)
{
    const World &source = m_document->world();
    if (!isTracking() || m_world->frame != source.frame || m_world->marbleCount() + 1 != source.marbleCount()
        || m_history.startSize() + 1 != source.marbleCount())
        return; // the timelineReset() that follows restarts it
    Added added{beforeEdit(i)};
    // In its first frame as the document's: where it was added (Home replays the scene with it).
    const auto k = static_cast<std::size_t>(i);
    FrameHistory::MarbleTrack track;
    track.start = {source.position[k], source.velocity[k], source.acceleration[k], source.lastHit[k]};
    added.setAside = m_history.insertMarble(i, track);
    if (added.setAside == 0)
        return; // no frame kept before it: it restarts
    m_added.push_back(std::move(added));
    m_followedStructure = true; // sceneChanged() starts it again from the scene, its frames kept
}

void CompareRun::onAddUndone(int i)
{
    const World &source = m_document->world();
    if (m_added.empty() || m_added.back().marble != i)
        return; // restarted since: the timelineReset() that follows restarts it again
    Added added = std::move(m_added.back());
    m_added.pop_back();
    if (!isTracking() || m_world->frame != source.frame || source.frame != added.frame
        || m_history.startSize() != source.marbleCount() + 1 || added.before.marbleCount() != source.marbleCount())
        return;
    m_history.removeMarble(i);
    if (!m_history.takeBackSetAside(added.setAside, added.before))
        return; // it restarts
    // Its state and start before the add: the add had started it again at this frame.
    if (startedAgainAt(added))
        takeBackStart(added);
    if (m_earlierLargest.marble == i)
        m_earlierLargest = {};
    takeOwnState(std::move(added.before));
    m_followedStructure = true;
    m_restoredOwnState = true;
}

void CompareRun::retakeGaps()
{
    // The largest gap of the frames forgotten, then the gaps of the frames up to this one, as
    // they were measured then, taken again in order.
    resetGaps(m_startFrame);
    if (m_earlierLargest.px > 0.0 && m_earlierLargestFrame > m_startFrame)
        takeGap(m_earlierLargest, m_earlierLargestFrame);
    for (std::size_t k = 0; k < m_gaps.size(); ++k) {
        const std::int64_t at = m_firstGapFrame + static_cast<std::int64_t>(k);
        if (at > m_startFrame) // since the start this frame belongs to
            takeGap(m_gaps[k], at);
    }
}

void CompareRun::onTimelineReset()
{
    if (std::exchange(m_followedStructure, false))
        return;
    restart();
}

CompareRun::Gap CompareRun::largestGap(const std::vector<Vec2> &a, const std::vector<Vec2> &b)
{
    Gap largest;
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i) {
        const double gap = distance(a[i], b[i]);
        // A strict ">" keeps the first marble among equal gaps, and skips a NaN.
        if (gap > largest.px)
            largest = {gap, static_cast<int>(i)};
    }
    return largest;
}

void CompareRun::remeasureKeptGaps()
{
    const FrameHistory &document = m_document->history();
    for (std::size_t k = 0; k < m_gaps.size(); ++k) {
        const std::int64_t at = m_firstGapFrame + static_cast<std::int64_t>(k);
        const std::vector<Vec2> *ours = document.positionsAt(at);
        const std::vector<Vec2> *theirs = m_history.positionsAt(at);
        // A frame set aside at a marble added (or forgotten by one history) keeps its gap: it
        // comes back with the marbles it was measured with, once the add is undone (its gap had
        // become 0, and so had the largest gap before the add).
        if (ours && theirs && ours->size() == theirs->size())
            m_gaps[k] = largestGap(*ours, *theirs);
    }
}

const std::vector<Vec2> *CompareRun::velocitiesAt(std::int64_t frame) const
{
    return isTracking() ? m_history.velocitiesAt(frame, *m_world) : nullptr;
}

void CompareRun::rewindTo(std::int64_t frame)
{
    // Back past the edits that started the comparison again: the comparison before them.
    while (frame < m_startFrame && !m_earlierStarts.empty()) {
        m_startFrame = m_earlierStarts.back();
        m_earlierStarts.pop_back();
    }
    // Back to the first start, or to a frame before it: a restart there gives the same state.
    // (At a later start the frames before it are kept: its own state there is stepped back to.)
    if (!isTracking() || frame < m_startFrame || (frame == m_startFrame && m_earlierStarts.empty())
        || m_world->marbleCount() != m_document->world().marbleCount()) {
        restart();
        return;
    }
    while (m_world->frame > frame && m_history.stepBack(*m_world)) {
    }
    // The gaps kept up to this frame (its own included).
    const std::int64_t kept = frame - m_firstGapFrame + 1;
    if (m_world->frame != frame || kept < 1 || kept > static_cast<std::int64_t>(m_gaps.size())) {
        restart(); // the history no longer holds that frame
        return;
    }
    m_gaps.resize(static_cast<std::size_t>(kept));
    retakeGaps();
    if (m_ghost)
        m_ghost->syncFromWorld();
}

void CompareRun::onFrameAdvanced()
{
    if (!isTracking())
        return;
    const World &source = m_document->world();
    // A marble held by the mouse is moved by the hand, not by either model: follow the document.
    // A frame count that does not match means frames ran that this object did not see.
    if (m_document->heldMarble() >= 0 || m_world->frame + 1 != source.frame
        || m_world->marbleCount() != source.marbleCount()) {
        restart();
        return;
    }
    m_history.record(*m_world);
    const StepResult result = m_world->step();
    if (!result.finite) {
        m_problem = tr("the %1 model stopped at frame %2: marble %3 left finite numbers")
                        .arg(QString::fromUtf8(modelName(*m_model).data(),
                                               static_cast<qsizetype>(modelName(*m_model).size())))
                        .arg(m_world->frame)
                        .arg(result.badMarble);
        updateGhost();
        Q_EMIT restarted();
        return;
    }
    measureGap();
    Q_EMIT advanced();
}

void CompareRun::onStepped()
{
    if (!isTracking())
        return;
    const World &source = m_document->world();
    if (m_document->heldMarble() >= 0 && m_world->position != source.position) {
        restart();
        return;
    }
    // A click on a marble (SceneDocument::pushMarble) only adds to the pending acceleration, to
    // act on the next frame. Between frames both worlds hold the same frame, and pending
    // accelerations are zero after every frame in every model except for pushes: copying the
    // document's gives the comparison marble the very same push, a = (p - c) * pushScale / m.
    if (m_world->frame == source.frame && m_world->marbleCount() == source.marbleCount())
        m_world->acceleration = source.acceleration;
    if (m_ghost)
        m_ghost->syncFromWorld();
}

void CompareRun::measureGap()
{
    const Gap current = largestGap(m_document->world().position, m_world->position);
    m_gaps.push_back(current);
    takeGap(current, m_world->frame);
    // Only the frames the history can still step back to need their own gap; of the others the
    // largest is enough (the history forgets its oldest frames past its budget).
    // (Those set aside at a marble added mid-run, which its undo gives back, count too.)
    const std::int64_t oldest
        = m_world->frame - static_cast<std::int64_t>(m_history.size() + m_history.setAsideSize());
    while (m_firstGapFrame < oldest && !m_gaps.empty()) {
        if (m_gaps.front().px > m_earlierLargest.px) {
            m_earlierLargest = m_gaps.front();
            m_earlierLargestFrame = m_firstGapFrame;
        }
        m_gaps.pop_front();
        ++m_firstGapFrame;
    }
}

void CompareRun::clearGapList(std::int64_t start)
{
    m_gaps.clear();
    m_firstGapFrame = start + 1;
    m_earlierLargest = {};
    m_earlierLargestFrame = start;
}

void CompareRun::resetGaps(std::int64_t frame)
{
    m_currentGap = 0.0;
    m_currentGapMarble = -1;
    m_largestGap = 0.0;
    m_largestGapMarble = -1;
    m_largestGapFrame = frame;
}

void CompareRun::takeGap(const Gap &gap, std::int64_t frame)
{
    m_currentGap = gap.px;
    m_currentGapMarble = gap.marble;
    // Strict again: the earliest frame keeps the largest gap among equal ones.
    if (gap.px > m_largestGap) {
        m_largestGap = gap.px;
        m_largestGapMarble = gap.marble;
        m_largestGapFrame = frame;
    }
}

QString CompareRun::summary() const
{
    if (!m_model)
        return QString();
    const std::string_view name = modelName(*m_model);
    const QString model = QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size()));
    if (!m_problem.isEmpty())
        return tr("Compare: %1 - not running: %2").arg(model, m_problem);
    // After a restart the gap counts from the restart, and the readout says so.
    const QString since = m_startFrame > 0 ? tr(" since frame %1").arg(m_startFrame) : QString();
    if (m_largestGapMarble < 0)
        return tr("Compare: %1 - largest gap 0 px%2").arg(model, since);
    return tr("Compare: %1 - largest gap %2 px (marble %3, frame %4)%5")
        .arg(model)
        .arg(shownNumber(m_largestGap, 'f', 1))
        .arg(m_largestGapMarble)
        .arg(m_largestGapFrame)
        .arg(since);
}

void CompareRun::setStage(QGraphicsScene *scene)
{
    if (scene == m_stage)
        return;
    removeGhost();
    if (m_stage)
        disconnect(m_stage, nullptr, this, nullptr);
    m_stage = scene;
    if (m_stage) {
        // The scene deletes its items when it dies: forget the ghost then, never delete it twice.
        connect(m_stage, &QObject::destroyed, this, [this] { m_ghost = nullptr; });
    }
    updateGhost();
}

void CompareRun::updateGhost()
{
    if (!m_stage || !isTracking()) {
        removeGhost();
        return;
    }
    if (!m_ghost) {
        m_ghost = new MarbleFieldItem(m_world.get(), MarbleFieldItem::Style::Ghost);
        m_ghost->setZValue(kGhostZValue);
        // Clicks and drags go to the document's marbles underneath, never to their ghosts.
        m_ghost->setAcceptedMouseButtons(Qt::NoButton);
        m_ghost->setAcceptHoverEvents(false);
        m_stage->addItem(m_ghost);
    }
    m_ghost->setWorld(m_world.get());
    m_ghost->setTints(m_tints);
}

void CompareRun::setTints(const QList<QPair<int, QColor>> &tints)
{
    m_tints = tints;
    if (m_ghost)
        m_ghost->setTints(m_tints);
}

void CompareRun::removeGhost()
{
    if (!m_ghost)
        return;
    if (m_stage)
        m_stage->removeItem(m_ghost);
    delete m_ghost;
    m_ghost = nullptr;
}

} // namespace marbles
