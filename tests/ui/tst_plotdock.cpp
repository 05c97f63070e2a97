#include "core/presets.h"
#include "core/world.h"
#include "ui/marbleitem.h"
#include "ui/plotdock.h"
#include "ui/ringbuffer.h"
#include "tests/ui/filesizelimit.h"

#include <QApplication>
#include <QChart>
#include <QChartView>
#include <QCheckBox>
#include <QDir>
#include <QFile>
#include <QGraphicsScene>
#include <QGraphicsTextItem>
#include <QHelpEvent>
#include <QImage>
#include <QLabel>
#include <QLegend>
#include <QLegendMarker>
#include <QLineSeries>
#include <QRadioButton>
#include <QScopeGuard>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QSet>
#include <QTest>
#include <QToolTip>
#include <QCategoryAxis>
#include <QValueAxis>

#include <cmath>
#include <sys/stat.h>
#include <deque>
#include <limits>
#include <map>

using namespace marbles;

class TestPlotDock : public QObject {
    Q_OBJECT

private slots:
    void ringBuffer_data();
    void randomTimelineKeepsTheRightSamples_data();
    void randomTimelineKeepsTheRightSamples();
    void ringBuffer();
    void oneSamplePerFrame_data();
    void oneSamplePerFrame();
    void speedsAndTotals_data();
    void speedsAndTotals();
    void resetClears();
    void cutAfterKeepsEarlierFrames_data();
    void cutAfterKeepsEarlierFrames();
    void plottedMarbles_data();
    void plottedMarbles();
    void selectionKeepsHistory();
    void unselectingBringsTheFirstMarblesBackWhole();
    void lineColoursAreNotTheStagesBlue();
    void newLineTakesEarlierSpeeds();
    void lineColours();
    void chartGetsSamples();
    void hugeSpeedsArePlotted();
    void momentumAxisReadsZeroAtZero();
    void topLabelsStayOnTheChart();
    void pausedComparisonKeepsItsEarlierLines();
    void liveRefresh();
    void refreshMovesAxesOnlyWhenTheirRangeChanges();
    void thinningKeepsSpikes();
    void thinningFollowsThePlotWidth();
    void secondsAxis();
    void frameAxisTicksAreWholeFrames_data();
    void frameAxisTicksAreWholeFrames();
    void legendLabelsFitTheRow();
    void legendListsMarblesInOrder();
    void totalsStayOverTheSpeedLines();
    void editsThatMakeTheLinesJumpAreMarked();
    void editedLinesJumpAtTheirMark();
    void comparedLinesJumpAtEditsAndRestarts();
    void shortChartKeepsItsLabelsWhole();
    void restartMarkedOnlyAfterADashedLine();
    void legendNamesEveryModelOfTheLines();
    void totalsOnRequest();
    void hoverShowsExactValues_data();
    void hoverShowsExactValues();
    void hoverNamesLinesOnTopOfEachOther();
    void exportCsv();
    void exportCsvError();
    void exportPng();
    void axesAreWrittenInTheDesktopsLanguage();
    void exportsAreOfferedByTheScenesName();
};

namespace {

/// Marbles at rest in a row; radius r gives mass 1.25 r.
/// Frames' velocities as a test keeps them, by frame number.
using KeptFrames = std::map<std::int64_t, std::vector<Vec2>>;

/// A velocity lookup for PlotDock::setVelocityLookup() that answers from `frames` (which must
/// outlive it), as Step Back's history does.
PlotDock::VelocityLookup lookupIn(const KeptFrames &frames)
{
    return [&frames](std::int64_t frame) -> const std::vector<Vec2> * {
        const auto it = frames.find(frame);
        return it == frames.end() ? nullptr : &it->second;
    };
}

World worldWith(int marbles)
{
    World world;
    for (int i = 0; i < marbles; ++i)
        world.addMarble({50.0 + 30.0 * i, 100.0}, 10.0);
    return world;
}

/// The labels of the legend's entries shown, in order.
QStringList shownLegendLabels(PlotDock &dock)
{
    QStringList shown;
    for (QLegendMarker *marker : dock.chartView()->chart()->legend()->markers()) {
        if (marker->isVisible())
            shown << marker->label();
    }
    return shown;
}

/// Sets every marble's velocity from the frame number (a different, known speed per frame) and
/// records the frame: frames 1..n.
void runFrames(PlotDock &dock, World &world, int n, const World *compare = nullptr)
{
    for (int f = 1; f <= n; ++f) {
        world.frame = f;
        for (int i = 0; i < world.marbleCount(); ++i)
            world.velocity[static_cast<std::size_t>(i)] = {0.01 * f, -0.5 * i};
        dock.appendFrame(world, compare);
    }
}

/// Gives `dock` the scene `world` (compared with `compareModel`, unless empty), `frames` frames of
/// it, and shows it at `size`; false if the window never showed.
bool showRun(PlotDock &dock, World &world, int frames, QSize size, const QString &compareModel = {})
{
    dock.reset(world);
    if (!compareModel.isEmpty())
        dock.setCompareModel(compareModel);
    runFrames(dock, world, frames);
    dock.resize(size);
    dock.show();
    return QTest::qWaitForWindowExposed(&dock);
}

/// Gives `dock` the scene `world` compared with the exact model, `frames` frames of it, and shows
/// it `width` px wide, its chart refreshed; false if the window never showed.
bool showComparing(PlotDock &dock, World &world, int frames, int width)
{
    if (!showRun(dock, world, frames, QSize(width, 350), QStringLiteral("exact")))
        return false;
    dock.refreshChart();
    return true;
}

/// The titles of `dock`'s chart's axes, in the chart's order.
QStringList axisTitles(PlotDock &dock)
{
    QStringList titles;
    for (QAbstractAxis *axis : dock.chartView()->chart()->axes())
        titles << axis->titleText();
    return titles;
}

/// The horizontal (time) axis of `line`.
QValueAxis *timeAxisOf(QLineSeries *line)
{
    return qobject_cast<QValueAxis *>(line->attachedAxes().value(0));
}

/// The vertical axis of `line` (speed, or the totals').
QValueAxis *valueAxisOf(QLineSeries *line)
{
    return qobject_cast<QValueAxis *>(line->attachedAxes().value(1));
}

/// The values of `line`'s points at x, in the order drawn (two at a jump).
QList<qreal> valuesAt(QLineSeries *line, double x)
{
    QList<qreal> ys;
    for (const QPointF &p : line->points()) {
        if (p.x() == x)
            ys << p.y();
    }
    return ys;
}

/// The values drawn are those expected, to a relative 1e-12.
bool sameValues(const QList<qreal> &drawn, const QList<qreal> &expected)
{
    if (drawn.size() != expected.size())
        return false;
    for (qsizetype k = 0; k < drawn.size(); ++k) {
        if (std::abs(drawn[k] - expected[k]) > 1e-12 * std::max(1.0, std::abs(expected[k])))
            return false;
    }
    return true;
}

double maxY(const QLineSeries *series)
{
    double m = -std::numeric_limits<double>::infinity();
    for (const QPointF &p : series->points())
        m = std::max(m, p.y());
    return m;
}

} // namespace

void TestPlotDock::randomTimelineKeepsTheRightSamples_data()
{
    QTest::addColumn<int>("capacity");
    QTest::addColumn<int>("seed");
    QTest::addRow("capacity 5000") << 5000 << 1;
    QTest::addRow("capacity 40, the oldest samples dropped") << 40 << 2;
    QTest::addRow("capacity 7") << 7 << 3;
}

void TestPlotDock::randomTimelineKeepsTheRightSamples()
{
    // A run as the window drives the dock: frames appended, Step Back and Back to Start cutting
    // the samples after the frame they return to (and the run going on from there, along a new
    // timeline), the marbles plotted changing (a newly plotted one takes its speeds for the
    // samples held from the kept frames), the comparison turned on and off, and a new scene now
    // and then. After each action the dock must hold exactly the newest frames of the current
    // timeline, up to its capacity, each with the speeds of the marbles plotted, the totals and,
    // while comparing, the comparison's.
    QFETCH(int, capacity);
    QFETCH(int, seed);
    constexpr int kMarbles = 20;
    PlotDock dock;
    dock.setCapacity(capacity);
    World world = worldWith(kMarbles);
    for (int i = 0; i < kMarbles; ++i)
        world.setRadius(i, 5.0 + i);
    KeptFrames kept;        // the current timeline's velocities
    KeptFrames compareKept; // the comparison's, while comparing
    dock.setVelocityLookup(lookupIn(kept), lookupIn(compareKept));
    dock.reset(world);
    SplitMix64 rng(static_cast<std::uint64_t>(seed));
    std::deque<std::int64_t> held; // the frames the dock must hold, oldest first
    bool comparing = false;
    QList<int> plotted; // empty: the first kMaxPlottedMarbles
    const auto speedOf = [](Vec2 v) { return std::sqrt(v.x * v.x + v.y * v.y); };
    const auto close = [](double actual, double expected) {
        return std::abs(actual - expected) <= 1e-12 * std::max(1.0, std::abs(expected));
    };
    std::int64_t frame = 0;
    for (int action = 0; action < 400; ++action) {
        switch (rng.below(10)) {
        case 0:
        case 1:
        case 2:
        case 3:
            for (int f = 1 + rng.below(12); f > 0; --f) {
                world.frame = ++frame;
                std::vector<Vec2> compare(kMarbles);
                for (int i = 0; i < kMarbles; ++i) {
                    world.velocity[static_cast<std::size_t>(i)] = {rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)};
                    compare[static_cast<std::size_t>(i)] = {rng.uniform(-5.0, 5.0), 0.0};
                }
                kept[frame] = world.velocity;
                World other = world;
                other.velocity = compare;
                if (comparing)
                    compareKept[frame] = compare;
                dock.appendFrame(world, comparing ? &other : nullptr);
                held.push_back(frame);
                if (static_cast<int>(held.size()) > capacity)
                    held.pop_front(); // the oldest sample makes room
            }
            break;
        case 4:
        case 5: {
            // Step Back (or Back to Start): the samples after the frame returned to go.
            const std::int64_t to = std::max<std::int64_t>(0, frame - 1 - rng.below(15));
            dock.cutAfter(to);
            while (!held.empty() && held.back() > to)
                held.pop_back();
            kept.erase(kept.upper_bound(to), kept.end());
            compareKept.erase(compareKept.upper_bound(to), compareKept.end());
            frame = to;
            break;
        }
        case 6: {
            plotted.clear();
            for (int k = rng.below(5); k > 0; --k) {
                const int i = rng.below(kMarbles);
                if (!plotted.contains(i))
                    plotted << i;
            }
            dock.setSelectedMarbles(plotted);
            break;
        }
        case 7:
            comparing = !comparing;
            dock.setCompareModel(comparing ? QStringLiteral("exact") : QString());
            compareKept.clear(); // a new comparison forgets the samples of any other
            break;
        case 8:
            if (rng.below(4) == 0) {
                // A new scene, or marbles added or removed: the samples start over from the
                // current frame on (the window calls startAt(); reset() alone holds none).
                world.frame = frame;
                kept.clear();
                compareKept.clear();
                held.clear();
                if (rng.below(2) == 0) {
                    dock.reset(world);
                } else {
                    dock.startAt(world);
                    held.push_back(frame);
                    kept[frame] = world.velocity;
                }
            } else if (rng.below(2) == 0) {
                // An edit that keeps the marbles: the current frame's sample is taken again (or
                // added, where the buffer no longer holds it), the earlier ones stay.
                world.frame = frame;
                for (int i = 0; i < kMarbles; ++i)
                    world.velocity[static_cast<std::size_t>(i)] = {rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)};
                kept[frame] = world.velocity;
                if (comparing)
                    compareKept[frame] = world.velocity; // the comparison restarts from the edited world
                dock.resample(world, comparing ? &world : nullptr);
                if (held.empty() || held.back() != frame) {
                    held.push_back(frame);
                    if (static_cast<int>(held.size()) > capacity)
                        held.pop_front();
                }
            }
            break;
        default:
            dock.refreshChart();
            break;
        }
        const QString where = QStringLiteral("action %1, frame %2").arg(action).arg(frame);
        QCOMPARE(dock.sampleCount(), static_cast<qsizetype>(held.size()));
        QList<int> expectedPlotted = plotted;
        if (expectedPlotted.isEmpty()) {
            for (int i = 0; i < PlotDock::kMaxPlottedMarbles; ++i)
                expectedPlotted << i;
        }
        QCOMPARE(dock.plottedMarbles(), expectedPlotted);
        for (qsizetype k = 0; k < dock.sampleCount(); ++k) {
            const std::int64_t f = held[static_cast<std::size_t>(k)];
            QCOMPARE(dock.sampleFrame(k), f);
            const std::vector<Vec2> &v = kept.at(f);
            double energy = 0.0;
            Vec2 momentum;
            for (int i = 0; i < kMarbles; ++i) {
                const double m = world.mass[static_cast<std::size_t>(i)];
                const Vec2 vi = v[static_cast<std::size_t>(i)];
                energy += 0.5 * m * (vi.x * vi.x + vi.y * vi.y);
                momentum.x += m * vi.x;
                momentum.y += m * vi.y;
            }
            QVERIFY2(close(dock.sampleKineticEnergy(k), energy), qPrintable(where));
            QVERIFY2(close(dock.sampleMomentum(k).x, momentum.x) && close(dock.sampleMomentum(k).y, momentum.y),
                     qPrintable(where));
            for (int i : expectedPlotted)
                QVERIFY2(close(dock.sampleSpeed(k, i), speedOf(v[static_cast<std::size_t>(i)])),
                         qPrintable(where + QStringLiteral(": marble %1, sample %2").arg(i).arg(k)));
            if (!comparing)
                continue;
            const auto c = compareKept.find(f);
            if (c == compareKept.end()) {
                QVERIFY2(std::isnan(dock.sampleCompareSpeed(k, expectedPlotted.front())), qPrintable(where));
                continue;
            }
            for (int i : expectedPlotted)
                QVERIFY2(close(dock.sampleCompareSpeed(k, i), speedOf(c->second[static_cast<std::size_t>(i)])),
                         qPrintable(where + QStringLiteral(": comparison, marble %1, sample %2").arg(i).arg(k)));
        }
    }
}

