#pragma once

#include "core/world.h"
#include "ui/ringbuffer.h"

#include <QColor>
#include <QDockWidget>
#include <QList>
#include <QPointF>
#include <QSize>
#include <QString>
#include <QStringList>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <vector>

class QCheckBox;
class QCategoryAxis;
class QChart;
class QChartView;
class QLabel;
class QLineSeries;
class QRadioButton;
class QTimer;
class QValueAxis;

namespace marbles {

class ElidingLabel;

/// The Plot dock: speed over time, one line per plotted marble in its colour, plus the total
/// kinetic energy and momentum on request. Samples go into a bounded ring buffer, one per
/// simulated frame; a timer hands them to the chart a few times a second, so plotting never
/// slows the simulation down.
///
/// While a second model runs beside the document's (CompareRun), each plotted marble gets a
/// second, dashed line in the same colour: its speed in the comparison model, labelled with
/// that model's name. The totals get one too (kinetic energy and momentum in the comparison
/// model, dashed, the document's drawn solid meanwhile): the book model's energy climbing
/// beside the exact model's flat line is one of the things a class compares.
class PlotDock : public QDockWidget {
    Q_OBJECT

public:
    /// Most marbles plotted at once (the selection, or the first ones when nothing is selected).
    static constexpr int kMaxPlottedMarbles = 12;
    /// Samples (frames) kept by default; older frames are dropped.
    static constexpr qsizetype kDefaultCapacity = 5000;
    /// Smallest picture exportPng() makes, px: the dock is often a wide, low strip, whose shape
    /// would make a squat picture for a worksheet or a slide.
    static constexpr QSize kMinPngSize{1200, 675};
    /// The chart's smallest height, px (a screen less tall than 720 px allows less: MainWindow).
    static constexpr int kMinimumChartHeight = 220;
    /// How often buffered samples are handed to the chart, ms (about 5 times a second).
    static constexpr int kRefreshIntervalMs = 200;

    /// The dock, objectName "plotDock", with no samples.
    explicit PlotDock(QWidget *parent = nullptr);

    /// Forgets every sample and takes marble colours, names and frameMs from `world`
    /// (a new or loaded scene, or an edit; a jump back in time is cutAfter()). Adds no sample.
    void reset(const World &world);
    /// reset(), then the first sample: `world` as it is now (and `compare`, as appendFrame()).
    /// The lines start where the timeline does, so a push at that frame shows as a jump from
    /// the speed before it. (replayKeptFrames() with no frame kept before it.)
    void startAt(const World &world, const World *compare = nullptr);
    /// reset(), then a sample of each frame Step Back can return to (the velocity lookups',
    /// setVelocityLookup(), from `firstFrame` on, those of a gap left out, as many as it holds),
    /// and of `world` and `compare` now. What the window does on a new timeline: after a marble
    /// left the scene mid-run or came back, whose frames the timeline kept, or an add undone,
    /// which gives back those before it, the lines run on through them, with the marbles there
    /// are now (they had started again at the edit); a new scene keeps no frame, and they start
    /// where it does.
    void replayKeptFrames(const World &world, const World *compare, std::int64_t firstFrame);
    /// After an edit that kept the marbles: the sample of the current frame (if held) is taken
    /// again from `world` as edited (and `compare`), the earlier ones stay; the model's name in
    /// the legend follows the world's.
    void resample(const World &world, const World *compare = nullptr);
    /// Forgets the samples of frames after `frame` (the timeline went back to it: Step Back,
    /// Rewind); the earlier samples, and the lines they draw, stay.
    void cutAfter(std::int64_t frame);
    /// Records one sample of `world` as it is now (call once per simulated frame), and of `compare`,
    /// the comparison model's world at the same frame, when comparing (null: no comparison sample).
    /// Costs O(plotted marbles) for the speeds plus one pass for the two totals; never touches the chart.
    void appendFrame(const World &world, const World *compare = nullptr);
    /// The velocities of a run's marbles at a frame, or null when that frame is not known.
    using VelocityLookup = std::function<const std::vector<Vec2> *(std::int64_t frame)>;
    /// Where the speeds of a newly plotted marble come from for the samples already held: the
    /// document's frames (`document`) and the comparison model's (`compare`), as far as they
    /// keep them (Step Back's history). Without them, its line starts at the next sample.
    void setVelocityLookup(VelocityLookup document, VelocityLookup compare);
    /// Marbles to plot, by scene index; empty plots all of them, up to kMaxPlottedMarbles.
    /// Marbles that stay plotted keep their history; newly plotted ones get the speeds of the
    /// samples held from the velocity lookup (a gap where it has none), and go on from there.
    void setSelectedMarbles(const QList<int> &indices);
    /// Samples held now: one per appendFrame() since reset(), at most capacity().
    qsizetype sampleCount() const;

