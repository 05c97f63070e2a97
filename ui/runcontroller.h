#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

namespace marbles {

class SceneDocument;

/// Runs the simulation in real time: a precise timer ticks, and each tick simulates as many
/// frames as the wall clock (times the run speed) has accumulated, so the speed stays right when
/// a tick comes late. When the machine cannot keep up, the run slows down instead of catching
/// up in bursts: a tick simulates at most kMaxFramesPerTick frames, and no more than fit in its
/// work budget at the cost the last tick measured per frame (at least one), so that the stage
/// is still redrawn some 25 times a second. The speed actually achieved is measured.
class RunController : public QObject {
    Q_OBJECT

public:
    /// Most frames simulated in one tick.
    static constexpr int kMaxFramesPerTick = 16;
    /// Slowest and fastest run speeds.
    static constexpr double kMinSpeed = 0.1;
    static constexpr double kMaxSpeed = 4.0;
    /// Default wall-clock time a tick may spend simulating (the rest of a display frame paints).
    static constexpr double kDefaultTickBudgetMs = 33.0;
    /// The achieved speed is measured over windows at least this long.
    static constexpr qint64 kSpeedWindowMs = 1000;

    /// Frames a tick runs when `owed` are due and each recently took `workMsPerFrame` of wall
    /// clock (0: not measured yet): all of them up to `maxFrames`, but only as many as fit in
    /// `budgetMs`, and always at least one.
    static int framesForTick(int owed, double workMsPerFrame, double budgetMs, int maxFrames = kMaxFramesPerTick);
    /// Most frames a tick of `tickMs` runs at `speed` with frames of `frameMs`: kMaxFramesPerTick,
    /// or twice the frames such a tick is due where that is more (short frames at a high speed:
    /// 1 ms frames at 4x are 64 a 16-ms tick, which 16 a tick held to a quarter of it).
    static int maxFramesForTick(double tickMs, double speed, double frameMs);

    /// Runs `document` (which must outlive this).
    explicit RunController(SceneDocument *document, QObject *parent = nullptr);

    /// True while the run is going.
    bool isRunning() const { return m_timer.isActive(); }
    /// Run speed, simulated time per wall-clock time (1 = real time).
    double speed() const { return m_speed; }
    /// Sets the run speed, clamped to [kMinSpeed, kMaxSpeed].
    void setSpeed(double speed);
    /// Wall-clock time a tick may spend simulating, in ms (kDefaultTickBudgetMs unless set).
    double tickBudgetMs() const { return m_tickBudgetMs; }
    void setTickBudgetMs(double ms);
    /// Simulated time per wall-clock time over the last full measuring window of this run
    /// (0 until one has passed).
    double achievedSpeed() const { return m_achievedSpeed; }
    /// True while running and the last window's achieved speed fell short of the chosen speed
    /// by more than 5 %: the frames take longer to compute than they last.
    bool isFallingBehind() const;

    /// Starts the run.
    void play();
    /// Stops the run.
    void pause();
    /// Starts or stops the run.
    void toggle();

Q_SIGNALS:
    /// The run started or stopped.
    void runningChanged(bool running);

private:
    void tick();
    void updateInterval();
    double frameMs() const;

    SceneDocument *m_document;
    QTimer m_timer;
    QElapsedTimer m_clock;
    double m_speed = 1.0;
    double m_accumulatedMs = 0.0;
    double m_tickBudgetMs = kDefaultTickBudgetMs;
    double m_workMsPerFrame = 0.0;  // wall clock per frame in the last tick (0: none yet)
    QElapsedTimer m_speedClock;     // the current measuring window
    double m_windowSimulatedMs = 0.0;
    double m_achievedSpeed = 0.0;
};

} // namespace marbles