void TestPlotDock::ringBuffer_data()
{
    QTest::addColumn<int>("capacity");
    QTest::addColumn<int>("pushes");

    QTest::addRow("empty") << 4 << 0;
    QTest::addRow("partly full") << 4 << 3;
    QTest::addRow("exactly full") << 4 << 4;
    QTest::addRow("wrapped once") << 4 << 6;
    QTest::addRow("wrapped many times") << 4 << 103;
    QTest::addRow("capacity 1") << 1 << 5;
}

void TestPlotDock::ringBuffer()
{
    QFETCH(int, capacity);
    QFETCH(int, pushes);

    RingBuffer<int> ring(static_cast<std::size_t>(capacity));
    for (int v = 1; v <= pushes; ++v)
        ring.push(v);
    const int held = std::min(capacity, pushes);
    QCOMPARE(ring.size(), static_cast<std::size_t>(held));
    // The newest `held` values, oldest first.
    for (int i = 0; i < held; ++i)
        QCOMPARE(ring.at(static_cast<std::size_t>(i)), pushes - held + 1 + i);
    if (held > 0)
        QCOMPARE(ring.last(), pushes);

    // Dropping the newest entries (a step back) keeps the older ones in order, and later pushes
    // follow them, whether or not the buffer had wrapped around.
    for (std::size_t drop : {std::size_t(0), std::size_t(1), std::size_t(3)}) {
        RingBuffer<int> cut(static_cast<std::size_t>(capacity));
        for (int v = 1; v <= pushes; ++v)
            cut.push(v);
        cut.dropNewest(drop);
        const int kept = std::max(held - static_cast<int>(drop), 0);
        QCOMPARE(cut.size(), static_cast<std::size_t>(kept));
        for (int i = 0; i < kept; ++i)
            QCOMPARE(cut.at(static_cast<std::size_t>(i)), pushes - held + 1 + i);
        for (int v = 1; v <= 2; ++v)
            cut.push(1000 + v);
        const int after = std::min(kept + 2, capacity);
        QCOMPARE(cut.size(), static_cast<std::size_t>(after));
        QCOMPARE(cut.last(), 1002);
        if (after >= 2)
            QCOMPARE(cut.at(static_cast<std::size_t>(after - 2)), 1001);
        if (after > 2)
            QCOMPARE(cut.at(static_cast<std::size_t>(after - 3)), pushes - held + kept);
    }

    ring.clear();
    QVERIFY(ring.isEmpty());
    QCOMPARE(ring.capacity(), static_cast<std::size_t>(capacity));
}

void TestPlotDock::oneSamplePerFrame_data()
{
    QTest::addColumn<int>("capacity"); // 0: the default
    QTest::addColumn<int>("frames");

    QTest::addRow("one frame") << 0 << 1;
    QTest::addRow("ten frames") << 0 << 10;
    QTest::addRow("full") << 0 << int(PlotDock::kDefaultCapacity);
    QTest::addRow("one past full") << 0 << int(PlotDock::kDefaultCapacity) + 1;
    QTest::addRow("small buffer wrapped") << 10 << 25;
}

void TestPlotDock::oneSamplePerFrame()
{
    QFETCH(int, capacity);
    QFETCH(int, frames);

    PlotDock dock;
    if (capacity > 0)
        dock.setCapacity(capacity);
    const qsizetype bound = capacity > 0 ? capacity : PlotDock::kDefaultCapacity;
    QCOMPARE(dock.capacity(), bound);
    World world = worldWith(3);
    dock.reset(world);
    QCOMPARE(dock.sampleCount(), 0);
    runFrames(dock, world, frames);

    const qsizetype held = std::min<qsizetype>(frames, bound);
    QCOMPARE(dock.sampleCount(), held);
    // The newest frames are kept, in order, one sample each.
    for (qsizetype i = 0; i < held; ++i)
        QCOMPARE(dock.sampleFrame(i), std::int64_t(frames - held + 1 + i));
    // The speed columns wrap together with the frames: sample i holds frame i's speed 0.01 f.
    const std::int64_t f = dock.sampleFrame(0);
    QCOMPARE_LE(std::abs(dock.sampleSpeed(0, 0) - 0.01 * double(f)), 1e-12);
}

void TestPlotDock::speedsAndTotals_data()
{
    QTest::addColumn<double>("vx0");
    QTest::addColumn<double>("vy0");
    QTest::addColumn<double>("vx1");
    QTest::addColumn<double>("vy1");

    QTest::addRow("3-4-5") << 3.0 << 4.0 << -6.0 << 0.0;
    QTest::addRow("at rest") << 0.0 << 0.0 << 0.0 << 0.0;
    QTest::addRow("tiny") << -1e-3 << 2e-3 << 5e-9 << -5e-9;
    QTest::addRow("large") << 1e6 << -1e6 << -2.5e5 << 7.0;
    QTest::addRow("opposite momenta") << 2.0 << 0.0 << -4.0 << 0.0;
}

void TestPlotDock::speedsAndTotals()
{
    QFETCH(double, vx0);
    QFETCH(double, vy0);
    QFETCH(double, vx1);
    QFETCH(double, vy1);

    World world;
    world.addMarble({100, 100}, 10.0, {vx0, vy0}, 2.0);
    world.addMarble({300, 100}, 20.0, {vx1, vy1}, 1.0);
    world.frame = 7;
    PlotDock dock;
    dock.reset(world);
    dock.appendFrame(world);
    QCOMPARE(dock.sampleCount(), 1);
    QCOMPARE(dock.sampleFrame(0), std::int64_t(7));

    auto close = [](double actual, double expected) {
        return std::abs(actual - expected) <= 1e-12 * std::max(1.0, std::abs(expected));
    };
    QVERIFY(close(dock.sampleSpeed(0, 0), std::sqrt(vx0 * vx0 + vy0 * vy0)));
    QVERIFY(close(dock.sampleSpeed(0, 1), std::sqrt(vx1 * vx1 + vy1 * vy1)));
    const double kinetic = 0.5 * 2.0 * (vx0 * vx0 + vy0 * vy0) + 0.5 * 1.0 * (vx1 * vx1 + vy1 * vy1);
    const double px = 2.0 * vx0 + 1.0 * vx1;
    const double py = 2.0 * vy0 + 1.0 * vy1;
    QVERIFY(close(dock.sampleKineticEnergy(0), kinetic));
    QVERIFY(close(dock.sampleMomentum(0).x, px));
    QVERIFY(close(dock.sampleMomentum(0).y, py));
    QVERIFY(std::isnan(dock.sampleSpeed(0, 2))); // no such marble
}

void TestPlotDock::resetClears()
{
    PlotDock dock;
    World world = worldWith(4);
    dock.reset(world);
    runFrames(dock, world, 30);
    dock.refreshChart();
    QCOMPARE(dock.speedSeries(0)->count(), 30);

    World smaller = worldWith(2);
    dock.reset(smaller);
    QCOMPARE(dock.sampleCount(), 0);
    QCOMPARE(dock.plottedMarbles(), QList<int>({0, 1}));
    dock.refreshChart();
    QCOMPARE(dock.speedSeries(0)->count(), 0);
    QVERIFY(!dock.speedSeries(3));

    runFrames(dock, smaller, 5);
    QCOMPARE(dock.sampleCount(), 5);
    QCOMPARE(dock.sampleFrame(0), std::int64_t(1));

    // startAt(): the same, with the world as it is now for first sample, which a cut back to
    // that frame keeps.
    smaller.frame = 40;
    smaller.velocity[1] = {3.0, 4.0};
    dock.startAt(smaller);
    QCOMPARE(dock.sampleCount(), 1);
    QCOMPARE(dock.sampleFrame(0), std::int64_t(40));
    QCOMPARE(dock.sampleSpeed(0, 1), 5.0);
    dock.refreshChart();
    QVERIFY(dock.speedSeries(1)->pointsVisible()); // one sample: no line, so its point is drawn
    for (int f = 41; f <= 43; ++f) {
        smaller.frame = f;
        dock.appendFrame(smaller);
    }
    QCOMPARE(dock.sampleCount(), 4);
    dock.refreshChart();
    QVERIFY(!dock.speedSeries(1)->pointsVisible());
    dock.cutAfter(40);
    QCOMPARE(dock.sampleCount(), 1);
    QCOMPARE(dock.sampleFrame(0), std::int64_t(40));
}

void TestPlotDock::cutAfterKeepsEarlierFrames_data()
{
    QTest::addColumn<int>("capacity");
    QTest::addColumn<int>("frames");
    QTest::addColumn<int>("cutAt");

    QTest::addRow("one frame back") << 100 << 30 << 29;
    QTest::addRow("ten frames back") << 100 << 30 << 20;
    QTest::addRow("wrapped buffer") << 16 << 30 << 25;
    QTest::addRow("before every sample") << 16 << 30 << 10;
    QTest::addRow("at the newest frame") << 100 << 30 << 30;
}

void TestPlotDock::cutAfterKeepsEarlierFrames()
{
    QFETCH(int, capacity);
    QFETCH(int, frames);
    QFETCH(int, cutAt);

    PlotDock dock;
    dock.setCapacity(capacity);
    World world = worldWith(3);
    dock.reset(world);
    dock.setCompareModel(QStringLiteral("exact"));
    World compare = world;
    for (int f = 1; f <= frames; ++f) {
        world.frame = f;
        compare.frame = f;
        for (int i = 0; i < world.marbleCount(); ++i) {
            world.velocity[static_cast<std::size_t>(i)] = {0.01 * f, -0.5 * i};
            compare.velocity[static_cast<std::size_t>(i)] = {0.02 * f, 0.0};
        }
        dock.appendFrame(world, &compare);
    }
    dock.cutAfter(cutAt);
    // Speeds are |v| of the velocities set above, to rounding.
    auto close = [](double actual, double expected) {
        return std::abs(actual - expected) <= 1e-12 * std::max(1.0, std::abs(expected));
    };

    // Frames first..cutAt stay, first being the oldest frame the buffer held.
    const int first = std::max(1, frames - capacity + 1);
    const int kept = std::max(0, cutAt - first + 1);
    QCOMPARE(dock.sampleCount(), static_cast<qsizetype>(kept));
    for (int k = 0; k < kept; ++k) {
        const int f = first + k;
        QCOMPARE(dock.sampleFrame(k), std::int64_t(f));
        QVERIFY(close(dock.sampleSpeed(k, 0), 0.01 * f));
        QVERIFY(close(dock.sampleCompareSpeed(k, 0), 0.02 * f));
    }
    dock.refreshChart();
    QCOMPARE(dock.speedSeries(1)->count(), kept);
    QCOMPARE(dock.compareSeries(1)->count(), kept);

    // The run goes on from the frame after the cut, every line aligned with the frames.
    world.frame = cutAt + 1;
    world.velocity[0] = {7.0, 0.0};
    compare.velocity[0] = {8.0, 0.0};
    dock.appendFrame(world, &compare);
    const qsizetype last = dock.sampleCount() - 1;
    QCOMPARE(dock.sampleCount(), static_cast<qsizetype>(std::min(kept + 1, capacity)));
    QCOMPARE(dock.sampleFrame(last), std::int64_t(cutAt + 1));
    QVERIFY(close(dock.sampleSpeed(last, 0), 7.0));
    QVERIFY(close(dock.sampleCompareSpeed(last, 0), 8.0));
}

void TestPlotDock::plottedMarbles_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addColumn<QList<int>>("selection");
    QTest::addColumn<QList<int>>("plotted");

    QList<int> firstTwelve;
    for (int i = 0; i < PlotDock::kMaxPlottedMarbles; ++i)
        firstTwelve.append(i);
    QList<int> fifteen;
    for (int i = 14; i >= 0; --i)
        fifteen.append(i);

    QTest::addRow("no marbles") << 0 << QList<int>{} << QList<int>{};
    QTest::addRow("all of three") << 3 << QList<int>{} << QList<int>{0, 1, 2};
    QTest::addRow("all, capped") << 40 << QList<int>{} << firstTwelve;
    QTest::addRow("selection order") << 5 << QList<int>{4, 1} << QList<int>{4, 1};
    QTest::addRow("selection, duplicates and strangers") << 5 << QList<int>{7, 2, 2, -1} << QList<int>{2};
    QTest::addRow("selection, capped") << 20 << fifteen << fifteen.mid(0, PlotDock::kMaxPlottedMarbles);
}

void TestPlotDock::plottedMarbles()
{
    QFETCH(int, marbles);
    QFETCH(QList<int>, selection);
    QFETCH(QList<int>, plotted);

    PlotDock dock;
    World world = worldWith(marbles);
    dock.reset(world);
    dock.setSelectedMarbles(selection);
    QCOMPARE(dock.plottedMarbles(), plotted);
    // One line per plotted marble, plus the totals' three (kinetic energy, momentum x and y) and
    // the edit marks' (empty until an edit makes the lines jump).
    QCOMPARE(dock.chartView()->chart()->series().size(), plotted.size() + 4);
    for (int m : plotted)
        QVERIFY(dock.speedSeries(m));

    // The selection also holds when it comes before the scene.
    PlotDock early;
    early.setSelectedMarbles(selection);
    early.reset(world);
    QCOMPARE(early.plottedMarbles(), plotted);
}

void TestPlotDock::selectionKeepsHistory()
{
    PlotDock dock;
    World world = worldWith(3);
    dock.setSelectedMarbles({0}); // before the scene: marble 2 is never plotted until chosen
    dock.reset(world);
    runFrames(dock, world, 10);

    dock.setSelectedMarbles({2, 0});
    QCOMPARE(dock.plottedMarbles(), QList<int>({2, 0}));
    QCOMPARE(dock.sampleCount(), 10);
    // Marble 0 kept its ten samples; marble 2 has none before it was selected.
    QCOMPARE_LE(std::abs(dock.sampleSpeed(0, 0) - 0.01), 1e-15);
    QVERIFY(std::isnan(dock.sampleSpeed(9, 2)));

    world.frame = 11;
    world.velocity[2] = {3.0, 4.0};
    dock.appendFrame(world);
    QCOMPARE_LE(std::abs(dock.sampleSpeed(10, 2) - 5.0), 1e-15);
    dock.refreshChart();
    QCOMPARE(dock.speedSeries(2)->count(), 1); // no points for the frames it was not plotted
    QCOMPARE(dock.speedSeries(0)->count(), 11);
}