    /// Samples kept at most.
    qsizetype capacity() const;
    /// Changes how many samples are kept (at least 1); forgets every sample.
    void setCapacity(qsizetype samples);

    /// Marble colours follow the marbles, not their numbers: a marble removed at index i takes
    /// its colour with it (the later marbles keep theirs), and one put back at i gets it back; a
    /// marble added gets the first colour no marble has. (Deleting a marble had given every
    /// later marble, and its line, the colour of the one before it.) The masses the samples were
    /// taken with follow them too: one put back at i has `mass` in the frames before.
    void marbleRemovedAt(int i, int countBefore);
    void marbleInsertedAt(int i, int countAfter, double mass);
    /// A new scene: marble i gets the i-th colour again.
    void forgetColourOrder();
    /// Scene indices of the marbles plotted now, in plotting order.
    QList<int> plottedMarbles() const;
    /// Frame number of sample `i` (0 = oldest held).
    std::int64_t sampleFrame(qsizetype i) const;
    /// Speed |v| of `marble` at sample `i`, px/frame; NaN when the marble was not plotted then.
    double sampleSpeed(qsizetype i, int marble) const;
    /// Total kinetic energy sum m v^2 / 2 at sample `i` (mass px^2/frame^2).
    double sampleKineticEnergy(qsizetype i) const;
    /// Total momentum sum m v at sample `i` (mass px/frame), both components.
    Vec2 sampleMomentum(qsizetype i) const;
    /// Seconds of wall clock at `frame`: frame * frameMs / 1000, with the latest frameMs seen.
    double secondsAt(std::int64_t frame) const;

    /// Plots the speeds of a comparison model named `model` ("exact") as dashed lines beside the
    /// solid ones; "" removes them. A new name forgets the comparison samples held so far.
    void setCompareModel(const QString &model);
    /// The comparison started again at `frame` from the scene (an edit, a marble held): its dashed
    /// lines jump there to the scene's values, which a dotted line across the chart marks, so
    /// that the jump is not read as a collision. Restarts on consecutive frames (a marble held
    /// while the run goes on) make one mark, at the last of them.
    void markCompareRestart(std::int64_t frame);
    /// The comparison no longer starts again at `frame` (an edit there undone): its mark goes.
    void unmarkCompareRestart(std::int64_t frame);
    /// The frames marked so, oldest first.
    const std::vector<std::int64_t> &compareRestarts() const { return m_compareRestarts; }
    /// The frames where an edit made the scene's lines jump, oldest first: a velocity set, the
    /// mass scale or a mass changed mid-run, or such a change carried back by Step Back (the
    /// parameters keep their latest values, so the frame stepped back to is taken again with
    /// them). A dash-dot line across the chart marks each ("scene edited"), so that the jump is not
    /// read as energy from nowhere. An edit undone where it was made takes its mark away.
    std::vector<std::int64_t> editMarks() const;
    /// Name of the comparison model plotted, or "" when none.
    QString compareModel() const { return m_compareModel; }
    /// Speed |v| of `marble` in the comparison model at sample `i`, px/frame; NaN when there was no
    /// comparison sample then.
    double sampleCompareSpeed(qsizetype i, int marble) const;
    /// The dashed comparison line of `marble`, or nullptr when it is not plotted or nothing is compared.
    QLineSeries *compareSeries(int marble) const;
    /// The lines that draw the runs of `line` before its last gap (its samples that are no
    /// number: a comparison paused, frames not kept), oldest first; `line` draws the last run.
    QList<QLineSeries *> earlierRuns(const QLineSeries *line) const;
    /// Total kinetic energy in the comparison model at sample `i`; NaN when there was no
    /// comparison sample then (or nothing is compared).
    double sampleCompareKineticEnergy(qsizetype i) const;
    /// Total momentum in the comparison model at sample `i`; NaNs likewise.
    Vec2 sampleCompareMomentum(qsizetype i) const;
    /// The comparison model's kinetic energy line, or nullptr when nothing is compared.
    QLineSeries *compareKineticSeries() const { return m_compareKineticSeries; }
    /// The comparison model's line of the momentum's x (0) or y (1) component, or nullptr when
    /// nothing is compared.
    QLineSeries *compareMomentumSeries(int component) const { return m_compareMomentumSeries.at(component); }
    /// The document's kinetic energy line (hidden until setKineticEnergyShown(true)).
    QLineSeries *kineticSeries() const { return m_kineticSeries; }
    /// The document's line of the total momentum's x (0) or y (1) component (hidden until
    /// setMomentumShown(true)).
    QLineSeries *momentumSeries(int component) const { return m_momentumSeries.at(component); }

