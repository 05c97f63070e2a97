#include "ui/runcontroller.h"

#include "ui/scenedocument.h"

#include <algorithm>
#include <cmath>

namespace marbles {

namespace {

/// Ticks come no faster than this (about a 60 Hz display): faster runs simulate several frames per tick.
constexpr double kMinTickMs = 16.0;

} // namespace

RunController::RunController(SceneDocument *document, QObject *parent)
    : QObject(parent)
    , m_document(document)
{
    m_timer.setTimerType(Qt::PreciseTimer);
    connect(&m_timer, &QTimer::timeout, this, &RunController::tick);
    connect(m_document, &SceneDocument::sceneChanged, this, &RunController::updateInterval);
    connect(m_document, &SceneDocument::simulationFailed, this, &RunController::pause);
}

double RunController::frameMs() const
{
    const double ms = m_document->world().params.frameMs;
    return std::isfinite(ms) && ms > 0.0 ? ms : 20.0;
}

void RunController::setSpeed(double speed)
{
    m_speed = std::clamp(speed, kMinSpeed, kMaxSpeed);
    updateInterval();
}

void RunController::setTickBudgetMs(double ms)
{
    m_tickBudgetMs = std::isfinite(ms) && ms > 0.0 ? ms : kDefaultTickBudgetMs;
}

bool RunController::isFallingBehind() const
{
    return isRunning() && m_achievedSpeed > 0.0 && m_achievedSpeed < 0.95 * m_speed;
}

int RunController::framesForTick(int owed, double workMsPerFrame, double budgetMs, int maxFrames)
{
    int frames = std::min(owed, maxFrames);
    if (workMsPerFrame > 0.0 && frames * workMsPerFrame > budgetMs)
        frames = static_cast<int>(std::clamp(std::floor(budgetMs / workMsPerFrame), 1.0, static_cast<double>(frames)));
    return std::max(frames, 0);
}

int RunController::maxFramesForTick(double tickMs, double speed, double frameMs)
{
    const double due = 2.0 * tickMs * speed / frameMs;
    return std::isfinite(due) && due > kMaxFramesPerTick ? static_cast<int>(std::min(std::ceil(due), 1.0e6))
                                                         : kMaxFramesPerTick;
}

void RunController::updateInterval()
{
    // One frame per tick at the scene's frameMs and speed, but not faster than the display.
    const double interval = std::max(kMinTickMs, frameMs() / m_speed);
    m_timer.setInterval(static_cast<int>(std::lround(std::min(interval, 1000.0))));
}

void RunController::play()
{
    if (isRunning())
        return;
    updateInterval();
    m_clock.start();
    m_speedClock.start();
    m_windowSimulatedMs = 0.0;
    m_achievedSpeed = 0.0;
    m_timer.start();
    Q_EMIT runningChanged(true);
    // The first frame follows at once: pressing Play shows motion without waiting a tick.
    m_accumulatedMs = frameMs();
    tick();
}

void RunController::pause()
{
    if (!isRunning())
        return;
    m_timer.stop();
    Q_EMIT runningChanged(false);
}

void RunController::toggle()
{
    if (isRunning())
        pause();
    else
        play();
}

void RunController::tick()
{
    // Simulated time owed = wall time since the last tick times the speed; whole frames are run,
    // the remainder waits for the next tick. What the budget leaves out is dropped, not owed:
    // a run that cannot keep up goes slower, it does not fall further and further behind.
    m_accumulatedMs += static_cast<double>(m_clock.nsecsElapsed()) / 1.0e6 * m_speed;
    m_clock.restart();
    const double ms = frameMs();
    const int owed = static_cast<int>(std::min(std::floor(m_accumulatedMs / ms), 1.0e6));
    const int frames =
        framesForTick(owed, m_workMsPerFrame, m_tickBudgetMs, maxFramesForTick(m_timer.interval(), m_speed, ms));
    if (frames < owed)
        m_accumulatedMs = 0.0;
    else
        m_accumulatedMs -= frames * ms;
    if (frames > 0) {
        QElapsedTimer work;
        work.start();
        const int done = m_document->advance(frames);
        if (done > 0)
            m_workMsPerFrame = static_cast<double>(work.nsecsElapsed()) / 1.0e6 / done;
        m_windowSimulatedMs += done * ms;
    }
    const qint64 window = m_speedClock.elapsed();
    if (window >= kSpeedWindowMs) {
        m_achievedSpeed = m_windowSimulatedMs / static_cast<double>(window);
        m_windowSimulatedMs = 0.0;
        m_speedClock.restart();
    }
}

} // namespace marbles