void TestPlotDock::unselectingBringsTheFirstMarblesBackWhole()
{
    // Nothing selected plots marbles 0 to 11; a marble selected for a while and then unselected
    // gives them back with every sample since the start (they were started again from what Step
    // Back keeps: a few hundred frames in a crowd, the rest gone), the comparison's too.
    PlotDock dock;
    World world = worldWith(20);
    dock.reset(world);
    dock.setCompareModel(QStringLiteral("exact"));
    const World same = world;
    dock.appendFrame(world, &same);
    for (int f = 1; f <= 9; ++f) {
        world.frame = f;
        world.velocity[3] = {0.0, static_cast<double>(f)};
        dock.appendFrame(world, &world);
    }
    dock.setSelectedMarbles({15});
    QCOMPARE(dock.plottedMarbles(), QList<int>({15}));
    for (int f = 10; f <= 14; ++f) {
        world.frame = f;
        world.velocity[3] = {0.0, static_cast<double>(f)};
        dock.appendFrame(world, &world);
    }
    dock.setSelectedMarbles({});
    QCOMPARE(dock.plottedMarbles().size(), 12);
    QCOMPARE(dock.sampleCount(), 15);
    for (int k = 1; k < 15; ++k) {
        QCOMPARE(dock.sampleSpeed(k, 3), static_cast<double>(k)); // while unplotted too
        QCOMPARE(dock.sampleCompareSpeed(k, 3), static_cast<double>(k));
    }
    // Marble 15 was not among the first twelve: it is not kept.
    dock.setSelectedMarbles({15});
    QVERIFY(std::isnan(dock.sampleSpeed(12, 15)));
}

void TestPlotDock::lineColoursAreNotTheStagesBlue()
{
    // The plotted marbles are drawn in their lines' colours, the others in the stage's blue: no
    // line may be that blue or near it (marble 0's was it, and on a crowd looked like any other),
    // and no two lines share a colour.
    PlotDock dock;
    dock.reset(worldWith(12));
    const QList<QPair<int, QColor>> colours = dock.plottedColours();
    QCOMPARE(colours.size(), 12);
    const QColor blue = MarbleItem::defaultColor();
    QSet<QRgb> seen;
    for (const auto &[marble, colour] : colours) {
        const double distance = std::hypot(colour.red() - blue.red(), colour.green() - blue.green(),
                                           colour.blue() - blue.blue());
        QVERIFY2(distance > 100, qPrintable(QStringLiteral("marble %1: %2").arg(marble).arg(colour.name())));
        seen.insert(colour.rgb());
    }
    QCOMPARE(seen.size(), 12);
    // The momentum's lines are apart from every marble's (a purple was 55 from marble 7's wine).
    for (int c : {0, 1}) {
        const QColor momentum = dock.momentumSeries(c)->pen().color();
        for (const auto &[marble, colour] : colours) {
            const double distance = std::hypot(colour.red() - momentum.red(), colour.green() - momentum.green(),
                                               colour.blue() - momentum.blue());
            QVERIFY2(distance > 100, qPrintable(QStringLiteral("momentum %1 and marble %2").arg(c).arg(marble)));
        }
    }
    // Marbles next to each other in number differ clearly, 0 and 1 (a two-marble lesson) most:
    // their vermilion and orange were 67 apart.
    auto apart = [&](int a, int b) {
        const QColor ca = colours.at(a).second;
        const QColor cb = colours.at(b).second;
        return std::hypot(ca.red() - cb.red(), ca.green() - cb.green(), ca.blue() - cb.blue());
    };
    QCOMPARE_GT(apart(0, 1), 200.0);
    for (int i = 0; i + 1 < 12; ++i)
        QVERIFY2(apart(i, i + 1) > 90.0, qPrintable(QStringLiteral("marbles %1 and %2").arg(i).arg(i + 1)));
}

void TestPlotDock::newLineTakesEarlierSpeeds()
{
    // With a velocity lookup (Step Back's history), a marble plotted later gets its speeds for
    // the samples already held; frames the lookup does not know stay gaps.
    PlotDock dock;
    World world = worldWith(3);
    KeptFrames kept;        // the document's frames 4..10
    KeptFrames compareKept; // the comparison's frames 9..10
    dock.setVelocityLookup(lookupIn(kept), lookupIn(compareKept));
    dock.setSelectedMarbles({0}); // before the scene: marble 2 is never plotted until chosen
    dock.reset(world);
    for (int f = 1; f <= 10; ++f) {
        world.frame = f;
        for (int i = 0; i < 3; ++i)
            world.velocity[static_cast<std::size_t>(i)] = {0.01 * f, -0.5 * i};
        if (f >= 4)
            kept[f] = world.velocity;
        if (f >= 9)
            compareKept[f] = {{0.0, 0.0}, {0.0, 0.0}, {3.0, 4.0 * f}};
        dock.appendFrame(world);
    }

    dock.setSelectedMarbles({2, 0});
    for (qsizetype k = 0; k < 10; ++k) {
        const double f = static_cast<double>(k + 1);
        if (k < 3)
            QVERIFY(std::isnan(dock.sampleSpeed(k, 2)));
        else
            QVERIFY(dock.sampleSpeed(k, 2) == length({0.01 * f, -1.0})); // the same arithmetic
        QVERIFY(dock.sampleSpeed(k, 0) == 0.01 * f); // kept its own samples
    }
    dock.refreshChart();
    QCOMPARE(dock.speedSeries(2)->count(), 7);

    // The frame the timeline starts from is kept too, then a gap: the line starts after the gap
    // (a line from frame 1 to frame 4 would show a change nobody saw: on a 20,000-marble crowd,
    // a straight fall from frame 0's speed to the first kept frame, 740 frames on).
    kept[1] = {{0.01, 0.0}, {0.01, -0.5}, {0.01, -1.0}};
    dock.setSelectedMarbles({0});
    dock.setSelectedMarbles({2, 0});
    QVERIFY(dock.sampleSpeed(0, 2) == length({0.01, -1.0}));
    QVERIFY(std::isnan(dock.sampleSpeed(1, 2)));
    dock.refreshChart();
    QCOMPARE(dock.speedSeries(2)->count(), 7);
    QCOMPARE(dock.speedSeries(2)->at(0).x(), 4.0);

    // A comparison starting now: its speeds where it knows the frames, gaps before.
    dock.setCompareModel(QStringLiteral("exact"));
    QVERIFY(std::isnan(dock.sampleCompareSpeed(7, 2)));
    QVERIFY(dock.sampleCompareSpeed(8, 2) == length({3.0, 36.0}));
    QVERIFY(dock.sampleCompareSpeed(9, 2) == length({3.0, 40.0}));
}

void TestPlotDock::lineColours()
{
    World world = worldWith(3);
    world.info[1].color = "#e04040";
    world.info[2].name = "red giant";
    PlotDock dock;
    dock.reset(world);
    QCOMPARE(dock.speedSeries(1)->pen().color(), QColor(0xe0, 0x40, 0x40));
    // Marbles without a colour get one of the palette's, never the stage's blue (and the stage
    // draws the marble so: lineColoursAreNotTheStagesBlue).
    const QColor c0 = dock.speedSeries(0)->pen().color();
    QVERIFY2(c0.isValid() && c0 != MarbleItem::defaultColor(), qPrintable(c0.name()));
    QVERIFY(dock.speedSeries(2)->name().contains(QStringLiteral("red giant")));
    QCOMPARE(dock.speedSeries(0)->name(), QStringLiteral("marble 0"));
    // As many colours as lines at most: none shared (marbles 0 and 8 were both blue).
    World twelve = worldWith(PlotDock::kMaxPlottedMarbles);
    dock.reset(twelve);
    QList<int> all;
    for (int i = 0; i < PlotDock::kMaxPlottedMarbles; ++i)
        all << i;
    dock.setSelectedMarbles(all);
    QSet<QRgb> colours;
    for (int i = 0; i < PlotDock::kMaxPlottedMarbles; ++i)
        colours.insert(dock.speedSeries(i)->pen().color().rgb());
    QCOMPARE(colours.size(), PlotDock::kMaxPlottedMarbles);
    // And none looks like the selection's near-black ring (when that was orange, the ring and the
    // orange line seemed to name the same marble), nor like any other grey of the plot.
    for (QRgb rgb : colours) {
        const QColor c = QColor::fromRgb(rgb);
        // No grey at all: the legend's model keys and the kinetic energy's line are greys too.
        QVERIFY2(c.saturation() >= 100, qPrintable(c.name()));
    }
    // And no two alike: marbles 1 and 8 were an orange and a gold 49 apart in RGB, 2 and 7 two
    // greens.
    const QList<QRgb> list(colours.begin(), colours.end());
    for (qsizetype a = 0; a < list.size(); ++a) {
        for (qsizetype b = a + 1; b < list.size(); ++b) {
            const QColor ca = QColor::fromRgb(list[a]);
            const QColor cb = QColor::fromRgb(list[b]);
            const double apart = std::hypot(ca.red() - cb.red(), ca.green() - cb.green(), ca.blue() - cb.blue());
            QVERIFY2(apart >= 55.0, qPrintable(ca.name() + QLatin1Char(' ') + cb.name()));
        }
    }
}

void TestPlotDock::chartGetsSamples()
{
    PlotDock dock;
    World world = worldWith(2);
    dock.reset(world);
    runFrames(dock, world, 50);
    dock.refreshChart();

    QLineSeries *line = dock.speedSeries(0);
    QCOMPARE(line->count(), 50);
    for (int i = 0; i < line->count(); ++i) {
        QCOMPARE_LE(std::abs(line->at(i).x() - double(i + 1)), 1e-12);
        QCOMPARE_LE(std::abs(line->at(i).y() - 0.01 * double(i + 1)), 1e-12);
    }
    // Autoscaled axes cover every point.
    auto *xAxis = timeAxisOf(line);
    auto *yAxis = valueAxisOf(line);
    QVERIFY(xAxis && yAxis);
    QCOMPARE_LE(xAxis->min(), 1.0);
    QCOMPARE_GE(xAxis->max(), 50.0);
    QCOMPARE_LE(yAxis->min(), 0.0);
    QCOMPARE_GE(yAxis->max(), std::max(maxY(line), maxY(dock.speedSeries(1))));
    // With room above the top point (0.5 px/frame, a round number): not along the chart's edge.
    QCOMPARE_GT(yAxis->max(), 1.03 * std::max(maxY(line), maxY(dock.speedSeries(1))));
    QCOMPARE(dock.chartView()->chart()->animationOptions(), QChart::NoAnimation);
}

void TestPlotDock::hugeSpeedsArePlotted()
{
    // The book's blow-up (friction above 2) passes 1.3e154 px/frame, where v.x^2 + v.y^2
    // overflows, hundreds of frames before its numbers stop being finite: the lines go on up to
    // there (they ended at the overflow, frame 1110 of 1978 in the default scene at friction 2.5).
    PlotDock dock;
    World world = worldWith(1);
    dock.reset(world);
    const double speeds[] = {3.0, 2e154, -4e200, 1.7e308};
    for (double v : speeds) {
        world.velocity[0] = {v, 0.0};
        ++world.frame;
        dock.appendFrame(world);
    }
    world.velocity[0] = {3.0, 4.0};
    ++world.frame;
    dock.appendFrame(world);
    dock.refreshChart();
    QLineSeries *line = dock.speedSeries(0);
    QCOMPARE(line->count(), 5);
    QCOMPARE(line->at(1).y(), 2e154);
    QCOMPARE(line->at(2).y(), 4e200);
    QCOMPARE(line->at(3).y(), 1.7e308);
    QCOMPARE(line->at(4).y(), 5.0); // the book's length below the overflow: sqrt(9 + 16)
    // Up to where Qt Charts' tick arithmetic, i * (max - min), still gives numbers (its ticks read
    // "inf" above); the last frames of a blow-up go off the top.
    const QValueAxis *axis = valueAxisOf(line);
    QCOMPARE_GE(axis->max(), 1e306);
    QVERIFY(std::isfinite(axis->tickCount() * (axis->max() - axis->min())));

    // A momentum as far below zero (the axis's 4 % of room beyond its lowest point had made
    // it -inf, and every tick read "inf"; a helper's finding), and above.
    dock.setMomentumShown(true);
    dock.setKineticEnergyShown(true);
    // Each tick, as Qt Charts works it out: min + k (max - min) / (ticks - 1).
    const auto ticksFinite = [](const QValueAxis *a) {
        for (int k = 0; k < a->tickCount(); ++k) {
            if (!std::isfinite(a->min() + k * (a->max() - a->min()) / std::max(a->tickCount() - 1, 1)))
                return false;
        }
        return a->min() < a->max();
    };
    for (const double v : {-7e307, -1.75e308, 1.75e308}) {
        world.velocity[0] = {v, 0.0};
        world.mass[0] = 1.0;
        ++world.frame;
        dock.appendFrame(world);
        dock.refreshChart();
        for (QValueAxis *a : {valueAxisOf(dock.momentumSeries(0)), valueAxisOf(dock.kineticSeries()), valueAxisOf(line)}) {
            QVERIFY2(ticksFinite(a), qPrintable(QStringLiteral("v %1: %2 to %3, %4 ticks").arg(v).arg(a->min()).arg(a->max()).arg(a->tickCount())));
            // Round numbers, zero on a tick where the axis reaches it (they read "8.98847e+306").
            const auto tickLabels = qobject_cast<QCategoryAxis *>(a)->categoriesLabels();
            for (const QString &label : tickLabels) {
                const double value = label.trimmed().toDouble();
                const bool guarded = a->max() > 1e306 || a->min() < -1e306;
                QVERIFY2(!guarded || label.trimmed().isEmpty() || value == std::round(value / 2e306) * 2e306,
                         qPrintable(label));
            }
            if (a->min() <= 0.0 && a->max() >= 0.0)
                QVERIFY2(tickLabels.contains(QStringLiteral("0")), qPrintable(tickLabels.join(QLatin1Char('|'))));
        }
    }
}