    /// Shows total kinetic energy (on the right-hand axis).
    void setKineticEnergyShown(bool shown);
    /// Shows the total momentum's x and y components, signed (on the right-hand axis): a
    /// momentum that turns round shows, where its size |sum m v| came back the same (the book
    /// model's head-on hit sends 25 to -25).
    void setMomentumShown(bool shown);
    /// Whether the totals' lines are shown.
    bool isKineticEnergyShown() const;
    bool isMomentumShown() const;
    /// Horizontal axis in seconds (true) or frames (false).
    void setTimeInSeconds(bool seconds);
    /// True when the horizontal axis counts seconds.
    bool isTimeInSeconds() const;
    /// Frames per second while the time axis is in seconds (speeds are drawn in px/s, the
    /// energy per second squared, the momentum per second), else 1.
    double perSecond() const;
    /// The units of the totals as drawn: "mass·px²/frame²" and "mass·px/frame", or per s.
    QString energyUnit() const;
    QString momentumUnit() const;

    /// Hands the buffered samples to the chart now (the timer does this ~5 times a second).
    void refreshChart();
    /// Points a line hands the chart at most: about one per pixel of the plot's width, between
    /// 200 and 2,000 (2,000 before the chart has a size). Longer lines are thinned to their
    /// lowest and highest samples per two pixel columns.
    qsizetype pointsPerLine() const;
    /// The chart view (for exporting and for tests).
    QChartView *chartView() const;
    /// The line of `marble`, or nullptr when it is not plotted.
    QLineSeries *speedSeries(int marble) const;
    /// Text describing the sample nearest to `point` on `series`: frame, time, what and the exact value.
    QString describePoint(const QLineSeries *series, QPointF point) const;
    /// The same for several lines at once, at time-axis value `x` ("frame 7 (0.14 s): marble 1,
    /// speed 1.2 px/frame; marble 1, exact, speed 1.2 px/frame").
    QString describePoints(const QList<const QLineSeries *> &lines, double x) const;
    /// Shows in the readout (and a tooltip) the value of the visible line nearest to the chart
    /// view's viewport pixel `viewportPos`, within kHoverReach px; clears it where none is.
    /// The view's mouse moves call it.
    void hoverAt(QPoint viewportPos);
    /// How far from a line, in px, the pointer still reads its value.
    static constexpr double kHoverReach = 8.0;
    /// The text the hover label shows now ("" when nothing is hovered).
    QString hoverText() const;
    /// True while the legend gives the marbles short labels ("#3"), the full ones not fitting.
    bool legendIsCompact() const { return m_compactLegend; }

    /// Writes every held sample as CSV, speeds in px/frame whatever the time axis shows:
    /// frame,time_s,speed_<i>_px_per_frame...,kinetic_energy_mass_px2_per_frame2,momentum_x_mass_px_per_frame,
    /// momentum_y_mass_px_per_frame (shortest round-trip digits; an empty field where a marble was
    /// not plotted), then speed_<i>_<model>_px_per_frame..., kinetic_energy_<model>_...,
    /// momentum_x_<model>_..., momentum_y_<model>_... while a comparison model is plotted.
    /// Returns "" or a message naming the file.
    QString exportCsv(const QString &path) const;
    /// Saves the chart as a PNG, at least kMinPngSize, with exportCaption() above it. Returns "" or
    /// a message naming the file.
    QString exportPng(const QString &path);
    /// The scene's name, for the PNG's caption.
    void setSceneName(const QString &name) { m_sceneName = name; }
    /// Whether the scene has edits not saved: the caption says "edited" after its name (a
    /// preset's picture, with a pin added and friction raised, read as the preset's).
    void setSceneEdited(bool edited) { m_sceneEdited = edited; }
    /// The scene's file ("" for an untitled scene): the exports are offered beside it.
    void setSceneFile(const QString &path) { m_sceneFile = path; }
    /// The file name the export dialogs offer, `extension` "csv" or "png": the scene's name and
    /// "-plot" ("pachinko-plot.csv"), beside the scene's file when it has one.
    QString suggestedExportPath(const QString &extension) const;
    /// The line written above the chart in a PNG: the scene, the models and the frames shown
    /// ("Preset: Pachinko board — model: book (solid), exact (dashed) — frames 0 to 137, 0.00
    /// to 2.74 s"), so that a picture in a worksheet says what it is.
    QString exportCaption() const;
    /// Asks where, then exportCsv() or exportPng() there (a warning says why not, where not);
    /// the dock's CSV... and PNG... buttons and File > Export Plot.
    void exportCsvInteractive();
    void exportPngInteractive();

