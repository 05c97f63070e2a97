#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

namespace marbles {

class SceneDocument;

/// Runs the simulation in real time: a precise timer ticks, and each tick simulates as many
/// frames as the wall clock (times the run speed) has accumulated, so the speed stays right when
/// a tick comes late. At most kMaxFramesPerTick frames are caught up per tick: when the machine
/// cannot keep up, the run slows down instead of freezing the window.
class RunController : public QObject {
    Q_OBJECT

public:
    /// Most frames simulated in one tick.
    static constexpr int kMaxFramesPerTick = 16;
    /// Slowest and fastest run speeds.
    static constexpr double kMinSpeed = 0.1;
    static constexpr double kMaxSpeed = 4.0;

    /// Runs `document` (which must outlive this).
    explicit RunController(SceneDocument *document, QObject *parent = nullptr);

    /// True while the run is going.
    bool isRunning() const { return m_timer.isActive(); }
    /// Run speed, simulated time per wall-clock time (1 = real time).
    double speed() const { return m_speed; }
    /// Sets the run speed, clamped to [kMinSpeed, kMaxSpeed].
    void setSpeed(double speed);

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
};

} // namespace marbles