void TestPlotDock::momentumAxisReadsZeroAtZero()
{
    // Seen under Xvfb during the book's blow-up (friction 2.5): the momentum's axis, -1e108 to
    // 1.5e108, read "1.3037e+92" on the zero line, where Qt Charts' min + k (max - min) /
    // (ticks - 1) missed zero by a rounding. Its labels are the axis's own now: each tick's
    // value, zero as "0".
    PlotDock dock;
    dock.setMomentumShown(true);
    World world = worldWith(1);
    world.mass[0] = 1.0;
    dock.reset(world);
    // Every power of ten up to 1e300 (1e24 missed zero so, among others).
    for (int e = 0; e <= 300; ++e) {
        const double scale = std::pow(10.0, e);
        for (const double v : {1.44 * scale, -0.96 * scale}) {
            world.velocity[0] = {v, 0.5 * v};
            ++world.frame;
            dock.appendFrame(world);
        }
        dock.refreshChart();
        auto *axis = qobject_cast<QCategoryAxis *>(valueAxisOf(dock.momentumSeries(0)));
        QVERIFY(axis);
        const QStringList labels = axis->categoriesLabels();
        QCOMPARE(labels.size(), axis->tickCount());
        QVERIFY2(axis->min() < 0.0 && axis->max() > 0.0, qPrintable(QString::number(axis->max())));
        const double step = (axis->max() - axis->min()) / (axis->tickCount() - 1);
        QVERIFY2(labels.contains(QStringLiteral("0")), qPrintable(labels.join(QLatin1Char('|'))));
        for (qsizetype k = 0; k < labels.size(); ++k) {
            // Each label is its tick's value, to the six digits of "%g" (a huge tick's label may
            // carry a space to differ from its neighbour's).
            bool ok = false;
            const double value = labels[k].trimmed().toDouble(&ok);
            const double tick = axis->min() + static_cast<double>(k) * step;
            QVERIFY2(ok, qPrintable(labels[k]));
            QVERIFY2(std::abs(value - tick) <= 1e-5 * step,
                     qPrintable(QStringLiteral("scale %1: label %2 at tick %3").arg(scale).arg(labels[k]).arg(tick)));
            QVERIFY2(value == 0.0 || std::abs(value) >= 0.5 * step, qPrintable(labels[k]));
        }
    }
}

void TestPlotDock::topLabelsStayOnTheChart()
{
    // Every value axis labels its own ticks (category axes), and Qt Charts leaves no room above
    // the plot for a category axis's top label, centred on the top tick: with the momentum's axis
    // one too, "6e+93" at the top of the speed and momentum axes was cut in half (seen under Xvfb).
    PlotDock dock;
    World world = worldWith(2);
    QVERIFY(showRun(dock, world, 30, QSize(900, 400)));
    for (const bool momentum : {false, true}) {
        dock.setMomentumShown(momentum);
        dock.setKineticEnergyShown(momentum);
        for (int k = 0; k < 3; ++k) {
            dock.refreshChart();
            QCoreApplication::processEvents();
        }
        QChart *chart = dock.chartView()->chart();
        const double halfLine = QFontMetrics(qobject_cast<QCategoryAxis *>(valueAxisOf(dock.speedSeries(0)))->labelsFont()).height() / 2.0;
        QVERIFY2(chart->plotArea().top() >= halfLine,
                 qPrintable(QStringLiteral("momentum %1: plot from %2 px, half a label %3 px").arg(momentum).arg(chart->plotArea().top()).arg(halfLine)));
    }
}

void TestPlotDock::pausedComparisonKeepsItsEarlierLines()
{
    // A helper's finding: compared with exact, friction set to 1.5 at frame 10 (which the exact
    // model cannot follow: the comparison pauses, its samples are no number) and back to 0.05 at
    // frame 13 (it starts again there): the dashed line of frames 0 to 9 vanished, the chart
    // drawing a line from its last gap on. Each run is drawn, the earlier ones as lines of their
    // own in the line's pen, out of the legend, under the totals.
    PlotDock dock;
    dock.setKineticEnergyShown(true);
    World world = worldWith(2);
    dock.reset(world);
    dock.setCompareModel(QStringLiteral("exact"));
    const qsizetype linesBefore = dock.chartView()->chart()->series().size();
    World compare = world;
    for (int f = 1; f <= 20; ++f) {
        world.frame = f;
        compare.frame = f;
        world.velocity[0] = {0.1 * f, 0.0};
        compare.velocity[0] = {0.2 * f, 0.0};
        const bool paused = f >= 6 && f <= 8;
        dock.appendFrame(world, paused ? nullptr : &compare);
    }
    dock.refreshChart();
    QLineSeries *dashed = dock.compareSeries(0);
    QVERIFY(dashed);
    // The last run, frames 9 to 20, on the line itself.
    QCOMPARE(dashed->count(), 12);
    QCOMPARE(dashed->at(0), QPointF(9.0, 0.2 * 9));
    const QList<QLineSeries *> earlier = dock.earlierRuns(dashed);
    QCOMPARE(earlier.size(), 1);
    QLineSeries *run = earlier.front();
    QCOMPARE(run->count(), 5); // frames 1 to 5
    QCOMPARE(run->at(0), QPointF(1.0, 0.2));
    QCOMPARE(run->at(4), QPointF(5.0, 0.2 * 5));
    QCOMPARE(run->pen(), dashed->pen());
    QVERIFY(run->isVisible());
    QChart *chart = dock.chartView()->chart();
    for (QLegendMarker *marker : chart->legend()->markers(run))
        QVERIFY(!marker->isVisible());
    // The comparison's energy likewise, and every total over the speed lines (drawn after them).
    QLineSeries *energy = dock.compareKineticSeries();
    QVERIFY(energy);
    QCOMPARE(energy->count(), 12);
    QCOMPARE(dock.earlierRuns(energy).size(), 1);
    const QList<QAbstractSeries *> order = chart->series();
    QVERIFY(order.indexOf(run) < order.indexOf(dock.kineticSeries()));
    QVERIFY(order.indexOf(run) < order.indexOf(energy));
    // The scene's own lines have no gap: nothing apart.
    QVERIFY(dock.earlierRuns(dock.speedSeries(0)).isEmpty());
    QCOMPARE(dock.speedSeries(0)->count(), 20);

    // Hidden with the energy, shown with it; out of the legend whatever (ticked off and on
    // between two refreshes, Qt Charts had listed them again, blank).
    const auto listed = [chart](const QList<QLineSeries *> &lines) {
        for (QLineSeries *line : lines) {
            for (QLegendMarker *marker : chart->legend()->markers(line)) {
                if (marker->isVisible())
                    return true;
            }
        }
        return false;
    };
    dock.resize(900, 400);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    dock.setKineticEnergyShown(false);
    dock.setKineticEnergyShown(true);
    QCoreApplication::processEvents();
    QVERIFY(dock.earlierRuns(dock.compareKineticSeries()).front()->isVisible());
    QVERIFY(!listed(dock.earlierRuns(dock.compareKineticSeries())));
    dock.setKineticEnergyShown(false);
    dock.refreshChart();
    QVERIFY(dock.earlierRuns(dock.compareKineticSeries()).isEmpty());
    dock.setKineticEnergyShown(true);
    dock.refreshChart();
    QCOMPARE(dock.earlierRuns(dock.compareKineticSeries()).size(), 1);
    QVERIFY(dock.earlierRuns(dock.compareKineticSeries()).front()->isVisible());
    QVERIFY(!listed(dock.earlierRuns(dock.compareKineticSeries())));

    // A new run: no gap, no lines apart left on the chart.
    dock.reset(world);
    dock.refreshChart();
    QVERIFY(!dock.compareSeries(0) || dock.earlierRuns(dock.compareSeries(0)).isEmpty());
    QCOMPARE(dock.chartView()->chart()->series().size(), linesBefore);
}

void TestPlotDock::liveRefresh()
{
    // appendFrame never touches the chart; the timer hands samples over a few times a second.
    PlotDock dock;
    dock.resize(500, 350);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    World world = worldWith(1);
    dock.reset(world);
    dock.refreshChart();
    runFrames(dock, world, 20);
    QCOMPARE(dock.speedSeries(0)->count(), 0);
    QTRY_COMPARE_WITH_TIMEOUT(dock.speedSeries(0)->count(), 20, 5 * PlotDock::kRefreshIntervalMs);
}

void TestPlotDock::refreshMovesAxesOnlyWhenTheirRangeChanges()
{
    // Every change of an axis's range makes the chart recompute each line on it (the refresh of a
    // 12-line plot of 3,000 frames took 52 ms while the axes went to the raw range and back to
    // the nice one at every refresh, stalling the stage five times a second). The axes change
    // once when their range does, and not at all when it stays.
    PlotDock dock;
    World world = worldWith(2);
    dock.reset(world);
    runFrames(dock, world, 45);
    dock.refreshChart();
    QLineSeries *line = dock.speedSeries(0);
    auto *xAxis = timeAxisOf(line);
    auto *yAxis = valueAxisOf(line);
    QVERIFY(xAxis && yAxis);
    const double xMax = xAxis->max();
    QSignalSpy xMoves(xAxis, &QValueAxis::rangeChanged);
    QSignalSpy yMoves(yAxis, &QValueAxis::rangeChanged);

    dock.refreshChart(); // nothing new
    QCOMPARE(xMoves.count(), 0);
    QCOMPARE(yMoves.count(), 0);

    const auto more = [&](int frames) {
        for (int k = 0; k < frames; ++k) {
            ++world.frame;
            dock.appendFrame(world);
        }
    };
    // One more frame inside the nice range: the line grows, the axes stay.
    QCOMPARE_GT(xMax, 46.0);
    more(1);
    dock.refreshChart();
    QCOMPARE(line->count(), 46);
    QCOMPARE(xMoves.count(), 0);

    // Past the end of the range: the axis moves once, straight to a range covering every sample.
    more(int(xMax));
    dock.refreshChart();
    QCOMPARE(xMoves.count(), 1);
    QCOMPARE_GE(xAxis->max(), line->at(line->count() - 1).x());
    QCOMPARE_LE(yMoves.count(), 1);
    QCOMPARE_GE(yAxis->max(), maxY(line));
}

void TestPlotDock::thinningKeepsSpikes()
{
    PlotDock dock;
    World world = worldWith(1);
    dock.reset(world);
    const int frames = int(PlotDock::kDefaultCapacity);
    for (int f = 1; f <= frames; ++f) {
        world.frame = f;
        world.velocity[0] = {f == 2501 ? 40.0 : 1.0 + 0.001 * (f % 7), 0.0};
        dock.appendFrame(world);
    }
    dock.refreshChart();
    QLineSeries *line = dock.speedSeries(0);
    // Fewer points than samples, but the one-frame spike is still drawn at its height and place.
    QCOMPARE_LT(line->count(), frames);
    QCOMPARE_LE(std::abs(maxY(line) - 40.0), 1e-12);
    bool found = false;
    for (const QPointF &p : line->points())
        found = found || (p.x() == 2501.0 && p.y() == 40.0);
    QVERIFY(found);
}

void TestPlotDock::thinningFollowsThePlotWidth()
{
    // A line never hands the chart many more points than the plot has pixel columns (each point
    // costs the chart a stroke and a draw), keeps its spikes, and is thinned again for a wider plot.
    PlotDock dock;
    dock.resize(500, 350);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    World world = worldWith(1);
    dock.reset(world);
    const int frames = 4000;
    for (int f = 1; f <= frames; ++f) {
        world.frame = f;
        world.velocity[0] = {f == 1234 ? 40.0 : 1.0 + 0.5 * (f % 2), 0.0};
        dock.appendFrame(world);
    }
    // The first refresh sets the axes, whose labels take their room from the plot: the points
    // follow the plot's width from the next one (the dock refreshes five times a second).
    dock.refreshChart();
    dock.refreshChart();
    QLineSeries *line = dock.speedSeries(0);
    const double width = dock.chartView()->chart()->plotArea().width() * dock.chartView()->devicePixelRatioF();
    QCOMPARE_GT(width, 100.0);
    QCOMPARE_LE(dock.pointsPerLine(), std::max(qsizetype(std::ceil(width)), qsizetype(200)));
    QCOMPARE_LE(line->count(), dock.pointsPerLine());
    QCOMPARE_GE(line->count(), dock.pointsPerLine() / 2);
    bool found = false;
    for (const QPointF &p : line->points())
        found = found || (p.x() == 1234.0 && p.y() == 40.0);
    QVERIFY(found);
    // Every bucket keeps its lowest and highest sample: the line still spans 1 to 1.5 throughout.
    QCOMPARE_LE(std::abs(line->at(1).y() - line->at(0).y()), 0.5 + 1e-12);
    QCOMPARE_GE(std::abs(line->at(1).y() - line->at(0).y()), 0.5 - 1e-12);

    const qsizetype narrow = line->count();
    dock.resize(1100, 350);
    QTRY_COMPARE_GT_WITH_TIMEOUT(line->count(), narrow, 5 * PlotDock::kRefreshIntervalMs);
    QCOMPARE_LE(line->count(), dock.pointsPerLine());
}

void TestPlotDock::secondsAxis()
{
    PlotDock dock;
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    World world = worldWith(1);
    world.params.frameMs = 25.0;
    dock.reset(world);
    runFrames(dock, world, 8);

    auto *seconds = dock.findChild<QRadioButton *>(QStringLiteral("secondAxisButton"));
    QVERIFY(seconds);
    QTest::mouseClick(seconds, Qt::LeftButton, {}, QPoint(seconds->height() / 2, seconds->height() / 2));
    QVERIFY(dock.isTimeInSeconds());
    dock.refreshChart();
    QLineSeries *line = dock.speedSeries(0);
    QCOMPARE(line->count(), 8);
    for (int i = 0; i < 8; ++i)
        QCOMPARE_LE(std::abs(line->at(i).x() - double(i + 1) * 25.0 / 1000.0), 1e-15);
    auto *xAxis = timeAxisOf(line);
    QCOMPARE(xAxis->titleText(), QStringLiteral("time (s)"));

    auto *frames = dock.findChild<QRadioButton *>(QStringLiteral("frameAxisButton"));
    QTest::mouseClick(frames, Qt::LeftButton, {}, QPoint(frames->height() / 2, frames->height() / 2));
    QVERIFY(!dock.isTimeInSeconds());
    dock.refreshChart();
    QCOMPARE_LE(std::abs(line->at(7).x() - 8.0), 1e-15);
    QCOMPARE(xAxis->titleText(), QStringLiteral("frame"));
}