    /// Takes the marbles' names and colours from `world` again (a marble renamed in the
    /// Inspector): the legend and the readout follow.
    void updateMarbleInfo(const World &world);
    /// Each plotted marble with its line's colour, in marble order.
    QList<QPair<int, QColor>> plottedColours() const;
    /// The colours the stage gives marbles without one of their own: the plotted marbles' lines'
    /// (plottedColours()), and in a scene of at most kMaxPlottedMarbles marbles the others keep
    /// theirs while a selection plots some, so that selecting a marble does not turn the others
    /// blue. In a larger scene only the plotted marbles wear colours.
    QList<QPair<int, QColor>> stageColours() const;

signals:
    /// A CSV or PNG was written to `path` by the interactive exports.
    void exported(const QString &path);
    /// The plotted marbles, or their colours, changed (plottedColours()).
    void plottedChanged();
    /// A choice the teacher's settings keep changed: the totals shown, or the time axis's unit.
    void choicesChanged();

protected:
    bool eventFilter(QObject *watched, QEvent *event) override;

private:
    /// One plotted marble: its speed history, aligned sample for sample with m_frames, and while
    /// comparing its speed in the comparison model (aligned the same way).
    struct Track {
        int marble = 0;
        RingBuffer<double> speed;
        QLineSeries *series = nullptr;
        RingBuffer<double> compareSpeed;
        QLineSeries *compareSeries = nullptr;
    };

    /// Calls `apply` on every buffer of sample values: all the ring buffers but m_frames.
    template<typename Apply>
    void forEachValueBuffer(Apply &&apply);
    void rebuildTracks();
    /// The models the solid lines ran in, in order ("book, then impulse").
    QString solidModels() const;
    QLineSeries *addSpeedSeries();
    void startFrom(RingBuffer<double> &values, int marble, const VelocityLookup &lookup) const;
    void startWithGaps(RingBuffer<double> &values) const { startFrom(values, 0, {}); }
    /// Fills the gaps (NaN) of a marble's samples where `lookup` knows the frame.
    void fillGaps(RingBuffer<double> &values, int marble, const VelocityLookup &lookup) const;
    void addCompareTrack(Track &t);
    void removeCompareTrack(Track &t);
    QLineSeries *addTotalSeries(QColor colour, QValueAxis *axis);
    /// Takes `series` off the chart and deletes it (nothing when null), the lines of its earlier
    /// runs with it; leaves it null.
    void deleteSeries(QLineSeries *&series);
    /// The lines of the earlier runs of `line` take its pen and its visibility.
    void followLine(const QLineSeries *line);
    /// A grey legend entry for the scene's model (solid) or the comparison's (dashed).
    QLineSeries *addKeySeries(bool dashed);
    /// Makes the lines drawn over the speed lines anew, after them (see the .cpp).
    void remakeOverlays();
    void showTotal(QLineSeries *series, bool shown);
    void styleSeries();
    void updateLegendLabels();
    /// Whether the legend's entries, the marks' keys among them, fit its one row: with their
    /// short labels or in full.
    bool legendFits(bool compact, bool markKeys = true) const;
    /// Shows or hides `series`'s legend entry; whether that changed anything.
    bool showKey(QLineSeries *series, bool shown);
    /// Whether marble `marble` has a name of its own (its key tells it by name, not "#3").
    bool isNamed(int marble) const;
    /// A marble's short label: its name, or "#3".
    QString compactMarbleLabel(int marble) const;
    QList<int> wantedMarbles() const;
    QColor marbleColor(int marble) const;
    /// Gives marbles 0..count-1 a place in the colour list (the first free ones to those without).
    void ensureColourOrder(int count);
    QString marbleLabel(int marble) const;
    double xOf(std::int64_t frame) const;
    const Track *trackOf(int marble) const;
    /// A line's value at one sample, in the units drawn, with what it is ("marble 2, speed").
    struct PlottedValue {
        QString what;
        double value;
        QString unit;
    };
    std::optional<PlottedValue> plottedValue(const QLineSeries *series, std::size_t sample) const;
    /// The sample whose frame is nearest to `x`, in the time axis' units (m_frames not empty).
    std::size_t nearestSample(double x) const;
    /// The visible lines nearest to chart point `at` within kHoverReach px (and those within a
    /// pixel of the nearest, drawn on top of it), nearest first; empty where none is.
    QList<const QLineSeries *> seriesNear(QPointF at) const;
    /// The scene's totals' lines, as totalName() counts them (null until the dock is built).
    std::array<QLineSeries *, 3> sceneTotals() const;
    /// The totals' names, 0 kinetic energy, 1 momentum x, 2 momentum y: in full, and as the
    /// legend gives them where the full ones do not fit ("KE", "p x", "p y").
    QString totalName(int k) const;
    QString totalShortName(int k) const;
    /// The legend's entries that are not lines of data: the two models' keys and the marks.
    enum class Key { Model, Compare, Restart, Edit };
    /// Such an entry's label, in full ("book (solid)", "comparison restarted") or short ("book",
    /// "restarted"), where its line sample tells the rest.
    QString keyName(Key key, bool compact) const;
    /// A series of marks (Key::Restart or Key::Edit) drawn in `style`, its legend entry shown
    /// when `listed`.
    QLineSeries *addMarkSeries(Qt::PenStyle style, Key key, bool listed);
    void updateAxisTitles();
    void updateTotalsAxis();

