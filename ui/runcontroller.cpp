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
    // the remainder waits for the next tick.
    m_accumulatedMs += static_cast<double>(m_clock.nsecsElapsed()) / 1.0e6 * m_speed;
    m_clock.restart();
    const double ms = frameMs();
    int frames = static_cast<int>(std::floor(m_accumulatedMs / ms));
    if (frames > kMaxFramesPerTick) {
        frames = kMaxFramesPerTick;
        m_accumulatedMs = 0.0;
    } else {
        m_accumulatedMs -= frames * ms;
    }
    if (frames <= 0)
        return;
    m_document->advance(frames);
}

} // namespace marbles