void TestPlotDock::frameAxisTicksAreWholeFrames_data()
{
    QTest::addColumn<int>("frames");
    for (int n : {0, 1, 2, 3, 4, 5, 7, 12, 250})
        QTest::addRow("%d frames", n) << n;
}

void TestPlotDock::frameAxisTicksAreWholeFrames()
{
    // A teacher stepping the first frames one by one reads frame numbers under the plot, never
    // "1.5"; the axis still covers every sample, and grows back to its usual ticks later.
    QFETCH(int, frames);
    PlotDock dock;
    World world = worldWith(1);
    dock.reset(world);
    runFrames(dock, world, frames);
    dock.refreshChart();
    auto *xAxis = timeAxisOf(dock.speedSeries(0));
    QVERIFY(xAxis);
    const auto checkTicks = [xAxis](int last) {
        QCOMPARE_GE(xAxis->tickCount(), 2);
        const double step = (xAxis->max() - xAxis->min()) / (xAxis->tickCount() - 1);
        for (int k = 0; k < xAxis->tickCount(); ++k) {
            const double tick = xAxis->min() + k * step;
            QVERIFY2(std::abs(tick - std::round(tick)) < 1e-9, qPrintable(QStringLiteral("tick %1").arg(tick)));
        }
        QCOMPARE_LE(xAxis->min(), last > 0 ? 1.0 : 0.0);
        QCOMPARE_GE(xAxis->max(), double(std::max(last, 1)));
        QCOMPARE_LE(xAxis->tickCount(), 6);
    };
    checkTicks(frames);
    if (QTest::currentTestFailed())
        return;
    // Later in the run the axis is back to its usual few ticks.
    for (int f = frames + 1; f <= frames + 300; ++f) {
        world.frame = f;
        dock.appendFrame(world);
    }
    dock.refreshChart();
    checkTicks(frames + 300);
    QCOMPARE_GE(xAxis->tickCount(), 4);
}

void TestPlotDock::legendLabelsFitTheRow()
{
    // A crowd's twelve plotted marbles and a comparison's two keys: at the width of a small
    // window's plot the full labels do not fit one row (Qt would cut each to "marb…"), so the
    // marbles are labelled "#3"; at a wide plot, and on hovering a line, "marble 3".
    PlotDock dock;
    World world = worldWith(20);
    QVERIFY(showComparing(dock, world, 5, 700));
    QTRY_VERIFY(dock.legendIsCompact());
    QCOMPARE(dock.speedSeries(3)->name(), QStringLiteral("#3"));
    // The models' keys too, their line samples telling solid from dashed ("book (s…" and
    // "exact (…" were cut at 1024 x 768: a helper's finding).
    const auto labels = [&dock] { return shownLegendLabels(dock); };
    const auto endsWith = [](const QStringList &all, const QStringList &tail) {
        return all.size() >= tail.size() && all.mid(all.size() - tail.size()) == tail;
    };
    QTRY_VERIFY2(endsWith(labels(), QStringList{QStringLiteral("book"), QStringLiteral("exact")}), qPrintable(labels().join(u'|')));
    dock.describePoint(dock.speedSeries(3), QPointF(2.0, 0.0));
    QVERIFY2(dock.describePoint(dock.speedSeries(3), QPointF(2.0, 0.0)).contains(QStringLiteral("marble 3, speed")),
             qPrintable(dock.describePoint(dock.speedSeries(3), QPointF(2.0, 0.0))));

    // The totals too ("momentum x" and "momentum y" were both cut to "mome…"); the readout
    // names them in full.
    dock.setMomentumShown(true);
    QTRY_VERIFY(dock.legendIsCompact());
    QCOMPARE(dock.momentumSeries(0)->name(), QStringLiteral("p x"));
    QCOMPARE(dock.momentumSeries(1)->name(), QStringLiteral("p y"));
    QVERIFY(dock.describePoint(dock.momentumSeries(1), QPointF(2.0, 0.0)).contains(QStringLiteral(": momentum y ")));

    dock.resize(3000, 350);
    QTRY_VERIFY(!dock.legendIsCompact());
    QCOMPARE(dock.speedSeries(3)->name(), QStringLiteral("marble 3"));
    QCOMPARE(dock.momentumSeries(0)->name(), QStringLiteral("momentum x"));
    QTRY_VERIFY(endsWith(labels(), QStringList{QStringLiteral("book (solid)"), QStringLiteral("exact (dashed)")}));

    // The comparison's restart key takes room in the row too: at the narrowest width where the
    // full labels fit without it, they do not with it (they were cut, "compari…", "moment…").
    int width = 700;
    for (; width < 3000; width += 10) {
        dock.resize(width, 350);
        QCoreApplication::processEvents();
        if (!dock.legendIsCompact())
            break;
    }
    QVERIFY(!dock.legendIsCompact());
    runFrames(dock, world, 2, &world); // a dashed line to jump from
    dock.markCompareRestart(dock.sampleFrame(dock.sampleCount() - 1));
    QCOMPARE(dock.compareRestarts().size(), std::size_t(1));
    dock.refreshChart();
    QVERIFY(dock.legendIsCompact());
    QTRY_VERIFY2(endsWith(labels(), QStringList{QStringLiteral("book"), QStringLiteral("exact"), QStringLiteral("restarted")}),
                 qPrintable(labels().join(u'|')));

    // Short, and still no room (at 1024 x 768 a named crowd's legend, compared, restarted and
    // edited, read "he…", "ex…", "re…", "e…": a helper's finding): the marks' keys go, the lines'
    // stay; the marks are still drawn.
    World edited = world;
    edited.frame = dock.sampleFrame(dock.sampleCount() - 1);
    edited.velocity[0] = {9.0, 9.0};
    dock.resample(edited, &edited);
    QCOMPARE(dock.editMarks().size(), std::size_t(1));
    dock.resize(520, 350);
    dock.refreshChart();
    QTRY_VERIFY2(endsWith(labels(), QStringList{QStringLiteral("book"), QStringLiteral("exact")}), qPrintable(labels().join(u'|')));
    QVERIFY(!labels().contains(QStringLiteral("restarted")) && !labels().contains(QStringLiteral("edited")));
    for (QAbstractSeries *series : dock.chartView()->chart()->series()) {
        if (series->name() == QStringLiteral("edited") || series->name() == QStringLiteral("restarted"))
            QCOMPARE(static_cast<QLineSeries *>(series)->count(), 3);
    }
    // Wide again, they come back.
    dock.resize(3000, 350);
    dock.refreshChart();
    QTRY_VERIFY2(endsWith(labels(), QStringList{QStringLiteral("comparison restarted"), QStringLiteral("scene edited")}),
                 qPrintable(labels().join(u'|')));

    // Narrower still, with both totals (a crowd's twelve marbles, kinetic energy and momentum at
    // 1024 x 768 were swatches without a word, the totals' names gone too: a helper's finding):
    // the unnamed marbles' keys go, and the models' and the totals' stay, named. Hovering a
    // line still names its marble.
    dock.setKineticEnergyShown(true);
    dock.resize(480, 350);
    dock.refreshChart();
    const QStringList keys{QStringLiteral("book"), QStringLiteral("exact"), QStringLiteral("KE"), QStringLiteral("p x"),
                           QStringLiteral("p y")};
    const auto labelSet = [&labels] {
        const QStringList all = labels();
        return QSet<QString>(all.begin(), all.end());
    };
    QTRY_VERIFY2(labelSet() == QSet<QString>(keys.begin(), keys.end()), qPrintable(labels().join(u'|')));
    QVERIFY(dock.describePoint(dock.speedSeries(3), QPointF(2.0, 0.0)).contains(QStringLiteral("marble 3, speed")));
    // Wide again, they come back.
    dock.resize(3000, 350);
    dock.refreshChart();
    QTRY_VERIFY2(labels().contains(QStringLiteral("marble 3")), qPrintable(labels().join(u'|')));
}

void TestPlotDock::legendListsMarblesInOrder()
{
    // Marble 3 selected, then nothing: marble 3 kept its samples and the others were plotted
    // again, yet the legend still reads marble 0, 1, 2, 3, then the two models' keys.
    PlotDock dock;
    World world = worldWith(4);
    QVERIFY(showComparing(dock, world, 6, 1400));
    const auto visibleLabels = [&dock] { return shownLegendLabels(dock); };
    const QStringList inOrder{QStringLiteral("marble 0"), QStringLiteral("marble 1"), QStringLiteral("marble 2"),
                              QStringLiteral("marble 3"), QStringLiteral("book (solid)"), QStringLiteral("exact (dashed)")};
    QTRY_COMPARE(visibleLabels(), inOrder);
    dock.setSelectedMarbles({3});
    dock.setSelectedMarbles({});
    dock.refreshChart();
    QTRY_COMPARE(visibleLabels(), inOrder); // new markers show once the legend is laid out
    QCOMPARE(dock.speedSeries(3)->count(), 6);
    QCOMPARE(dock.sampleSpeed(5, 3), std::hypot(0.06, 1.5));
}

void TestPlotDock::editsThatMakeTheLinesJumpAreMarked()
{
    // A helper's finding: the mass scale changed at frame 100, Step Back to 70 (the parameters
    // keep their latest values, so frame 70 is taken again with it), and the energy line rose
    // at 70 without a word, "energy from nowhere" to a class. Where a frame's sample is taken
    // again and the scene's lines jump, the frame is marked; undone there, the mark goes.
    PlotDock dock;
    World world = worldWith(3);
    QVERIFY(showRun(dock, world, 10, QSize(1400, 350)));
    const auto marks = [&dock] {
        dock.refreshChart();
        QList<qreal> xs;
        for (QAbstractSeries *series : dock.chartView()->chart()->series()) {
            if (series->name() == QStringLiteral("scene edited")) {
                for (const QPointF &p : static_cast<QLineSeries *>(series)->points())
                    xs << p.x();
            }
        }
        return xs;
    };
    const auto listed = [&dock] {
        for (QLegendMarker *marker : dock.chartView()->chart()->legend()->markers()) {
            if (marker->series()->name() == QStringLiteral("scene edited"))
                return marker->isVisible();
        }
        return false;
    };
    QVERIFY(dock.editMarks().empty());
    QVERIFY(marks().isEmpty());
    QVERIFY(!listed());

    // Taken again as it was (Step Back to a frame, a friction edit): no jump, no mark.
    dock.cutAfter(8);
    World at8 = world;
    at8.frame = 8;
    for (int i = 0; i < at8.marbleCount(); ++i)
        at8.velocity[static_cast<std::size_t>(i)] = {0.01 * 8, -0.5 * i};
    dock.resample(at8, nullptr);
    QVERIFY(dock.editMarks().empty());

    // The mass scale changed there: the energy and momentum jump, the speeds do not.
    World heavier = at8;
    heavier.setMassScale(2.5);
    dock.resample(heavier, nullptr);
    QCOMPARE(dock.editMarks(), std::vector<std::int64_t>{8});
    QCOMPARE(marks(), (QList<qreal>{8, 8, 8})); // down, up and down again at frame 8
    QTRY_VERIFY(listed());
    // At the newest frame, it is not drawn on the chart's edge: the time axis goes on past it.
    const QList<QAbstractAxis *> across = dock.chartView()->chart()->axes(Qt::Horizontal);
    QVERIFY(!across.isEmpty());
    auto *time = qobject_cast<QValueAxis *>(across.first());
    QVERIFY(time);
    QVERIFY2(time->max() > 8.0, qPrintable(QString::number(time->max())));
    // Edited again at the same frame (a velocity too): still one mark.
    heavier.velocity[1] = {3, 0};
    dock.resample(heavier, nullptr);
    QCOMPARE(dock.editMarks(), std::vector<std::int64_t>{8});
    // Both undone: the frame has its values as stepped again, and the mark goes.
    dock.resample(at8, nullptr);
    QVERIFY(dock.editMarks().empty());
    QVERIFY(marks().isEmpty());
    QTRY_VERIFY(!listed());

    // A speed alone: marked (the energy and momentum may stay, a velocity turned round).
    World turned = at8;
    turned.velocity[2] = {-turned.velocity[2].x, -turned.velocity[2].y};
    dock.setSelectedMarbles({2});
    dock.resample(turned, nullptr);
    QCOMPARE(dock.editMarks(), std::vector<std::int64_t>{8});
    // Run on, then back before the mark: it goes with the frames after the one stepped back to,
    // and comes at that frame if the edit is carried there.
    world = turned;
    for (int f = 9; f <= 12; ++f) {
        world.frame = f;
        dock.appendFrame(world, nullptr);
    }
    dock.cutAfter(5);
    QVERIFY(dock.editMarks().empty());
    World at5 = world;
    at5.frame = 5;
    at5.setMassScale(4.0);
    dock.resample(at5, nullptr);
    QCOMPARE(dock.editMarks(), std::vector<std::int64_t>{5});
    // A new scene forgets them.
    dock.reset(world);
    QVERIFY(dock.editMarks().empty());
}