    std::size_t m_capacity = kDefaultCapacity;
    RingBuffer<std::int64_t> m_frames;
    RingBuffer<double> m_kinetic;
    std::array<RingBuffer<double>, 2> m_momentum; ///< x and y
    RingBuffer<double> m_compareKinetic;  ///< while comparing, aligned with m_frames
    std::array<RingBuffer<double>, 2> m_compareMomentum; ///< while comparing, aligned with m_frames
    std::vector<Track> m_tracks;
    // The marbles plotted when none is selected (0 to kMaxPlottedMarbles - 1) that are not plotted
    // now: still sampled, without lines, so that taking the selection away brings their lines
    // back whole (they were started again from what Step Back keeps, a few hundred frames in a
    // crowd).
    std::vector<Track> m_parked;
    /// Each marble's place in the default colour list (marbles past its end: their index).
    std::vector<int> m_hues;
    /// The places of the marbles removed, with their index then, newest last (marbleInsertedAt()).
    std::vector<std::pair<int, int>> m_removedHues;
    /// The masses the scene's samples were taken with, from `frame` on (up to the next entry's),
    /// oldest first: replayKeptFrames() takes each frame again with them. (With the masses of
    /// now, a mass edited at frame 60 and a marble deleted and put back had redrawn frames 0 to
    /// 59 with the new mass: an elastic head-on collision's momentum jumped where it is kept.)
    struct MassesFrom {
        std::int64_t frame = 0;
        std::vector<double> mass;
    };
    std::vector<MassesFrom> m_massesFrom;
    /// The masses of the marbles removed, as (frame, mass) from each entry of m_massesFrom, with
    /// their index then, newest last: a delete undone gives its marble its masses back (with
    /// its mass of now, a mass changed mid-run was drawn from frame 0; a helper's finding).
    std::vector<std::pair<int, std::vector<std::pair<std::int64_t, double>>>> m_removedMasses;
    /// Keeps the masses `world` has from its frame on (appendFrame()).
    void noteMasses(const World &world);
    /// The masses frame `frame` was taken with, where they are known for `count` marbles; else null.
    static const std::vector<double> *massesAt(const std::vector<MassesFrom> &eras, std::int64_t frame, int count);
    VelocityLookup m_documentVelocities; ///< may be empty (no earlier speeds for new lines)
    VelocityLookup m_compareVelocities;  ///< may be empty

    QList<int> m_selected;
    int m_marbleCount = 0;
    std::vector<QString> m_colors; ///< "#rrggbb" per marble, "" for the default palette
    std::vector<QString> m_names;
    /// The document's models along the lines held, oldest first (one unless the model was
    /// changed mid-run): the solid lines' legend entry names them all.
    QStringList m_models{QStringLiteral("book")};
    QString m_compareModel; ///< the comparison model's name, "" when none
    QString m_sceneName;
    bool m_sceneEdited = false;
    QString m_sceneFile;
    double m_frameMs = 20.0;
    bool m_timeInSeconds = false;
    bool m_dirty = false;