void TestPlotDock::shortChartKeepsItsLabelsWhole()
{
    // A helper's finding at a scale of 1.5 on a 1280 x 720 projector: the plot about 100 px high,
    // every speed label read "…" (six labels, each given less than a line by Qt) and the titles
    // "speed (px/fr…" and "kinetic ener…". A short chart has as many ticks as it has room for, a
    // line apart at least, and its side titles in short.
    PlotDock dock;
    World world = worldWith(3);
    dock.setKineticEnergyShown(true);
    dock.setMomentumShown(true);
    dock.reset(world);
    for (int f = 1; f <= 20; ++f) {
        world.frame = f;
        world.velocity[0] = {0.9 * f, 0.0};  // up to 18 px/frame
        world.velocity[1] = {-1.2 * f, 0.0}; // a momentum below zero: the axes share its zero line
        dock.appendFrame(world, nullptr);
    }
    const auto speedAxis = [&dock]() -> QCategoryAxis * {
        for (QAbstractAxis *axis : dock.chartView()->chart()->axes(Qt::Vertical)) {
            if (auto *category = qobject_cast<QCategoryAxis *>(axis); category && category->alignment() == Qt::AlignLeft)
                return category;
        }
        return nullptr;
    };
    dock.chartView()->setMinimumHeight(150); // as MainWindow lets it on a screen less than 600 px high
    dock.resize(900, 200);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    for (int k = 0; k < 3; ++k) { // the layout settles with the labels it is given
        dock.refreshChart();
        QCoreApplication::processEvents();
    }
    QCategoryAxis *speed = speedAxis();
    QVERIFY(speed);
    const double height = dock.chartView()->chart()->plotArea().height();
    const int line = QFontMetrics(speed->labelsFont()).height();
    QVERIFY2(height < 4.0 * 2 * line, qPrintable(QString::number(height))); // short indeed
    const qsizetype labels = speed->categoriesLabels().size();
    // At least a line and a half apart (five labels in 57 px had 14 px each for a 14-px line).
    QVERIFY2(labels >= 2 && (labels - 1) * 1.5 * line <= height,
             qPrintable(QStringLiteral("%1 labels in %2 px, a line %3 px").arg(labels).arg(height).arg(line)));
    // Short, and as long as the chart is high at most ("v (px/frame)", or "speed" where even that
    // is not: a lone "v" turned up the side read as ">").
    QVERIFY2(speed->titleText() != QStringLiteral("speed (px/frame)") && speed->titleText() != QStringLiteral("v")
                 && QFontMetrics(speed->titleFont()).horizontalAdvance(speed->titleText()) <= height,
             qPrintable(speed->titleText()));

    dock.resize(900, 700);
    for (int k = 0; k < 3; ++k) {
        dock.refreshChart();
        QCoreApplication::processEvents();
    }
    speed = speedAxis();
    QVERIFY(speed);
    QCOMPARE(speed->titleText(), QStringLiteral("speed (px/frame)"));
    QCOMPARE_GE(speed->categoriesLabels().size(), 4);

    // The speeds alone, up to 4 px/frame (Qt's nice numbers gave 0 to 6 in steps of 2 for the
    // three ticks asked for: four labels of "…" at 1280 x 720 x 1.5, seen under Xvfb).
    dock.setKineticEnergyShown(false);
    dock.setMomentumShown(false);
    World slow = worldWith(2);
    dock.reset(slow);
    for (int f = 1; f <= 20; ++f) {
        slow.frame = f;
        slow.velocity[0] = {4.0, 0.0};
        slow.velocity[1] = {-1.0, 0.0};
        dock.appendFrame(slow, nullptr);
    }
    dock.resize(900, 200);
    for (int k = 0; k < 3; ++k) {
        dock.refreshChart();
        QCoreApplication::processEvents();
    }
    speed = speedAxis();
    QVERIFY(speed);
    const double shortHeight = dock.chartView()->chart()->plotArea().height();
    const qsizetype shortLabels = speed->categoriesLabels().size();
    QVERIFY2(shortLabels >= 2 && (shortLabels - 1) * 1.5 * line <= shortHeight,
             qPrintable(QStringLiteral("%1 labels in %2 px, a line %3 px").arg(shortLabels).arg(shortHeight).arg(line)));
    QCOMPARE_GE(speed->max(), 4.0); // the line still under the top
}

void TestPlotDock::totalsStayOverTheSpeedLines()
{
    // Compared with exact, energy and momentum shown, after a restart: the totals are drawn over
    // the speed lines and listed after them, then the models' keys and the restart mark; and so
    // they stay when a selection makes new speed lines and when the comparison model changes.
    // (A selection had put the comparison's totals under the speed lines and "comparison
    // restarted" first in the legend.)
    PlotDock dock;
    World world = worldWith(4);
    dock.setKineticEnergyShown(true);
    dock.setMomentumShown(true);
    dock.reset(world);
    dock.setCompareModel(QStringLiteral("exact"));
    for (int f = 1; f <= 6; ++f) {
        world.frame = f;
        world.velocity[0] = {0.5 * f, 0.25 * f};
        dock.appendFrame(world, &world); // the comparison's lines on the scene's
    }
    dock.resize(1400, 350);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    dock.markCompareRestart(3);
    dock.refreshChart();
    // What each line is, in the chart's order (the order it draws them in), and the same for
    // the legend's entries shown.
    QString model = QStringLiteral("exact");
    const auto role = [&dock, &model](const QAbstractSeries *series) -> QString {
        for (int i = 0; i < 4; ++i) {
            if (series == dock.speedSeries(i))
                return QStringLiteral("marble %1").arg(i);
            if (series == dock.compareSeries(i))
                return QStringLiteral("marble %1, %2").arg(i).arg(model);
        }
        if (series == dock.kineticSeries())
            return QStringLiteral("energy");
        if (series == dock.compareKineticSeries())
            return QStringLiteral("energy, %1").arg(model);
        for (int c : {0, 1}) {
            if (series == dock.momentumSeries(c))
                return QStringLiteral("momentum %1").arg(c);
            if (series == dock.compareMomentumSeries(c))
                return QStringLiteral("momentum %1, %2").arg(c).arg(model);
        }
        return series->name(); // the keys and the restart marks
    };
    // The speed lines first, in any order (a comparison started adds its dashed lines after
    // the solid ones), then the rest in this order.
    const auto drawn = [&] {
        QStringList roles;
        for (const QAbstractSeries *series : dock.chartView()->chart()->series())
            roles << role(series);
        QStringList first = roles.mid(0, 8);
        first.sort();
        return first + roles.mid(8);
    };
    const auto listed = [&] {
        QStringList roles;
        for (QLegendMarker *marker : dock.chartView()->chart()->legend()->markers()) {
            if (marker->isVisible())
                roles << role(marker->series());
        }
        return roles;
    };
    QStringList speeds;
    for (int i = 0; i < 4; ++i)
        speeds << QStringLiteral("marble %1").arg(i) << QStringLiteral("marble %1, exact").arg(i); // sorted
    const QStringList overlays{QStringLiteral("energy"),         QStringLiteral("energy, exact"),
                               QStringLiteral("momentum 0"),     QStringLiteral("momentum 0, exact"),
                               QStringLiteral("momentum 1"),     QStringLiteral("momentum 1, exact"),
                               QStringLiteral("book (solid)"),   QStringLiteral("exact (dashed)"),
                               QStringLiteral("comparison restarted"), QStringLiteral("scene edited")};
    const QStringList legend{QStringLiteral("marble 0"),   QStringLiteral("marble 1"),     QStringLiteral("marble 2"),
                             QStringLiteral("marble 3"),   QStringLiteral("energy"),       QStringLiteral("momentum 0"),
                             QStringLiteral("momentum 1"), QStringLiteral("book (solid)"), QStringLiteral("exact (dashed)"),
                             QStringLiteral("comparison restarted")};
    QCOMPARE(drawn(), speeds + overlays);
    QTRY_COMPARE(listed(), legend);
    const QList<QPointF> energy = dock.kineticSeries()->points();
    const QList<QPointF> momentum = dock.momentumSeries(0)->points();
    const QList<QPointF> compareEnergy = dock.compareKineticSeries()->points();
    QCOMPARE(energy.size(), 6);
    QCOMPARE(compareEnergy.size(), 6);

    dock.setSelectedMarbles({3});
    dock.setSelectedMarbles({});
    dock.refreshChart();
    QCOMPARE(drawn(), speeds + overlays);
    QTRY_COMPARE(listed(), legend); // new markers show once the legend is laid out
    // The new lines have the points the old ones had.
    QCOMPARE(dock.kineticSeries()->points(), energy);
    QCOMPARE(dock.momentumSeries(0)->points(), momentum);
    QCOMPARE(dock.compareKineticSeries()->points(), compareEnergy);

    // Another comparison model starts with no restart: no mark in the legend until one.
    model = QStringLiteral("impulse");
    dock.setCompareModel(model);
    dock.refreshChart();
    for (QString *name : {&speeds[1], &speeds[3], &speeds[5], &speeds[7]})
        name->replace(QStringLiteral("exact"), QStringLiteral("impulse"));
    QStringList impulseOverlays = overlays;
    for (int k : {1, 3, 5})
        impulseOverlays[k].replace(QStringLiteral("exact"), QStringLiteral("impulse"));
    impulseOverlays[7] = QStringLiteral("impulse (dashed)");
    QStringList impulseLegend = legend;
    impulseLegend[8] = impulseOverlays[7];
    impulseLegend.removeLast();
    QCOMPARE(drawn(), speeds + impulseOverlays);
    QTRY_COMPARE(listed(), impulseLegend);
}

void TestPlotDock::editedLinesJumpAtTheirMark()
{
    // A helper's finding: the mass scale changed at frame 60 made the energy and momentum slope up
    // from frame 59 to 60, which pupils read as energy gained during that frame. The line goes
    // straight up at the mark, from the value the frame had as stepped.
    PlotDock dock;
    for (const char *box : {"kineticCheck", "momentumCheck"})
        dock.findChild<QCheckBox *>(QLatin1String(box))->setChecked(true);
    World world = worldWith(3);
    dock.reset(world);
    dock.setSelectedMarbles({1, 2});
    runFrames(dock, world, 8);
    const World at8 = world;
    World edited = at8;
    edited.setMassScale(2.5);
    edited.velocity[2] = {3, 4};
    dock.resample(edited, nullptr);
    QCOMPARE(dock.editMarks(), std::vector<std::int64_t>{8});
    for (int f = 9; f <= 10; ++f) {
        edited.frame = f;
        dock.appendFrame(edited, nullptr);
    }
    dock.refreshChart();
    // The points at frame 8 (sample 7: the samples start at frame 1), in the order drawn.
    QVERIFY(sameValues(valuesAt(dock.kineticSeries(), 8), QList<qreal>{at8.kineticEnergy(), dock.sampleKineticEnergy(7)}));
    QVERIFY(sameValues(valuesAt(dock.momentumSeries(1), 8), QList<qreal>{at8.momentum().y, dock.sampleMomentum(7).y}));
    QVERIFY(sameValues(valuesAt(dock.speedSeries(2), 8), QList<qreal>{length(at8.velocity[2]), 5.0}));
    // Not where the line did not jump (marble 1's speed: the mass scale is no velocity), nor
    // anywhere else.
    QCOMPARE(valuesAt(dock.speedSeries(1), 8).size(), 1);
    QCOMPARE(dock.kineticSeries()->points().size(), 11); // frames 1 to 10, and the jump

    // Marbles came or went since: the totals as stepped had others in them. The jump is from
    // the frame before.
    dock.marbleRemovedAt(0, 3);
    dock.refreshChart();
    QVERIFY(sameValues(valuesAt(dock.kineticSeries(), 8), QList<qreal>{dock.sampleKineticEnergy(6), dock.sampleKineticEnergy(7)}));
}

void TestPlotDock::comparedLinesJumpAtEditsAndRestarts()
{
    // A helper's re-test of the jumps: the comparison's dashed lines still sloped across the
    // frame before an edit (the comparison starts again there). They go straight up or down at
    // an edit, from their value as stepped; a restart alone has no value as stepped to go from.
    PlotDock dock;
    for (const char *box : {"kineticCheck", "momentumCheck"})
        dock.findChild<QCheckBox *>(QLatin1String(box))->setChecked(true);
    World world = worldWith(2);
    dock.reset(world);
    dock.setCompareModel(QStringLiteral("exact"));
    World compare = world;
    const auto step = [&](int f, double scale) {
        world.frame = f;
        compare.frame = f;
        for (int i = 0; i < world.marbleCount(); ++i) {
            world.velocity[static_cast<std::size_t>(i)] = {0.01 * f, 1.0 + i};
            compare.velocity[static_cast<std::size_t>(i)] = {scale * 0.01 * f, 2.0 + i};
        }
        dock.appendFrame(world, &compare);
    };
    for (int f = 1; f <= 8; ++f)
        step(f, 1.0);
    const World compareAt8 = compare;
    // The mass scale changed at frame 8: the comparison starts again there, from the scene.
    World edited = world;
    edited.setMassScale(2.5);
    World restarted = edited;
    dock.resample(edited, &restarted);
    dock.markCompareRestart(8);
    world = edited;
    compare = restarted;
    for (int f = 9; f <= 11; ++f)
        step(f, 1.0);
    // A restart without an edit.
    step(12, 3.0);
    dock.markCompareRestart(12);
    dock.refreshChart();
    QVERIFY(sameValues(valuesAt(dock.compareKineticSeries(), 8), {compareAt8.kineticEnergy(), restarted.kineticEnergy()}));
    QVERIFY(sameValues(valuesAt(dock.compareMomentumSeries(1), 8), {compareAt8.momentum().y, restarted.momentum().y}));
    QVERIFY(sameValues(valuesAt(dock.compareSeries(1), 8), {length(compareAt8.velocity[1]), length(restarted.velocity[1])}));
    QCOMPARE(valuesAt(dock.compareKineticSeries(), 12).size(), 1);
    QCOMPARE(valuesAt(dock.kineticSeries(), 8).size(), 2);
    QCOMPARE(valuesAt(dock.kineticSeries(), 12).size(), 1);
}

void TestPlotDock::restartMarkedOnlyAfterADashedLine()
{
    // A comparison that starts at frame 3 is not marked there (no dashed line before it jumps),
    // nor where Step Back goes before that start and it starts again; it is where it restarts
    // after frames of its own. (Step Back before the start had marked it.)
    PlotDock dock;
    World world = worldWith(2);
    dock.reset(world);
    const auto run = [&](int from, int to, bool compared) {
        for (int f = from; f <= to; ++f) {
            world.frame = f;
            world.velocity[0] = {0.5 * f, 0.0};
            dock.appendFrame(world, compared ? &world : nullptr);
        }
    };
    run(1, 2, false);
    dock.setCompareModel(QStringLiteral("exact"));
    run(3, 6, true);
    dock.markCompareRestart(3);
    QVERIFY(dock.compareRestarts().empty());
    dock.cutAfter(2); // Step Back to frame 2
    dock.markCompareRestart(2);
    QVERIFY(dock.compareRestarts().empty());
    run(3, 6, true);
    dock.markCompareRestart(5);
    QCOMPARE(dock.compareRestarts(), std::vector<std::int64_t>{5});
}

void TestPlotDock::legendNamesEveryModelOfTheLines()
{
    // Compared with exact, the scene's own model changed mid-run (an edit keeps the lines): the
    // solid lines are the book's up to the change and the impulse model's after it.
    PlotDock dock;
    World world = worldWith(2);
    dock.setCompareModel(QStringLiteral("exact"));
    const auto solidKey = [&dock]() -> QString {
        for (QAbstractSeries *series : dock.chartView()->chart()->series()) {
            if (series->name().endsWith(QStringLiteral("(solid)")))
                return series->name();
        }
        return {};
    };
    dock.startAt(world, &world);
    QCOMPARE(solidKey(), QStringLiteral("book (solid)"));
    // At the first frame, before any line: the model named is the new one alone.
    world.params.model = ModelKind::Exact;
    dock.resample(world, &world);
    QCOMPARE(solidKey(), QStringLiteral("exact (solid)"));
    world.params.model = ModelKind::Book;
    dock.resample(world, &world);
    QCOMPARE(solidKey(), QStringLiteral("book (solid)"));
    for (int f = 1; f <= 5; ++f) {
        world.frame = f;
        dock.appendFrame(world, &world);
    }
    world.params.model = ModelKind::Impulse;
    dock.resample(world, &world);
    QCOMPARE(solidKey(), QStringLiteral("book, then impulse (solid)"));
    QCOMPARE(dock.sampleCount(), 6);
    // Back to the first frame: no line is left, and the model now is the one named.
    dock.cutAfter(0);
    QCOMPARE(solidKey(), QStringLiteral("impulse (solid)"));
}

void TestPlotDock::totalsOnRequest()
{
    PlotDock dock;
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    World world = worldWith(2);
    dock.reset(world);
    runFrames(dock, world, 12);
    dock.refreshChart();

    QLineSeries *kinetic = nullptr;
    QLineSeries *momentum = nullptr;
    QLineSeries *momentumY = nullptr;
    for (QAbstractSeries *s : dock.chartView()->chart()->series()) {
        if (s->name() == QStringLiteral("kinetic energy"))
            kinetic = qobject_cast<QLineSeries *>(s);
        if (s->name() == QStringLiteral("momentum x"))
            momentum = qobject_cast<QLineSeries *>(s);
        if (s->name() == QStringLiteral("momentum y"))
            momentumY = qobject_cast<QLineSeries *>(s);
    }
    QVERIFY(kinetic && momentum && momentumY);
    // One colour, apart from the marbles'; y dotted (a second colour came near a marble's).
    QCOMPARE(momentum->pen().style(), Qt::SolidLine);
    QCOMPARE(momentumY->pen().style(), Qt::CustomDashLine);
    QVERIFY(!kinetic->isVisible());
    QCOMPARE(kinetic->count(), 0);

    auto *box = dock.findChild<QCheckBox *>(QStringLiteral("kineticCheck"));
    QTest::mouseClick(box, Qt::LeftButton, {}, QPoint(box->height() / 2, box->height() / 2));
    dock.refreshChart();
    QVERIFY(kinetic->isVisible());
    QCOMPARE(kinetic->count(), 12);
    QVERIFY(!momentum->isVisible());
    // KE at frame 12: each marble m = 12.5, v = (0.12, -0.5 i).
    const double v0 = 0.12 * 0.12;
    const double v1 = 0.12 * 0.12 + 0.25;
    QCOMPARE_LE(std::abs(kinetic->at(11).y() - 0.5 * 12.5 * (v0 + v1)), 1e-12);
    // The right-hand axes, one per total, titled with what it shows and shown with it.
    QValueAxis *energyAxis = nullptr;
    QValueAxis *momentumAxis = nullptr;
    for (QAbstractAxis *axis : dock.chartView()->chart()->axes(Qt::Vertical)) {
        if (axis->alignment() != Qt::AlignRight)
            continue;
        auto *value = qobject_cast<QValueAxis *>(axis);
        QVERIFY(value);
        (value->titleText() == QStringLiteral("kinetic energy") ? energyAxis : momentumAxis) = value;
    }
    QVERIFY(energyAxis && momentumAxis);
    QCOMPARE(momentumAxis->titleText(), QStringLiteral("momentum"));
    // Its labels and title in its lines' colour: which of three axes side by side is its.
    QCOMPARE(momentumAxis->labelsColor(), momentum->pen().color());
    QCOMPARE(momentumAxis->titleBrush().color(), momentum->pen().color());
    QVERIFY(energyAxis->isVisible());
    QVERIFY(!momentumAxis->isVisible());
    QVERIFY(kinetic->attachedAxes().contains(energyAxis));
    QVERIFY(momentum->attachedAxes().contains(momentumAxis) && momentumY->attachedAxes().contains(momentumAxis));

    box = dock.findChild<QCheckBox *>(QStringLiteral("momentumCheck"));
    QTest::mouseClick(box, Qt::LeftButton, {}, QPoint(box->height() / 2, box->height() / 2));
    dock.refreshChart();
    QVERIFY(momentum->isVisible() && momentumY->isVisible());
    QCOMPARE(momentum->count(), 12);
    // Signed components: |p| hid a momentum turning round (the book's head-on hit, 25 to -25).
    const double px = 12.5 * 0.24;
    const double py = 12.5 * -0.5;
    QCOMPARE_LE(std::abs(momentum->at(11).y() - px), 1e-12);
    QCOMPARE_LE(std::abs(momentumY->at(11).y() - py), 1e-12);
    QVERIFY(energyAxis->isVisible() && momentumAxis->isVisible());
    // Each axis spans its own total (a shared one flattened the smaller to a line at 0), the
    // momentum's both signs.
    QVERIFY(momentumAxis->max() >= px && momentumAxis->max() < 2 * (px - py));
    QVERIFY(momentumAxis->min() <= py && momentumAxis->min() > 2 * py);
    // One zero line: each axis's zero at the same height, on a tick of each (a momentum's zero
    // had sat above the speeds' and the energy's, where its line read as a speed above zero).
    QValueAxis *speedAxis = qobject_cast<QValueAxis *>(dock.chartView()->chart()->axes(Qt::Vertical, dock.speedSeries(0)).value(0));
    QVERIFY(speedAxis);
    auto zeroHeight = [](const QValueAxis *axis) { return -axis->min() / (axis->max() - axis->min()); };
    QCOMPARE_GT(zeroHeight(momentumAxis), 0.0);
    for (const QValueAxis *axis : {speedAxis, energyAxis}) {
        QCOMPARE_LE(std::abs(zeroHeight(axis) - zeroHeight(momentumAxis)), 1e-12);
        const double tick = zeroHeight(axis) * (axis->tickCount() - 1);
        QCOMPARE_LE(std::abs(tick - std::round(tick)), 1e-9);
        // No more ticks than an axis has alone: nine were too close, each label then read "…".
        QCOMPARE_LE(axis->tickCount(), 6);
        QCOMPARE(axis->tickCount(), momentumAxis->tickCount());
        // A speed or an energy is never negative: its axis labels its ticks from zero up, each at
        // its tick, and none of those below ("speed -2" read as a speed there could be).
        auto *labelled = qobject_cast<QCategoryAxis *>(axis == speedAxis ? speedAxis : energyAxis); // categoriesLabels() is not const
        QVERIFY(labelled);
        QCOMPARE(labelled->labelsPosition(), QCategoryAxis::AxisLabelsPositionOnValue);
        const QStringList labels = labelled->categoriesLabels();
        QCOMPARE(labels.size(), axis->tickCount());
        const double step = (axis->max() - axis->min()) / (axis->tickCount() - 1);
        for (int k = 0; k < labels.size(); ++k) {
            const double at = axis->min() + k * step;
            QCOMPARE_LE(std::abs(labelled->endValue(labels[k]) - at), 1e-9 * step);
            if (at < -1e-9 * step)
                QCOMPARE(labels[k].trimmed(), QString());
            else
                QCOMPARE(labels[k], QString::asprintf(axis->labelFormat().toLatin1().constData(), std::max(at, 0.0)));
        }
        QCOMPARE(labels[static_cast<qsizetype>(std::round(tick))], QStringLiteral("0"));
    }
    QVERIFY(energyAxis->max() >= kinetic->at(11).y() && energyAxis->max() < 2 * kinetic->at(11).y());
    dock.setKineticEnergyShown(false);
    QVERIFY(!energyAxis->isVisible() && momentumAxis->isVisible());
    dock.setMomentumShown(false);
    QVERIFY(!momentumAxis->isVisible());
    dock.refreshChart();
    QCOMPARE(speedAxis->min(), 0.0); // without a signed total, the speeds' axis starts at zero again
}

void TestPlotDock::hoverShowsExactValues_data()
{
    QTest::addColumn<bool>("seconds");
    QTest::addColumn<double>("hoverX"); // not exactly on a sample: the nearest one is described
    QTest::addColumn<QString>("expected");

    QTest::addRow("frames") << false << 6.8 << "frame 7 (0.14 s): marble 1, speed 1.23457 px/frame";
    // With the time in seconds the speed is per second too (1.2345678 px/frame at 20 ms a frame).
    QTest::addRow("seconds") << true << 0.141 << "frame 7 (0.14 s): marble 1, speed 61.7284 px/s";
}

void TestPlotDock::hoverShowsExactValues()
{
    QFETCH(bool, seconds);
    QFETCH(double, hoverX);
    QFETCH(QString, expected);

    PlotDock dock;
    World world = worldWith(2);
    dock.reset(world);
    for (int f = 1; f <= 10; ++f) {
        world.frame = f;
        world.velocity[1] = {f == 7 ? 1.2345678 : 0.5, 0.0};
        dock.appendFrame(world);
    }
    dock.setTimeInSeconds(seconds);
    dock.refreshChart();
    QLineSeries *line = dock.speedSeries(1);
    // The line and its axis in the same units as the hover (a speed axis in px/frame under a
    // time axis in seconds mixed two time units).
    QCOMPARE_LE(std::abs(line->at(6).y() - (seconds ? 1.2345678 * 50.0 : 1.2345678)), 1e-12);
    QValueAxis *speedAxis = nullptr;
    for (QAbstractAxis *axis : dock.chartView()->chart()->axes(Qt::Vertical)) {
        if (axis->alignment() == Qt::AlignLeft)
            speedAxis = qobject_cast<QValueAxis *>(axis);
    }
    QVERIFY(speedAxis);
    QCOMPARE(speedAxis->titleText(), seconds ? QStringLiteral("speed (px/s)") : QStringLiteral("speed (px/frame)"));
    QVERIFY(dock.sampleSpeed(6, 1) == 1.2345678); // held in px/frame either way (and so exported), same bits
    QCOMPARE(dock.describePoint(line, QPointF(hoverX, 1.2)), expected);

    // The readout follows the pointer to the nearest line: a few pixels off it still reads it
    // (Qt's hovered() signal needed the pointer on the 2 px pen), far from every line nothing.
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    dock.refreshChart();
    QChartView *view = dock.chartView();
    auto pixelOf = [&](double x, double y) {
        const QPointF inChart = view->chart()->mapToPosition(QPointF(x, y), line);
        return view->mapFromScene(view->chart()->mapToScene(inChart));
    };
    const QPoint onLine = pixelOf(line->at(6).x(), line->at(6).y()); // the peak at frame 7
    QTest::mouseMove(view->viewport(), onLine);
    QCOMPARE(dock.hoverText(), expected);
    QTest::mouseMove(view->viewport(), onLine - QPoint(0, 5));
    QCOMPARE(dock.hoverText(), expected);
    dock.hoverAt(onLine - QPoint(0, 40)); // marble 0's line is at 0, further down
    QCOMPARE(dock.hoverText(), QString());
    QTest::mouseMove(view->viewport(), onLine + QPoint(0, 4));
    QCOMPARE(dock.hoverText(), expected);
    QTest::mouseMove(view->viewport(), QPoint(1, 1)); // outside the plot area
    QCOMPARE(dock.hoverText(), QString());

    // The view's own tooltip event, a moment after the pointer stops, keeps the readout's
    // tooltip up (it hid it about a second after it was shown).
    // (Offscreen, the first tooltip goes within half a second anyway; the view's event must
    // bring it back, not keep it away.)
    dock.hoverAt(onLine);
    QVERIFY(QToolTip::isVisible());
    QTest::qWait(500);
    QHelpEvent help(QEvent::ToolTip, onLine, view->viewport()->mapToGlobal(onLine));
    QApplication::sendEvent(view->viewport(), &help);
    QTest::qWait(500); // a tooltip hidden goes after 300 ms
    QVERIFY(QToolTip::isVisible());
    QCOMPARE(QToolTip::text(), expected);
    QToolTip::hideText();
}