    QChart *m_chart = nullptr;
    QChartView *m_chartView = nullptr;
    bool m_compactLegend = false; // the marbles' legend labels are the short ones
    bool m_markKeysHidden = false; // even short, the legend has no room for the marks' keys
    bool m_marbleKeysHidden = false; // nor for the unnamed marbles' ("#3": hovering a line names it)
    QValueAxis *m_axisX = nullptr;
    // Speeds and energies are never negative: their axes label no tick below zero (they have
    // such ticks only to share the momentum's zero line), so they are category axes.
    QCategoryAxis *m_axisSpeed = nullptr;
    QCategoryAxis *m_axisTotals = nullptr; // kinetic energy, on the right
    QCategoryAxis *m_axisMomentum = nullptr; // momentum x and y, on the right beside it: its own scale
    QValueAxis *m_rangeScratch = nullptr; ///< works out nice ranges away from the chart
    QLineSeries *m_kineticSeries = nullptr;
    std::array<QLineSeries *, 2> m_momentumSeries{}; ///< x and y
    QLineSeries *m_compareKineticSeries = nullptr;  ///< while comparing
    std::array<QLineSeries *, 2> m_compareMomentumSeries{}; ///< while comparing
    QLineSeries *m_modelKey = nullptr;   ///< legend entry only, while comparing: "book (solid)"
    QLineSeries *m_compareKey = nullptr; ///< legend entry only, while comparing: "exact (dashed)"
    QLineSeries *m_restartMarks = nullptr; ///< while comparing: a dotted line at each restart
    std::vector<std::int64_t> m_compareRestarts;
    /// Per line with a gap, the lines of its runs before the last gap (drawRuns()).
    std::map<const QLineSeries *, std::vector<QLineSeries *>> m_earlierRuns;
    /// The scene's values at one sample: what a jump in its lines is seen in.
    struct SceneSample {
        double kinetic = 0.0;
        Vec2 momentum;
        std::vector<std::pair<int, double>> speeds; ///< (marble, speed) of every sampled marble
        /// The comparison's, while comparing (NaN, none otherwise); not part of sameAs().
        double compareKinetic = std::numeric_limits<double>::quiet_NaN();
        Vec2 compareMomentum{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
        std::vector<std::pair<int, double>> compareSpeeds;
        /// The same bits, marble by marble where both have a marble's speed.
        bool sameAs(const SceneSample &other) const;
    };
    /// The newest sample's scene values (there must be one).
    SceneSample newestSceneSample() const;
    /// A frame where an edit made the lines jump, with the values it had as stepped.
    struct EditMark {
        std::int64_t frame = 0;
        SceneSample asStepped;
        /// False once marbles came or went: the totals as stepped had other marbles in them.
        bool asSteppedKnown = true;
    };
    /// A value of a scene line in a sample as stepped, scaled as drawn; none where it has none.
    using SampleValue = std::function<std::optional<double>(const SceneSample &)>;
    /// Where an edit made a line jump at frame F, the line goes straight up or down at F, from
    /// the value F had as stepped (or, where marbles came or went since, the sample before it):
    /// it sloped across the frame before, which read as a change during that frame (a helper's
    /// finding). A comparison's line does so where it was running at the mark (it starts again
    /// there). Widens [yMin, yMax] to cover the points added.
    void addEditJumps(QList<QPointF> &points, const SampleValue &asStepped, double &yMin, double &yMax) const;
    /// Gives `line` the last of `runs` (thinnedRuns()) and the earlier ones to lines of their own
    /// (made or deleted as their count changes), each with its jumps at edits (addEditJumps()).
    /// True when it made a line (drawn over the lines made before it).
    bool drawRuns(QLineSeries *line, std::vector<QList<QPointF>> runs, const SampleValue &asStepped, double &yMin,
                  double &yMax);
    std::vector<EditMark> m_editMarks;
    QLineSeries *m_editMarkSeries = nullptr; ///< a dash-dot line at each edit mark
    QCheckBox *m_showKinetic = nullptr;
    QCheckBox *m_showMomentum = nullptr;
    QRadioButton *m_frameAxis = nullptr;
    QRadioButton *m_secondAxis = nullptr;
    ElidingLabel *m_hoverLabel = nullptr; ///< the readout, whole in its fullText()
    QLabel *m_capNote = nullptr;
    QTimer *m_refreshTimer = nullptr;
};

} // namespace marbles