void TestPlotDock::hoverNamesLinesOnTopOfEachOther()
{
    // Two marbles at the same speed draw one line over the other: the readout names both (it
    // named the one drawn last, as if the other had no value there). Large values are plain
    // numbers ("1.03125e+06" read badly in class).
    PlotDock dock;
    World world = worldWith(6);
    dock.reset(world);
    for (int f = 1; f <= 10; ++f) {
        world.frame = f;
        for (Vec2 &v : world.velocity)
            v = {0.5, 0.0};
        dock.appendFrame(world);
    }
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    dock.refreshChart();
    QChartView *view = dock.chartView();
    QLineSeries *line = dock.speedSeries(0);
    const QPoint on = view->mapFromScene(view->chart()->mapToScene(view->chart()->mapToPosition(QPointF(4.0, 0.5), line)));
    const int narrowest = dock.minimumSizeHint().width();
    dock.hoverAt(on);
    QStringList all;
    for (int i = 0; i < 6; ++i)
        all << QStringLiteral("marble %1, speed 0.5 px/frame").arg(i);
    QCOMPARE(dock.hoverText(), QStringLiteral("frame 4 (0.08 s): ") + all.join(QStringLiteral("; ")));
    // However long, the readout does not widen the dock (seven lines' made the window wider
    // than the screen): it is cut to the room it has.
    QCOMPARE(dock.minimumSizeHint().width(), narrowest);
    auto *label = dock.findChild<QLabel *>(QStringLiteral("hoverLabel"));
    QVERIFY(label->text().size() <= dock.hoverText().size());
    QCOMPARE_LE(label->fontMetrics().horizontalAdvance(label->text()), std::max(label->width(), 1) + 1);

    world.velocity[0] = {4000.0, 0.0};
    world.frame = 11;
    dock.appendFrame(world);
    dock.setKineticEnergyShown(true);
    dock.refreshChart();
    // 12.5 x 4000^2 / 2 + 5 x 12.5 x 0.5^2 / 2 = 100000007.8125
    QCOMPARE(dock.describePoint(dock.kineticSeries(), QPointF(11.0, 0.0)),
             QStringLiteral("frame 11 (0.22 s): kinetic energy 100000008 mass\u00b7px\u00b2/frame\u00b2"));
    QValueAxis *energyAxis = nullptr;
    for (QAbstractAxis *axis : view->chart()->axes(Qt::Vertical)) {
        if (axis->alignment() == Qt::AlignRight && axis->isVisible())
            energyAxis = qobject_cast<QValueAxis *>(axis);
    }
    QVERIFY(energyAxis);
    QCOMPARE(energyAxis->labelFormat(), QStringLiteral("%.0f"));
    // One rule for the axis and the readout (the axis went back to powers of ten at 1e9, the
    // readout at 1e12): whole up to 1e12, then powers of ten on both.
    for (const auto &[speed, whole] : {std::pair{40000.0, true}, std::pair{4.0e6, false}}) {
        world.velocity[0] = {speed, 0.0};
        ++world.frame;
        dock.appendFrame(world);
        dock.refreshChart();
        const QString readout = dock.describePoint(dock.kineticSeries(), QPointF(double(world.frame), 0.0));
        QCOMPARE(readout.contains(QLatin1Char('e')) && readout.contains(QStringLiteral("e+")), !whole);
        QCOMPARE(energyAxis->labelFormat(), whole ? QStringLiteral("%.0f") : QStringLiteral("%.6g"));
    }
}

void TestPlotDock::exportCsv()
{
    World world;
    world.params.frameMs = 20.0;
    world.addMarble({100, 100}, 10.0, {3.0, 4.0}, 2.0);
    world.addMarble({300, 100}, 20.0, {-6.0, 0.0}, 1.0);
    PlotDock dock;
    dock.setSelectedMarbles({0}); // before the scene: marble 1 is not plotted at first
    dock.reset(world);
    for (int f = 1; f <= 2; ++f) {
        world.frame = f;
        dock.appendFrame(world);
    }
    dock.setSelectedMarbles({}); // marble 1 is plotted from frame 3 on
    world.frame = 3;
    world.velocity[1] = {-0.1, 0.0};
    dock.appendFrame(world);
    // Marble 1's mass doubled at frame 4: the plot's mark is in the file too.
    world.frame = 4;
    dock.appendFrame(world);
    world.mass[1] = 2.0;
    dock.resample(world, nullptr);
    QCOMPARE(dock.editMarks(), std::vector<std::int64_t>{4});

    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString path = dir.filePath(QStringLiteral("plot.csv"));
    QCOMPARE(dock.exportCsv(path), QString());

    QFile file(path);
    QVERIFY(file.open(QIODevice::ReadOnly | QIODevice::Text));
    const QStringList lines = QString::fromUtf8(file.readAll()).split(QLatin1Char('\n'));
    // KE = 2*25/2 + 1*36/2 = 43 and p = (6, 8) + (-6, 0) = (0, 8) at frames 1-2;
    // KE = 25 + 0.005 and p = (5.9, 8) at frame 3; with marble 1's mass 2, KE = 25 + 0.01 and
    // p = (5.8, 8) at frame 4.
    const QStringList expected = {
        QStringLiteral("frame,time_s,speed_0_px_per_frame,speed_1_px_per_frame,kinetic_energy_mass_px2_per_frame2,"
                       "momentum_x_mass_px_per_frame,momentum_y_mass_px_per_frame,scene_edited"),
        QStringLiteral("1,0.02,5,,43,0,8,0"),
        QStringLiteral("2,0.04,5,,43,0,8,0"),
        QStringLiteral("3,0.06,5,0.1,%1,%2,8,0")
            .arg(QString::number(25.0 + 0.5 * 0.1 * 0.1, 'g', QLocale::FloatingPointShortest),
                 QString::number(6.0 - 0.1, 'g', QLocale::FloatingPointShortest)),
        QStringLiteral("4,0.08,5,0.1,%1,%2,8,1")
            .arg(QString::number(25.0 + 0.5 * 2.0 * (0.1 * 0.1), 'g', QLocale::FloatingPointShortest),
                 QString::number(6.0 - 2.0 * 0.1, 'g', QLocale::FloatingPointShortest)),
        QString(), // the file ends with a newline
    };
    QCOMPARE(lines.size(), expected.size());
    for (qsizetype i = 0; i < lines.size(); ++i)
        QCOMPARE(lines.at(i), expected.at(i));
}

void TestPlotDock::exportCsvError()
{
    PlotDock dock;
    World world = worldWith(1);
    dock.reset(world);
    runFrames(dock, world, 3);
    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("no/such/folder/plot.csv"));
    const QString error = dock.exportCsv(path);
    QVERIFY(error.startsWith(path));
    QVERIFY(!QFile::exists(path));
    const QString png = dir.filePath(QStringLiteral("no/such/folder/plot.png"));
    QVERIFY(dock.exportPng(png).startsWith(png));
    QVERIFY(!QFile::exists(png));

    // A disk that fills up halfway: the file that was there stays as it was (Qt's buffered
    // QSaveFile renamed a cut-short file over it and reported success).
    for (const QString &name : {QStringLiteral("plot.csv"), QStringLiteral("plot.png")}) {
        const QString target = dir.filePath(name);
        QFile old(target);
        QVERIFY(old.open(QIODevice::WriteOnly));
        old.write("the teacher's earlier export\n");
        old.close();
        QString failure;
        {
            test::FileSizeLimit limit(100);
            QVERIFY(limit.ok());
            failure = name.endsWith(QStringLiteral(".csv")) ? dock.exportCsv(target) : dock.exportPng(target);
        }
        QVERIFY2(failure.startsWith(target + QStringLiteral(": cannot write: ")), qPrintable(failure));
        QVERIFY(old.open(QIODevice::ReadOnly));
        QCOMPARE(old.readAll(), QByteArray("the teacher's earlier export\n"));
        old.close();
    }
    QCOMPARE(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden),
             (QStringList{QStringLiteral("plot.csv"), QStringLiteral("plot.png")}));

    // Not a regular file (a named pipe here; /dev/null as root): refused, and left as it is
    // (QSaveFile renames its temporary file over whatever is there).
    const QByteArray pipe = QFile::encodeName(dir.filePath(QStringLiteral("pipe.csv")));
    QVERIFY(::mkfifo(pipe.constData(), 0600) == 0);
    const QString refused = dock.exportCsv(QString::fromLocal8Bit(pipe));
    QVERIFY2(refused.endsWith(QStringLiteral("cannot write: not a regular file (a folder or a device)")), qPrintable(refused));
    struct stat info {};
    QVERIFY(::stat(pipe.constData(), &info) == 0 && S_ISFIFO(info.st_mode));

    // A folder that is not there is named.
    const QString missing = dock.exportCsv(dir.filePath(QStringLiteral("no such folder/plot.csv")));
    QVERIFY2(missing.endsWith(QStringLiteral("cannot write: there is no folder ") + dir.filePath(QStringLiteral("no such folder"))),
             qPrintable(missing));
}

void TestPlotDock::exportPng()
{
    PlotDock dock;
    dock.resize(640, 420);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    World world = worldWith(3);
    dock.reset(world);
    runFrames(dock, world, 100);

    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("plot.png"));
    QCOMPARE(dock.exportPng(path), QString());
    QImage image(path);
    QVERIFY(!image.isNull());
    // At least kMinPngSize (the dock is smaller), and the dock keeps its own size.
    const qreal dpr = dock.chartView()->devicePixelRatioF();
    QCOMPARE(image.size(), dock.chartView()->size().expandedTo(PlotDock::kMinPngSize) * dpr);
    QCOMPARE_LT(dock.chartView()->width(), PlotDock::kMinPngSize.width());
    // Not blank: the marbles' lines are drawn.
    const QColor line = dock.speedSeries(0)->pen().color();
    int linePixels = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x)
            linePixels += image.pixelColor(x, y) == line ? 1 : 0;
    }
    QCOMPARE_GT(linePixels, 50);
    // A caption above the chart says what it shows, for a worksheet: dark text in the top strip.
    dock.setSceneName(QStringLiteral("Preset: Pachinko board"));
    QCOMPARE(dock.exportCaption(), QStringLiteral("Preset: Pachinko board \u2014 model: book \u2014 frames 1 to 100, 0.02 to 2.00 s"));
    QCOMPARE(dock.exportPng(path), QString());
    image.load(path);
    int ink = 0;
    for (int y = 0; y < int(16 * dpr); ++y) {
        for (int x = 0; x < image.width() / 3; ++x)
            ink += qGray(image.pixel(x, y)) < 100 ? 1 : 0;
    }
    QCOMPARE_GT(ink, 30);
    // From a crowd the picture holds twelve lines, and says so.
    World crowd = worldWith(20);
    dock.reset(crowd);
    runFrames(dock, crowd, 2);
    QCOMPARE(dock.exportCaption(),
             QStringLiteral("Preset: Pachinko board \u2014 model: book \u2014 %1 of 20 marbles plotted \u2014 frames 1 to 2, "
                            "0.02 to 0.04 s")
                 .arg(PlotDock::kMaxPlottedMarbles));
    // A scene with edits not saved says so: a preset's picture, a pin added and friction
    // raised, read as the preset's (a teacher's finding).
    dock.setSceneEdited(true);
    QVERIFY(dock.exportCaption().startsWith(QStringLiteral("Preset: Pachinko board \u2014 edited \u2014 model: book")));
    // Frames of 0.05 ms: the times in three digits (they read "0.00 to 0.00 s", a helper's finding).
    World brief = worldWith(1);
    brief.params.frameMs = 0.05;
    dock.reset(brief);
    runFrames(dock, brief, 2);
    QVERIFY2(dock.exportCaption().endsWith(QStringLiteral("frames 1 to 2, 5e-05 to 0.0001 s")), qPrintable(dock.exportCaption()));
    // The picture's totals axes carry their units (the window gives them in its status bar and
    // tooltips); the dock's own titles stay as they were.
    dock.setKineticEnergyShown(true);
    const QStringList before = axisTitles(dock);
    QCOMPARE(dock.exportPng(path), QString());
    QCOMPARE(axisTitles(dock), before);
}

void TestPlotDock::axesAreWrittenInTheDesktopsLanguage()
{
    // A German-locale tester's finding: the axes read "0.2 0.4" beside fields that wrote "0,2".
    // Qt Charts, asked for the desktop's numbers, wrote no label at all for "%g": the time axis
    // had gone blank.
    const QLocale before;
    QLocale::setDefault(QLocale(QLocale::German, QLocale::Germany));
    const auto restore = qScopeGuard([before] { QLocale::setDefault(before); });
    World world;
    world.addMarble({100, 100}, 10.0, {0.03, 0.0}); // 1.5 px/s
    PlotDock dock;
    dock.resize(900, 400);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    dock.setTimeInSeconds(true);
    dock.reset(world);
    for (int f = 0; f < 40; ++f) {
        world.frame = f;
        dock.appendFrame(world);
    }
    auto *view = dock.findChild<QChartView *>(QStringLiteral("plotChartView"));
    QVERIFY(view);
    QStringList labels;
    const auto timeAxisLabelled = [&labels, view] {
        labels.clear();
        for (QGraphicsItem *item : view->scene()->items()) {
            if (auto *text = dynamic_cast<QGraphicsTextItem *>(item); text && !text->toPlainText().isEmpty())
                labels << text->toPlainText();
        }
        return labels.contains(QStringLiteral("0,2")) && labels.contains(QStringLiteral("0,4")); // 0 to 0.78 s
    };
    // The chart lays its axes out on its own time.
    QTRY_VERIFY2(timeAxisLabelled(), qPrintable(labels.join(QLatin1Char('|'))));
    for (const QString &label : std::as_const(labels))
        QVERIFY2(!label.contains(QLatin1Char('.')), qPrintable(label));
}

void TestPlotDock::exportsAreOfferedByTheScenesName()
{
    // Every export was offered as "marbles-plot.csv" in the working folder, whatever the scene.
    PlotDock dock;
    dock.setSceneName(QStringLiteral("Preset: Four marbles (Figure 11.8)"));
    QCOMPARE(dock.suggestedExportPath(QStringLiteral("csv")), QStringLiteral("four-marbles-figure-11.8-plot.csv"));
    dock.setSceneName(QStringLiteral("Untitled"));
    QCOMPARE(dock.suggestedExportPath(QStringLiteral("png")), QStringLiteral("untitled-plot.png"));
    dock.setSceneName(QStringLiteral("collision.marbles.json"));
    dock.setSceneFile(QStringLiteral("/home/teacher/lessons/collision.marbles.json"));
    QCOMPARE(dock.suggestedExportPath(QStringLiteral("csv")), QStringLiteral("/home/teacher/lessons/collision-plot.csv"));
    // Letters beyond ASCII are kept (a German-locale tester's "Übung Stoß" was offered as
    // "bung-sto-plot.csv").
    dock.setSceneName(QStringLiteral("Übung Stoß.marbles.json"));
    dock.setSceneFile(QStringLiteral("/home/lehrer/Übung Stoß.marbles.json"));
    QCOMPARE(dock.suggestedExportPath(QStringLiteral("png")), QStringLiteral("/home/lehrer/übung-stoß-plot.png"));
    dock.setSceneName(QStringLiteral("Choc élastique"));
    dock.setSceneFile(QString());
    QCOMPARE(dock.suggestedExportPath(QStringLiteral("csv")), QStringLiteral("choc-élastique-plot.csv"));
    dock.setSceneName(QString());
    dock.setSceneFile(QString());
    QCOMPARE(dock.suggestedExportPath(QStringLiteral("csv")), QStringLiteral("marbles-plot.csv"));
}

QTEST_MAIN(TestPlotDock)
#include "tst_plotdock.moc"
