#include "ui/plotdock.h"

#include "ui/elidinglabel.h"
#include "ui/filedialog.h"
#include "ui/filenames.h"
#include "ui/numbertext.h"
#include "ui/quiettext.h"
#include "ui/wholefile.h"

#include <QBuffer>
#include <QCategoryAxis>
#include <QChart>
#include <QChartView>
#include <QCheckBox>
#include <QDir>
#include <QFileInfo>
#include <QFontMetrics>
#include <QGraphicsLayout>
#include <QHBoxLayout>
#include <QHelpEvent>
#include <QLabel>
#include <QLegendMarker>
#include <QLineF>
#include <QLineSeries>
#include <QMessageBox>
#include <QMouseEvent>
#include <QPainter>
#include <QPixmap>
#include <QPushButton>
#include <QRadioButton>
#include <QSet>
#include <QTimer>
#include <QToolTip>
#include <QValueAxis>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace marbles {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Ticks on the time axis before the nice numbers adjust them (QValueAxis's default).
constexpr int kAxisTicks = 5;

/// A line longer than the plot is wide in pixels is thinned before it reaches the chart: each
/// bucket of samples (two pixel columns' worth) becomes its lowest and its highest point, so
/// spikes (collisions) stay visible. Every point costs the chart twice (Qt Charts strokes the
/// whole line to find its shape, then draws it): with 12 lines of 3,000 samples, one point per
/// sample took a refresh 10.3 ms, half of them in drawing. At most this many points, and this
/// many while the chart has no size yet:
constexpr qsizetype kMaxPointsPerLine = 2000;
/// Thinning never leaves fewer points than this.
constexpr qsizetype kMinPointsPerLine = 200;

/// Dashes of a comparison model's lines, in pen widths: short enough that even the legend's
/// short sample line shows two dashes.
const QList<qreal> kCompareDashes{2.5, 2.0};

/// The pen of a comparison model's line in `colour`.
QPen comparePen(QColor colour)
{
    QPen pen(colour, 2.0, Qt::CustomDashLine);
    pen.setCapStyle(Qt::FlatCap);
    pen.setDashPattern(kCompareDashes);
    return pen;
}

/// Colours of the two totals' lines (the comparison model's in the same colour, dashed): apart
/// from every marble's.
const QColor kKineticColour(0x33, 0x33, 0x33);
// The momentum's navy, the farthest colour from every marble's, the greys and the stage's blue
// (a purple and a navy for x and y were near the wine of marble 7 and the violet of marble 5,
// and a green for y looked like marble 1's bluish green): x solid, y dotted, each dashed the
// more for a compared model.
const QColor kMomentumColour(0x00, 0x00, 0xa0);
/// The grey of the comparison restarts' and the edits' marks, told apart by their dashes and
/// dots: a colour of their own would come near a marble's.
const QColor kMarkColour(0x75, 0x75, 0x75);

/// The pen of the momentum's component `c` (0 x, 1 y), the comparison model's when `compared`.
QPen momentumPen(int c, bool compared)
{
    if (c == 0)
        return compared ? comparePen(kMomentumColour) : QPen(kMomentumColour, 2.0);
    QPen pen(kMomentumColour, 2.0, Qt::CustomDashLine);
    pen.setCapStyle(Qt::FlatCap);
    pen.setDashPattern(compared ? QList<qreal>{2.5, 1.5, 1.0, 1.5} : QList<qreal>{1.0, 1.5});
    return pen;
}

/// Marbles without a colour of their own are drawn blue on the stage, and the plotted ones in
/// their lines' colours (StageView::setMarbleTints()): so no line is that blue or near it (marble
/// 0's line was the stage's blue, and on a crowd its marble looked like every other), and the
/// hues are clearly different from each other (colour-blind safe, after Okabe and Ito, with the
/// sky blue left out): four shades of blue, which the lines once were, could not be told apart.
/// No grey either (a cyan took its place): the comparison's legend keys, the kinetic energy's
/// line and the selection's ring are greys. A violet and a magenta took the places of a gold and a
/// dark green, which a class took for the orange and the bluish green. Neighbours in the list
/// differ most, the first two above all (a two-marble collision is the commonest lesson): its
/// vermilion and orange had been marbles 0 and 1, hard to tell apart on a projector.
QColor defaultMarbleColor(int marble)
{
    // Twelve, as many as lines are plotted at most (kMaxPlottedMarbles): no two lines share one.
    static const QColor hues[] = {
        QColor(0xd5, 0x5e, 0x00), QColor(0x00, 0x9e, 0x73), QColor(0xcc, 0x79, 0xa7), QColor(0xe6, 0x9f, 0x00),
        QColor(0x4d, 0xd0, 0xe1), QColor(0x55, 0x00, 0xff), QColor(0x99, 0x99, 0x33), QColor(0x88, 0x22, 0x55),
        QColor(0xff, 0x22, 0xff), QColor(0x8c, 0x51, 0x0a), QColor(0x66, 0xa6, 0x1e), QColor(0xe7, 0x29, 0x8a),
    };
    static_assert(sizeof(hues) / sizeof(hues[0]) >= PlotDock::kMaxPlottedMarbles);
    constexpr int count = sizeof(hues) / sizeof(hues[0]);
    return hues[marble % count];
}

/// Distance from `p` to the segment from `a` to `b`.
double distanceToSegment(QPointF p, QPointF a, QPointF b)
{
    const QPointF ab = b - a;
    const double lengthSquared = QPointF::dotProduct(ab, ab);
    const double t = lengthSquared > 0.0 ? std::clamp(QPointF::dotProduct(p - a, ab) / lengthSquared, 0.0, 1.0) : 0.0;
    return QLineF(p, a + t * ab).length();
}

/// The shortest decimal text that reads back as the same double ("" for NaN: no sample).
QString csvNumber(double value)
{
    if (std::isnan(value))
        return QString();
    return QString::number(value, 'g', QLocale::FloatingPointShortest);
}

/// The finite points (x(i), y(i)), i in [0, n), thinned to at most maxPoints in all (within
/// each bucket the lowest and the highest point are kept, in sample order), as the runs the
/// samples that are no number leave between them, oldest first. Widens [yMin, yMax] to cover them.
/// A line has no value for the frames its model did not keep (a marble selected after a long
/// run of a large scene: Step Back's history holds its last few hundred frames; a comparison
/// started mid-run, or paused by an edit it cannot follow): each run is drawn apart
/// (PlotDock::drawRuns()), as a line across the gap (from frame 0's value to the first kept one)
/// would show a change that was never seen.
template<typename XFn, typename YFn>
std::vector<QList<QPointF>> thinnedRuns(qsizetype n, qsizetype maxPoints, XFn x, YFn y, double &yMin, double &yMax)
{
    std::vector<QList<QPointF>> runs;
    qsizetype first = 0;
    while (first < n && !std::isfinite(y(first)))
        ++first;
    if (first == n)
        return runs;
    const qsizetype bucket = n - first <= maxPoints ? 1 : (2 * (n - first) + maxPoints - 1) / maxPoints;
    for (qsizetype begin = first; begin < n;) {
        qsizetype end = begin;
        while (end < n && std::isfinite(y(end)))
            ++end;
        QList<QPointF> &out = runs.emplace_back();
        out.reserve(bucket == 1 ? end - begin : 2 * ((end - begin) / bucket + 1));
        for (qsizetype start = begin; start < end; start += bucket) {
            qsizetype lo = start;
            qsizetype hi = start;
            for (qsizetype i = start + 1; i < std::min(end, start + bucket); ++i) {
                const double v = y(i);
                if (v < y(lo))
                    lo = i;
                if (v > y(hi))
                    hi = i;
            }
            yMin = std::min(yMin, y(lo));
            yMax = std::max(yMax, y(hi));
            out.append(QPointF(x(std::min(lo, hi)), y(std::min(lo, hi))));
            if (lo != hi)
                out.append(QPointF(x(std::max(lo, hi)), y(std::max(lo, hi))));
        }
        begin = end;
        while (begin < n && !std::isfinite(y(begin)))
            ++begin; // a run that stopped on a blow-up ends with a frame that is no number
    }
    return runs;
}

/// A speed or a momentum as plotted: the book's sqrt(x^2 + y^2) (the same bits as the models'
/// own lengths), but where the squares overflow, the size without overflow: the book's blow-up
/// passes 1.3e154 px/frame some 800 frames before its numbers stop being finite, and its lines
/// ended there.
double magnitude(Vec2 u)
{
    const double l = length(u);
    return std::isinf(l) ? std::hypot(u.x, u.y) : l;
}

/// An axis's range and tick count.
struct AxisRange {
    double min = 0.0;
    double max = 1.0;
    int ticks = kAxisTicks;
};

/// A range a little wider than [lo, hi], never empty, with readable tick values: what
/// QValueAxis::applyNiceNumbers() makes of it from `ticks` ticks. Worked out on `scratch`, an
/// axis of no chart, so that the chart's axes change only when the outcome does: every change of
/// a chart axis's range recomputes the geometry of every line on it.
AxisRange niceRange(QValueAxis *scratch, double lo, double hi, int ticks = kAxisTicks)
{
    if (!(lo <= hi)) {
        lo = 0.0;
        hi = 1.0;
    }
    if (hi - lo < 1e-12) {
        const double pad = std::max(std::abs(hi) * 0.1, 1.0);
        lo -= lo == 0.0 ? 0.0 : pad;
        hi += pad;
    }
    // Qt Charts works out tick i as i * (max - min) / ticks, which overflows near the largest
    // double (the book's blow-up reaches 1e308 px/frame): its ticks read "inf". The axis stops
    // short of that; the last few frames of such a run go off its top.
    // Likewise below zero: a momentum past -1.7e308 read "inf" at every tick (a helper's finding).
    // Its ticks are round numbers 2e306 apart with zero on one, up to 8e306 either way (below
    // the largest double / 20): the axes read "8.98847e+306", and their zero lines, off every
    // tick, could not be aligned (alignZeros()).
    constexpr double largest = std::numeric_limits<double>::max() / (4 * kAxisTicks);
    if (hi > largest || lo < -largest) {
        constexpr double step = 2e306;
        constexpr double most = 4.0;
        static_assert(most * step <= largest);
        double below = std::clamp(std::floor(lo / step), -most, most);
        double above = std::clamp(std::ceil(hi / step), -most, most);
        if (above <= below) { // all of it beyond one end: the step inside that end
            if (above >= most)
                below = most - 1.0;
            else
                above = below + 1.0;
        }
        return {below * step, above * step, static_cast<int>(above - below) + 1};
    }
    scratch->setTickCount(ticks);
    scratch->setRange(lo, hi);
    scratch->applyNiceNumbers();
    return {scratch->min(), scratch->max(), scratch->tickCount()};
}

/// Puts zero at the same height on every axis of `ranges` (each with zero on one of its ticks,
/// as nice ranges from 0 or across it have): each keeps its tick spacing and gets as many ticks
/// below zero as the one with most, and as many above. A negative momentum had put its axis's
/// zero above the others', where its line read as a speed above zero. Ranges without zero on a
/// tick (the overflow guard's) are left as they are. At most `maxTicks` ticks.
void alignZeros(std::initializer_list<AxisRange *> ranges, int maxTicks)
{
    struct Steps {
        AxisRange *range;
        double step;
    };
    std::vector<Steps> steps;
    int below = 0;
    int above = 0;
    for (AxisRange *r : ranges) {
        if (r->ticks < 2 || !(r->min <= 0.0) || !(r->max >= 0.0))
            continue;
        const double step = (r->max - r->min) / (r->ticks - 1);
        const double under = -r->min / step;
        const double over = r->max / step;
        if (!(step > 0.0) || std::abs(under - std::round(under)) > 1e-6 || std::abs(over - std::round(over)) > 1e-6)
            continue;
        steps.push_back({r, step});
        below = std::max(below, static_cast<int>(std::round(under)));
        above = std::max(above, static_cast<int>(std::round(over)));
    }
    if (below == 0 || steps.size() < 2)
        return;
    // No more ticks than the axes had (each, kAxisTicks and the one or two nice numbers add):
    // nine, from -4 to 10, were too close for the dock's plot, whose every label then read "…".
    // Fewer are had by doubling every spacing (1, 2, 5 become 2, 4, 10), keeping zero on a tick.
    while (below + above + 1 > maxTicks) {
        below = 0;
        above = 0;
        for (Steps &s : steps) {
            s.step *= 2.0;
            below = std::max(below, static_cast<int>(std::ceil(-s.range->min / s.step - 1e-9)));
            above = std::max(above, static_cast<int>(std::ceil(s.range->max / s.step - 1e-9)));
        }
    }
    for (const Steps &s : steps)
        *s.range = {-below * s.step, above * s.step, below + above + 1};
}

/// At most `maxTicks` ticks on `range` (Qt's nice numbers may add one or two to those asked for: four
/// labels of "…" on a short chart, speeds alone shown): its spacing doubled until they fit, its
/// minimum kept (zero, on a tick). Ranges with too few ticks to have a spacing are left alone.
AxisRange atMostTicks(AxisRange range, int maxTicks)
{
    if (range.ticks < 2 || range.ticks <= maxTicks || maxTicks < 2)
        return range;
    double step = (range.max - range.min) / (range.ticks - 1);
    int ticks = range.ticks;
    while (ticks > maxTicks && std::isfinite(step * 2.0)) {
        step *= 2.0;
        ticks = static_cast<int>(std::ceil((range.max - range.min) / step - 1e-9)) + 1;
    }
    return {range.min, range.min + (ticks - 1) * step, ticks};
}

/// Frames are whole numbers: where the nice range would put ticks less than a frame apart (the
/// first few frames of a run), the range is widened to whole frames with a tick at each.
AxisRange wholeTicks(AxisRange range)
{
    if (range.ticks < 2 || (range.max - range.min) / (range.ticks - 1) >= 1.0)
        return range;
    const double lo = std::floor(range.min);
    const double hi = std::max(std::ceil(range.max), lo + 1.0);
    return {lo, hi, static_cast<int>(hi - lo) + 1};
}

/// Gives `axis` `range`, touching only what differs.
void applyRange(QValueAxis *axis, const AxisRange &range)
{
    if (axis->min() != range.min || axis->max() != range.max)
        axis->setRange(range.min, range.max);
    if (axis->tickCount() != range.ticks)
        axis->setTickCount(range.ticks);
    // Plain numbers by the readout's rule (readableNumber(), "%.6g" giving six digits): the
    // energy in seconds read "1.5e+06". (With the chart's numbers in the desktop's language, Qt
    // Charts writes no label for a format without its precision: "%g" left the axis blank.)
    const double size = std::max(std::abs(range.min), std::abs(range.max));
    const QString format = writtenWhole(size) ? QStringLiteral("%.0f") : QStringLiteral("%.6g");
    if (axis->labelFormat() != format)
        axis->setLabelFormat(format);
}

/// Which ticks of a labelled axis have a label.
enum class Labels { All, NotBelowZero };

/// Gives `axis` `range`, as applyRange() does, with labels of our own at its ticks, a tick within
/// rounding of zero reading "0": Qt Charts works its ticks out as min + k (max - min) / (ticks - 1),
/// and the momentum's axis of a blow-up (-1e108 to 1.5e108) read "1.3037e+92" on its zero line.
/// A quantity that is never negative (a speed, an energy) gets no label below zero (Labels::
/// NotBelowZero): aligned with the momentum's zero line (alignZeros()) its axis reaches below
/// zero, where "speed -2" read as a speed there could be.
void applyLabelledRange(QCategoryAxis *axis, const AxisRange &range, Labels which)
{
    applyRange(axis, range);
    QStringList labels;
    QList<double> ends;
    const double step = range.ticks > 1 ? (range.max - range.min) / (range.ticks - 1) : 0.0;
    QString blank;
    for (int k = 0; k < std::max(range.ticks, 1); ++k) {
        // Where Qt Charts puts tick k (min + k * spacing); a tick within rounding of zero is zero.
        double at = range.min + k * step;
        if (std::abs(at) <= 1e-9 * step)
            at = 0.0;
        QString label;
        if (at < 0.0 && which == Labels::NotBelowZero) {
            blank += QLatin1Char(' '); // category labels must differ: " ", "  ", ...
            label = blank;
        } else {
            // The format's numbers, in the desktop's language (see shownNumber()).
            label = axis->labelFormat() == QLatin1String("%.0f") ? shownNumber(at, 'f', 0) : shownNumber(at, 'g', 6);
        }
        while (labels.contains(label)) // "%.6g" can write two huge ticks alike
            label += QLatin1Char(' ');
        labels << label;
        ends << at;
    }
    bool same = axis->categoriesLabels() == labels && axis->startValue() == range.min;
    for (qsizetype k = 0; same && k < labels.size(); ++k)
        same = axis->endValue(labels[k]) == ends[k];
    if (same)
        return;
    for (const QString &old : axis->categoriesLabels())
        axis->remove(old);
    axis->setStartValue(range.min);
    for (qsizetype k = 0; k < labels.size(); ++k)
        axis->append(labels[k], ends[k]);
}

// The model's name as the legend gives it ("book (solid)").
QString modelLabel(const World &world)
{
    const std::string_view model = modelName(world.params.model);
    return QString::fromUtf8(model.data(), static_cast<qsizetype>(model.size()));
}

} // namespace

PlotDock::PlotDock(QWidget *parent)
    : QDockWidget(tr("Plot"), parent)
    , m_frames(kDefaultCapacity)
    , m_kinetic(kDefaultCapacity)
    , m_momentum{RingBuffer<double>(kDefaultCapacity), RingBuffer<double>(kDefaultCapacity)}
    , m_compareKinetic(kDefaultCapacity)
    , m_compareMomentum{RingBuffer<double>(kDefaultCapacity), RingBuffer<double>(kDefaultCapacity)}
{
    setObjectName(QStringLiteral("plotDock"));

    auto *page = new QWidget(this);
    auto *column = new QVBoxLayout(page);
    column->setContentsMargins(4, 4, 4, 4);
    column->setSpacing(4);

    auto *controls = new QHBoxLayout;
    m_frameAxis = new QRadioButton(tr("Fr&ames"), page);
    m_frameAxis->setObjectName(QStringLiteral("frameAxisButton"));
    m_frameAxis->setToolTip(tr("Horizontal axis in frames, the physics' own unit of time"));
    m_secondAxis = new QRadioButton(tr("Se&conds"), page);
    m_secondAxis->setObjectName(QStringLiteral("secondAxisButton"));
    m_secondAxis->setToolTip(tr("Horizontal axis in seconds: t = frame \u00d7 frame interval / 1000; speeds in px/s"));
    m_frameAxis->setChecked(true);
    m_showKinetic = new QCheckBox(tr("&Kinetic energy"), page);
    m_showKinetic->setObjectName(QStringLiteral("kineticCheck"));
    m_showKinetic->setToolTip(tr("Total kinetic energy, \u03a3 m v\u00b2 / 2 (its own axis, on the right)"));
    m_showMomentum = new QCheckBox(tr("Momen&tum"), page);
    m_showMomentum->setObjectName(QStringLiteral("momentumCheck"));
    m_showMomentum->setToolTip(tr("The total momentum \u03a3 m v, its x and y components (their own axis, on the right).\n"
                                  "Walls, pins, friction, gravity and pushes change it in every model; hits between marbles keep it\n"
                                  "in the exact and impulse models, not in the book's."));
    auto *csvButton = new QPushButton(tr("CSV\u2026"), page);
    csvButton->setObjectName(QStringLiteral("exportCsvButton"));
    csvButton->setToolTip(tr("Export the samples as CSV: frame, time, each marble's speed, kinetic energy, momentum"));
    auto *pngButton = new QPushButton(tr("PNG\u2026"), page);
    pngButton->setObjectName(QStringLiteral("exportPngButton"));
    pngButton->setToolTip(tr("Save the chart as a PNG image"));
    controls->addWidget(m_frameAxis);
    controls->addWidget(m_secondAxis);
    controls->addSpacing(8);
    controls->addWidget(m_showKinetic);
    controls->addWidget(m_showMomentum);
    controls->addStretch(1);
    controls->addWidget(csvButton);
    controls->addWidget(pngButton);
    column->addLayout(controls);

    m_chart = new QChart;
    m_chart->setAnimationOptions(QChart::NoAnimation);
    m_chart->legend()->setAlignment(Qt::AlignBottom);
    // Legend entries drawn as short lines in each series' pen, so a dashed line reads as dashed.
    m_chart->legend()->setMarkerShape(QLegend::MarkerShapeFromSeries);
    m_chart->layout()->setContentsMargins(0, 0, 0, 0);
    m_chart->setBackgroundRoundness(0);
    // The time axis's numbers in the desktop's language, as the other axes' and the readout's.
    m_chart->setLocale(shownLocale());
    m_chart->setLocalizeNumbers(true);

    m_axisX = new QValueAxis(m_chart);
    m_axisX->setLabelFormat(QStringLiteral("%.6g"));
    m_axisSpeed = new QCategoryAxis(m_chart);
    m_axisSpeed->setLabelFormat(QStringLiteral("%.6g"));
    m_axisSpeed->setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
    m_rangeScratch = new QValueAxis(this); // never added to the chart (niceRange())
    m_chart->addAxis(m_axisX, Qt::AlignBottom);
    m_chart->addAxis(m_axisSpeed, Qt::AlignLeft);
    // Energy and momentum each on an axis of its own: they differ in units and in size (on a
    // crowd the energy's 1e7 made the momentum a flat line at 0 on a shared axis).
    m_axisTotals = new QCategoryAxis(m_chart);
    m_axisTotals->setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
    m_axisMomentum = new QCategoryAxis(m_chart);
    m_axisMomentum->setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
    for (QCategoryAxis *axis : {m_axisTotals, m_axisMomentum}) {
        axis->setLabelFormat(QStringLiteral("%.6g"));
        // Its ticks fall elsewhere than the speed axis's: two sets of grid lines read as a double grid.
        axis->setGridLineVisible(false);
        axis->setVisible(false);
        m_chart->addAxis(axis, Qt::AlignRight);
    }
    m_axisTotals->setTitleText(tr("kinetic energy"));
    m_axisMomentum->setTitleText(tr("momentum"));
    // In its lines' navy: three axes side by side, and a line at the height of a label of another
    // axis read as that value (a momentum of 100 beside an energy of 200 at the same height).
    m_axisMomentum->setLabelsColor(kMomentumColour);
    m_axisMomentum->setTitleBrush(kMomentumColour);
    // A category axis leaves no room above the chart for its top label, which a value axis does:
    // each axis's top label would run off the chart by half its height.
    m_chart->setMargins(QMargins(2, 2 + QFontMetrics(m_axisSpeed->labelsFont()).height() / 2, 2, 2));
    updateTotalsAxis();

    remakeOverlays(); // the totals, hidden until their boxes are ticked

    m_chartView = new QChartView(m_chart, page);
    m_chartView->setObjectName(QStringLiteral("plotChartView"));
    m_chartView->setAccessibleName(tr("Plot of the speeds over time"));
    // No keys work the chart: Tab stopped on it with nothing marked (a helper's finding).
    m_chartView->setFocusPolicy(Qt::NoFocus);
    m_chartView->setRenderHint(QPainter::Antialiasing);
    m_chartView->setMinimumSize(240, kMinimumChartHeight);
    m_chartView->installEventFilter(this);
    // The readout follows the pointer to the nearest line within kHoverReach px: Qt's own
    // hovered() signal fired only with the pointer on a line's 2 px pen.
    m_chartView->setMouseTracking(true);
    m_chartView->viewport()->installEventFilter(this);
    column->addWidget(m_chartView, 1);

    m_hoverLabel = new ElidingLabel(page);
    m_hoverLabel->setObjectName(QStringLiteral("hoverLabel"));
    m_hoverLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);
    // Its text is cut to the room it has: a readout naming seven lines, as long as the window
    // was wide, made the window wider than the screen (a regression tester's finding: the docks
    // went off its right edge, and stayed there).
    m_hoverLabel->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
    m_capNote = new QLabel(page);
    m_capNote->setObjectName(QStringLiteral("capNote"));
    setQuietText(m_capNote);
    auto *footer = new QHBoxLayout;
    footer->addWidget(m_hoverLabel, 1);
    footer->addWidget(m_capNote);
    column->addLayout(footer);
    setWidget(page);

    updateAxisTitles();

    m_refreshTimer = new QTimer(this);
    m_refreshTimer->setInterval(kRefreshIntervalMs);
    connect(m_refreshTimer, &QTimer::timeout, this, [this] {
        // Only when something changed, and only while someone can see it.
        if (m_dirty && isVisible())
            refreshChart();
    });
    m_refreshTimer->start();

    connect(m_showKinetic, &QCheckBox::toggled, this, &PlotDock::setKineticEnergyShown);
    connect(m_showMomentum, &QCheckBox::toggled, this, &PlotDock::setMomentumShown);
    connect(m_secondAxis, &QRadioButton::toggled, this, &PlotDock::setTimeInSeconds);
    connect(csvButton, &QPushButton::clicked, this, &PlotDock::exportCsvInteractive);
    connect(pngButton, &QPushButton::clicked, this, &PlotDock::exportPngInteractive);
}

template<typename Apply>
void PlotDock::forEachValueBuffer(Apply &&apply)
{
    apply(m_kinetic);
    apply(m_compareKinetic);
    for (int c : {0, 1}) {
        apply(m_momentum[c]);
        apply(m_compareMomentum[c]);
    }
    for (std::vector<Track> *tracks : {&m_tracks, &m_parked}) {
        for (Track &t : *tracks) {
            apply(t.speed);
            apply(t.compareSpeed);
        }
    }
}

void PlotDock::reset(const World &world)
{
    m_frames.clear();
    m_compareRestarts.clear();
    m_editMarks.clear();
    m_massesFrom.clear();
    forEachValueBuffer([](RingBuffer<double> &values) { values.clear(); });

    m_marbleCount = world.marbleCount();
    m_colors.assign(world.info.size(), QString());
    m_names.assign(world.info.size(), QString());
    for (std::size_t i = 0; i < world.info.size(); ++i) {
        m_colors[i] = QString::fromStdString(world.info[i].color);
        m_names[i] = QString::fromStdString(world.info[i].name);
    }
    m_frameMs = world.params.frameMs;
    m_models = QStringList{modelLabel(world)};
    m_parked.clear(); // another scene's marbles
    rebuildTracks();
    m_hoverLabel->setFullText(QString());
    m_dirty = true;
}

void PlotDock::startAt(const World &world, const World *compare)
{
    replayKeptFrames(world, compare, world.frame); // no frame before it
}

void PlotDock::replayKeptFrames(const World &world, const World *compare, std::int64_t firstFrame)
{
    // No further back than the plot holds. (Further back than the lines went: an add undone
    // gives back the frames before it, where the lines had started again.)
    // The edits' marks on the frames drawn again stay: a marble deleted mid-run, or Step Back
    // past the plot's oldest sample, had taken away the mark of a velocity set before, the jump
    // still in the line (a helper's finding).
    std::vector<EditMark> marks = std::move(m_editMarks);
    const std::vector<MassesFrom> masses = std::move(m_massesFrom);
    reset(world);
    const std::int64_t from = std::max(firstFrame, world.frame - static_cast<std::int64_t>(capacity()) + 1);
    if (m_documentVelocities && from < world.frame) {
        // The marbles of now, with the velocities of each kept frame (what Step Back returns to)
        // and the masses it was taken with where they are known.
        World ours = world;
        std::optional<World> theirs;
        if (compare)
            theirs = *compare;
        const std::vector<double> *massesTaken = &world.mass; // what ours.mass holds
        for (std::int64_t f = from; f < world.frame; ++f) {
            const std::vector<Vec2> *velocities = m_documentVelocities(f);
            if (!velocities || velocities->size() != ours.velocity.size())
                continue;
            ours.velocity = *velocities;
            ours.frame = f;
            const std::vector<double> *mass = massesAt(masses, f, world.marbleCount());
            if (!mass)
                mass = &world.mass;
            if (mass != massesTaken) { // a copy only where they change (a crowd's replay is O(frames x marbles))
                ours.mass = *mass;
                massesTaken = mass;
            }
            const std::vector<Vec2> *compared = theirs && m_compareVelocities ? m_compareVelocities(f) : nullptr;
            if (compared && compared->size() == theirs->velocity.size()) {
                theirs->velocity = *compared;
                theirs->frame = f;
                if (theirs->mass.size() == ours.mass.size())
                    theirs->mass = ours.mass;
            } else {
                compared = nullptr;
            }
            appendFrame(ours, compared ? &*theirs : nullptr);
        }
    }
    appendFrame(world, compare);
    // The masses the frames were taken with are those they had: rebuilt from the frames, two
    // entries that differ only in a marble removed would have become one, and its undo could not
    // give each its own mass back.
    m_massesFrom = masses;
    noteMasses(world);
    std::erase_if(marks, [this](const EditMark &m) { return m.frame <= m_frames.at(0) || m.frame > m_frames.last(); });
    m_editMarks = std::move(marks);
}

void PlotDock::resample(const World &world, const World *compare)
{
    std::optional<SceneSample> before;
    if (!m_frames.isEmpty() && m_frames.last() == world.frame) {
        before = newestSceneSample();
        m_frames.dropNewest(1);
        forEachValueBuffer([](RingBuffer<double> &values) { values.dropNewest(1); });
    }
    appendFrame(world, compare);
    // Where the scene's lines now jump (from a sample before this one), the edit is marked; an
    // edit undone there, which gives the frame its values as stepped again, is not.
    if (before && m_frames.size() > 1) {
        const SceneSample now = newestSceneSample();
        const auto mark = std::find_if(m_editMarks.begin(), m_editMarks.end(),
                                       [&world](const EditMark &m) { return m.frame == world.frame; });
        if (mark != m_editMarks.end()) {
            if (now.sameAs(mark->asStepped))
                m_editMarks.erase(mark);
        } else if (!now.sameAs(*before)) {
            m_editMarks.push_back({world.frame, std::move(*before)});
        }
    }
    const QString model = modelLabel(world);
    if (model != m_models.last()) {
        // The lines before this frame are still the last model's (none but this frame: no line yet).
        if (m_frames.size() <= 1)
            m_models.clear();
        m_models.append(model);
        styleSeries();
    }
    m_hoverLabel->setFullText(QString());
}

void PlotDock::markCompareRestart(std::int64_t frame)
{
    // Only where a dashed line before it jumps: not at the comparison's start, nor where Step
    // Back went before that start (a mark had appeared there, and not at the start itself).
    const auto comparedBefore = [this, frame] {
        for (std::size_t k = m_frames.size(); k-- > 0;) {
            if (m_frames.at(k) < frame && k < m_compareKinetic.size() && !std::isnan(m_compareKinetic.at(k)))
                return true;
        }
        return false;
    };
    if (m_compareModel.isEmpty() || !comparedBefore())
        return;
    if (!m_compareRestarts.empty() && m_compareRestarts.back() + 1 >= frame)
        m_compareRestarts.back() = frame;
    else
        m_compareRestarts.push_back(frame);
    m_dirty = true;
}

void PlotDock::unmarkCompareRestart(std::int64_t frame)
{
    if (std::erase(m_compareRestarts, frame) > 0)
        m_dirty = true;
}

std::vector<std::int64_t> PlotDock::editMarks() const
{
    std::vector<std::int64_t> frames;
    for (const EditMark &m : m_editMarks)
        frames.push_back(m.frame);
    return frames;
}

PlotDock::SceneSample PlotDock::newestSceneSample() const
{
    SceneSample sample;
    sample.kinetic = m_kinetic.last();
    sample.momentum = {m_momentum[0].last(), m_momentum[1].last()};
    for (const std::vector<Track> *tracks : {&m_tracks, &m_parked}) {
        for (const Track &t : *tracks) {
            sample.speeds.emplace_back(t.marble, t.speed.last());
            if (t.compareSpeed.size() > 0)
                sample.compareSpeeds.emplace_back(t.marble, t.compareSpeed.last());
        }
    }
    if (m_compareKinetic.size() > 0) {
        sample.compareKinetic = m_compareKinetic.last();
        sample.compareMomentum = {m_compareMomentum[0].last(), m_compareMomentum[1].last()};
    }
    return sample;
}

bool PlotDock::SceneSample::sameAs(const SceneSample &other) const
{
    if (!sameBits(kinetic, other.kinetic) || !sameBits(momentum, other.momentum))
        return false;
    for (const auto &[marble, speed] : speeds) {
        for (const auto &[otherMarble, otherSpeed] : other.speeds) {
            if (marble == otherMarble && !sameBits(speed, otherSpeed))
                return false;
        }
    }
    return true;
}

void PlotDock::cutAfter(std::int64_t frame)
{
    std::erase_if(m_compareRestarts, [frame](std::int64_t restart) { return restart > frame; });
    std::erase_if(m_editMarks, [frame](const EditMark &m) { return m.frame > frame; });
    // Frames grow along the buffer: the samples to forget are the newest ones.
    std::size_t later = 0;
    while (later < m_frames.size() && m_frames.at(m_frames.size() - 1 - later) > frame)
        ++later;
    if (later == 0)
        return;
    m_frames.dropNewest(later);
    forEachValueBuffer([later](RingBuffer<double> &values) { values.dropNewest(later); });
    if (m_frames.size() <= 1 && m_models.size() > 1) {
        // Back to where no line is left: the model now is the only one to name.
        m_models = QStringList{m_models.last()};
        styleSeries();
    }
    m_hoverLabel->setFullText(QString());
    m_dirty = true;
}

void PlotDock::appendFrame(const World &world, const World *compare)
{
    if (world.marbleCount() != m_marbleCount) {
        // Marbles were added or removed without a reset(): follow the new count; the colours and
        // names of new marbles come from the world (a rare, structural event: O(marbles) is fine).
        m_marbleCount = world.marbleCount();
        m_colors.resize(world.info.size());
        m_names.resize(world.info.size());
        for (std::size_t i = 0; i < world.info.size(); ++i) {
            m_colors[i] = QString::fromStdString(world.info[i].color);
            m_names[i] = QString::fromStdString(world.info[i].name);
        }
        rebuildTracks();
    }
    m_frameMs = world.params.frameMs;
    m_frames.push(world.frame);
    noteMasses(world);
    m_kinetic.push(world.kineticEnergy());
    const Vec2 p = world.momentum();
    m_momentum[0].push(p.x);
    m_momentum[1].push(p.y);
    for (std::vector<Track> *tracks : {&m_tracks, &m_parked}) {
        for (Track &t : *tracks) {
            const auto i = static_cast<std::size_t>(t.marble);
            t.speed.push(i < world.velocity.size() ? magnitude(world.velocity[i]) : kNaN);
            if (!m_compareModel.isEmpty())
                t.compareSpeed.push(compare && i < compare->velocity.size() ? magnitude(compare->velocity[i]) : kNaN);
        }
    }
    if (!m_compareModel.isEmpty()) {
        m_compareKinetic.push(compare ? compare->kineticEnergy() : kNaN);
        const Vec2 q = compare ? compare->momentum() : Vec2{kNaN, kNaN};
        m_compareMomentum[0].push(q.x);
        m_compareMomentum[1].push(q.y);
    }
    m_dirty = true;
}

void PlotDock::setSelectedMarbles(const QList<int> &indices)
{
    QList<int> unique;
    for (int i : indices) {
        if (i >= 0 && !unique.contains(i))
            unique.append(i);
    }
    if (unique == m_selected)
        return;
    m_selected = unique;
    rebuildTracks();
    m_dirty = true;
}

qsizetype PlotDock::sampleCount() const
{
    return static_cast<qsizetype>(m_frames.size());
}

qsizetype PlotDock::capacity() const
{
    return static_cast<qsizetype>(m_capacity);
}

void PlotDock::setCapacity(qsizetype samples)
{
    m_capacity = static_cast<std::size_t>(std::max<qsizetype>(samples, 1));
    m_frames.setCapacity(m_capacity);
    forEachValueBuffer([this](RingBuffer<double> &values) { values.setCapacity(m_capacity); });
    m_dirty = true;
}

QList<int> PlotDock::plottedMarbles() const
{
    QList<int> out;
    for (const Track &t : m_tracks)
        out.append(t.marble);
    return out;
}

std::int64_t PlotDock::sampleFrame(qsizetype i) const
{
    return m_frames.at(static_cast<std::size_t>(i));
}

double PlotDock::sampleSpeed(qsizetype i, int marble) const
{
    const Track *t = trackOf(marble);
    return t ? t->speed.at(static_cast<std::size_t>(i)) : kNaN;
}

double PlotDock::sampleCompareSpeed(qsizetype i, int marble) const
{
    const Track *t = trackOf(marble);
    return t && t->compareSeries ? t->compareSpeed.at(static_cast<std::size_t>(i)) : kNaN;
}

QLineSeries *PlotDock::compareSeries(int marble) const
{
    const Track *t = trackOf(marble);
    return t ? t->compareSeries : nullptr;
}

double PlotDock::sampleCompareKineticEnergy(qsizetype i) const
{
    return m_compareKineticSeries ? m_compareKinetic.at(static_cast<std::size_t>(i)) : kNaN;
}

Vec2 PlotDock::sampleCompareMomentum(qsizetype i) const
{
    if (!m_compareMomentumSeries[0])
        return {kNaN, kNaN};
    return {m_compareMomentum[0].at(static_cast<std::size_t>(i)), m_compareMomentum[1].at(static_cast<std::size_t>(i))};
}

void PlotDock::setCompareModel(const QString &model)
{
    if (model == m_compareModel)
        return;
    for (Track &t : m_tracks)
        removeCompareTrack(t);
    for (Track &t : m_parked)
        t.compareSpeed.clear();
    m_compareKinetic.clear();
    for (int c : {0, 1})
        m_compareMomentum[c].clear();
    m_compareRestarts.clear();
    m_compareModel = model;
    if (!m_compareModel.isEmpty()) {
        for (Track &t : m_tracks)
            addCompareTrack(t);
        for (Track &t : m_parked)
            startFrom(t.compareSpeed, t.marble, m_compareVelocities);
        // The comparison starts now: no comparison totals for the samples already held.
        startWithGaps(m_compareKinetic);
        for (int c : {0, 1})
            startWithGaps(m_compareMomentum[c]);
    }
    remakeOverlays(); // the comparison's totals, keys and restart marks, or none
}

double PlotDock::sampleKineticEnergy(qsizetype i) const
{
    return m_kinetic.at(static_cast<std::size_t>(i));
}

Vec2 PlotDock::sampleMomentum(qsizetype i) const
{
    return {m_momentum[0].at(static_cast<std::size_t>(i)), m_momentum[1].at(static_cast<std::size_t>(i))};
}

bool PlotDock::isKineticEnergyShown() const
{
    return m_showKinetic->isChecked();
}

bool PlotDock::isMomentumShown() const
{
    return m_showMomentum->isChecked();
}

double PlotDock::secondsAt(std::int64_t frame) const
{
    return static_cast<double>(frame) * m_frameMs / 1000.0;
}

void PlotDock::setKineticEnergyShown(bool shown)
{
    if (m_showKinetic->isChecked() != shown)
        m_showKinetic->setChecked(shown); // comes back here through toggled()
    showTotal(m_kineticSeries, shown);
    showTotal(m_compareKineticSeries, shown);
    updateTotalsAxis();
    m_dirty = true;
    emit choicesChanged();
}

void PlotDock::setMomentumShown(bool shown)
{
    if (m_showMomentum->isChecked() != shown)
        m_showMomentum->setChecked(shown);
    for (int c : {0, 1}) {
        showTotal(m_momentumSeries[c], shown);
        showTotal(m_compareMomentumSeries[c], shown);
    }
    updateTotalsAxis();
    m_dirty = true;
    emit choicesChanged();
}

void PlotDock::setTimeInSeconds(bool seconds)
{
    if (m_secondAxis->isChecked() != seconds)
        (seconds ? m_secondAxis : m_frameAxis)->setChecked(true);
    m_timeInSeconds = seconds;
    updateAxisTitles();
    m_dirty = true;
    emit choicesChanged();
}

bool PlotDock::isTimeInSeconds() const
{
    return m_timeInSeconds;
}

void PlotDock::refreshChart()
{
    const auto n = static_cast<qsizetype>(m_frames.size());
    auto x = [this](qsizetype i) { return xOf(m_frames.at(static_cast<std::size_t>(i))); };
    const qsizetype maxPoints = pointsPerLine();

    double speedMin = std::numeric_limits<double>::infinity();
    double speedMax = -std::numeric_limits<double>::infinity();
    // Held in px/frame; drawn per second when the time axis is in seconds (speed x f, momentum
    // x f, energy x f^2), so that a line's slope and its axis are in the same time unit.
    const double f = perSecond();
    // Lines in runs: the earlier runs are lines of their own, added to the chart after the rest.
    bool runsAdded = false;
    for (Track &t : m_tracks) {
        std::vector<QList<QPointF>> runs = thinnedRuns(
            n, maxPoints, x, [&t, f](qsizetype i) { return t.speed.at(static_cast<std::size_t>(i)) * f; }, speedMin,
            speedMax);
        const auto speedIn = [&t, f](const std::vector<std::pair<int, double>> &speeds) -> std::optional<double> {
            for (const auto &[marble, speed] : speeds) {
                if (marble == t.marble)
                    return speed * f;
            }
            return std::nullopt;
        };
        runsAdded |= drawRuns(
            t.series, std::move(runs), [&speedIn](const SceneSample &s) { return speedIn(s.speeds); }, speedMin,
            speedMax);
        if (t.compareSeries) {
            runsAdded |= drawRuns(t.compareSeries,
                     thinnedRuns(
                         n, maxPoints, x,
                         [&t, f](qsizetype i) { return t.compareSpeed.at(static_cast<std::size_t>(i)) * f; },
                         speedMin, speedMax),
                     [&speedIn](const SceneSample &s) { return speedIn(s.compareSpeeds); }, speedMin, speedMax);
        }
    }
    // The totals and the marks are drawn over the speed lines: after them on the chart.
    if (runsAdded)
        remakeOverlays();

    struct Extent {
        double min = std::numeric_limits<double>::infinity();
        double max = -std::numeric_limits<double>::infinity();
    } energy, momentum;
    // asStepped: the line's value as stepped, for its jumps at edits (addEditJumps()).
    auto refreshTotal = [&](QLineSeries *series, const RingBuffer<double> &values, bool shown, double scale,
                            Extent &extent, const SampleValue &asStepped) {
        std::vector<QList<QPointF>> runs;
        if (shown) {
            runs = thinnedRuns(
                n, maxPoints, x,
                [&values, scale](qsizetype i) { return values.at(static_cast<std::size_t>(i)) * scale; }, extent.min,
                extent.max);
        }
        drawRuns(series, std::move(runs), asStepped, extent.min, extent.max);
    };
    refreshTotal(m_kineticSeries, m_kinetic, m_showKinetic->isChecked(), f * f, energy,
                 [f](const SceneSample &s) { return std::optional<double>(s.kinetic * f * f); });
    if (m_compareKineticSeries)
        refreshTotal(m_compareKineticSeries, m_compareKinetic, m_showKinetic->isChecked(), f * f, energy,
                     [f](const SceneSample &s) { return std::optional<double>(s.compareKinetic * f * f); });
    for (int c : {0, 1}) {
        refreshTotal(m_momentumSeries[c], m_momentum[c], m_showMomentum->isChecked(), f, momentum,
                     [c, f](const SceneSample &s) { return std::optional<double>((c == 0 ? s.momentum.x : s.momentum.y) * f); });
        if (m_compareMomentumSeries[c])
            refreshTotal(m_compareMomentumSeries[c], m_compareMomentum[c], m_showMomentum->isChecked(), f, momentum,
                         [c, f](const SceneSample &s) {
                             return std::optional<double>((c == 0 ? s.compareMomentum.x : s.compareMomentum.y) * f);
                         });
    }

    // Speeds and the energy are never negative: their axes start at zero. The momentum's
    // components may be: its axis takes in zero and both signs where they occur.
    // A mark at the newest frame would lie on the chart's right edge, where the frame hides it:
    // the axis then reaches a frame further (to its next round number).
    const bool markAtEnd = n > 0
        && ((!m_editMarks.empty() && m_editMarks.back().frame >= m_frames.last())
            || (m_restartMarks && !m_compareRestarts.empty() && m_compareRestarts.back() >= m_frames.last()));
    const double end = n > 0 ? (markAtEnd ? xOf(m_frames.last() + 1) : x(n - 1)) : 0.0;
    const AxisRange time = n > 0 ? niceRange(m_rangeScratch, x(0), end) : niceRange(m_rangeScratch, 0.0, xOf(100));
    applyRange(m_axisX, m_timeInSeconds ? time : wholeTicks(time));
    // A little room above the highest point: a line at a round maximum (Newton's cradle's 6
    // px/frame) ran along the chart's top edge, where it could hardly be seen.
    const auto top = [](double max) { return std::isfinite(max) ? std::max(max, 0.0) * 1.04 : 1.0; };
    const auto bottom = [](double min) { return std::isfinite(min) ? std::min(min, 0.0) * 1.04 : 0.0; };
    updateAxisTitles();
    // As many ticks up the chart as its height has room for, each label a line and as much
    // again apart: at a scale of 1.5 on a 1280 x 720 projector the plot is about 100 px high,
    // and Qt cut each of six labels that had less than a line to "…" (a helper's finding).
    const double plotHeight = m_chart->plotArea().height();
    const int lineHeight = QFontMetrics(m_axisSpeed->labelsFont()).height();
    const int valueTicks = plotHeight > 0.0 && lineHeight > 0
        ? std::clamp(static_cast<int>(plotHeight / (2.0 * lineHeight)) + 1, 2, kAxisTicks)
        : kAxisTicks;
    // On a short chart, no more ticks than asked for (the nice numbers' extra ones read "…").
    const int tickRoom = valueTicks == kAxisTicks ? std::numeric_limits<int>::max() : valueTicks;
    AxisRange speedRange = atMostTicks(niceRange(m_rangeScratch, 0.0, top(speedMax), valueTicks), tickRoom);
    AxisRange energyRange = atMostTicks(niceRange(m_rangeScratch, 0.0, top(energy.max), valueTicks), tickRoom);
    AxisRange momentumRange = niceRange(m_rangeScratch, bottom(momentum.min), top(momentum.max), valueTicks);
    // One zero line for every axis drawn.
    if (m_showMomentum->isChecked())
        alignZeros(m_showKinetic->isChecked() ? std::initializer_list<AxisRange *>{&speedRange, &energyRange, &momentumRange}
                                              : std::initializer_list<AxisRange *>{&speedRange, &momentumRange},
                   // one more than asked where there is room (the nice numbers' own), none on a short chart
                   valueTicks == kAxisTicks ? kAxisTicks + 1 : valueTicks);
    applyLabelledRange(m_axisSpeed, speedRange, Labels::NotBelowZero);
    applyLabelledRange(m_axisTotals, energyRange, Labels::NotBelowZero);
    applyLabelledRange(m_axisMomentum, momentumRange, Labels::All);
    // A dotted line, down and up, at each comparison restart, and a dash-dot one at each edit
    // that made the lines jump (from the frames the plot still holds): the joins along the time
    // axis vanish.
    const double markTop = m_axisSpeed->max();
    const auto markAt = [this, markTop](QList<QPointF> &marks, std::int64_t frame) {
        marks << QPointF(xOf(frame), 0.0) << QPointF(xOf(frame), markTop) << QPointF(xOf(frame), 0.0);
    };
    if (m_editMarkSeries) {
        QList<QPointF> marks;
        for (const EditMark &m : m_editMarks) {
            if (n > 0 && m.frame >= m_frames.at(0))
                markAt(marks, m.frame);
        }
        m_editMarkSeries->replace(marks);
    }
    if (m_restartMarks) {
        QList<QPointF> marks;
        for (const std::int64_t restart : m_compareRestarts)
            markAt(marks, restart);
        m_restartMarks->replace(marks);
    }
    // Their keys, while they have marks and the row has room for them; whether any key came or
    // went.
    const auto showKeys = [this] {
        bool changed = false;
        const auto show = [&](QLineSeries *series, bool shown) { changed = showKey(series, shown) || changed; };
        for (QLineSeries *series : {m_restartMarks, m_editMarkSeries})
            show(series, series && series->count() > 0 && !m_markKeysHidden);
        return changed;
    };
    if (showKeys()) {
        // A key takes room in the row: the labels are measured again, which may leave no room
        // for the keys after all.
        updateLegendLabels();
        showKeys();
        // Qt Charts 6.4 draws a marker shown afterwards over its neighbour ("mediumparison
        // restarted", a regression tester's finding) until the legend is laid out again.
        m_chart->legend()->hide();
        m_chart->legend()->show();
    }
    m_dirty = false;
}

QChartView *PlotDock::chartView() const
{
    return m_chartView;
}

QLineSeries *PlotDock::speedSeries(int marble) const
{
    const Track *t = trackOf(marble);
    return t ? t->series : nullptr;
}

std::size_t PlotDock::nearestSample(double x) const
{
    // The sample whose frame is nearest to x (in the time axis' units): frames grow along the buffer.
    const double frame = m_timeInSeconds && m_frameMs > 0.0 ? x * 1000.0 / m_frameMs : x;
    std::size_t lo = 0;
    std::size_t hi = m_frames.size() - 1;
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (static_cast<double>(m_frames.at(mid)) < frame)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo > 0 && std::abs(static_cast<double>(m_frames.at(lo - 1)) - frame) <=
                      std::abs(static_cast<double>(m_frames.at(lo)) - frame))
        --lo;
    return lo;
}

std::optional<PlotDock::PlottedValue> PlotDock::plottedValue(const QLineSeries *series, std::size_t sample) const
{
    // In the units drawn (refreshChart()).
    const double perS = perSecond();
    // The totals with their units (switched to seconds, the energy went from 1500 to 4e+06 with
    // nothing to say why; the axis titles have no room for them).
    const QString energyUnit = this->energyUnit();
    const QString momentumUnit = this->momentumUnit();
    // Named in full (the legend may give them short names).
    const QString compared = QStringLiteral(", ") + m_compareModel;
    const struct {
        const QLineSeries *line;
        const RingBuffer<double> *values;
        double scale;
        const QString &unit;
        QString what;
    } totals[] = {
        {m_kineticSeries, &m_kinetic, perS * perS, energyUnit, totalName(0)},
        {m_momentumSeries[0], &m_momentum[0], perS, momentumUnit, totalName(1)},
        {m_momentumSeries[1], &m_momentum[1], perS, momentumUnit, totalName(2)},
        {m_compareKineticSeries, &m_compareKinetic, perS * perS, energyUnit, totalName(0) + compared},
        {m_compareMomentumSeries[0], &m_compareMomentum[0], perS, momentumUnit, totalName(1) + compared},
        {m_compareMomentumSeries[1], &m_compareMomentum[1], perS, momentumUnit, totalName(2) + compared},
    };
    for (const auto &total : totals) {
        if (total.line && total.line == series)
            return PlottedValue{total.what, total.values->at(sample) * total.scale, total.unit};
    }
    const QString unit = m_timeInSeconds ? tr("px/s") : tr("px/frame");
    for (const Track &t : m_tracks) {
        if (t.series == series)
            return PlottedValue{tr("%1, speed").arg(marbleLabel(t.marble)), t.speed.at(sample) * perS, unit};
        if (t.compareSeries && t.compareSeries == series)
            return PlottedValue{tr("%1, speed").arg(t.compareSeries->name()), t.compareSpeed.at(sample) * perS, unit};
    }
    return std::nullopt;
}

QString PlotDock::describePoint(const QLineSeries *series, QPointF point) const
{
    return describePoints({series}, point.x());
}

QString PlotDock::describePoints(const QList<const QLineSeries *> &lines, double x) const
{
    if (m_frames.isEmpty())
        return QString();
    const std::size_t sample = nearestSample(x);
    QStringList values;
    for (const QLineSeries *series : lines) {
        if (const std::optional<PlottedValue> plotted = plottedValue(series, sample))
            values << tr("%1 %2 %3").arg(plotted->what, readableNumber(plotted->value), plotted->unit);
    }
    if (values.isEmpty())
        return QString();
    const std::int64_t f = m_frames.at(sample);
    return tr("frame %1 (%2 s): %3").arg(f).arg(shownNumber(secondsAt(f), 'g', 6), values.join(QStringLiteral("; ")));
}

QList<const QLineSeries *> PlotDock::seriesNear(QPointF at) const
{
    // The visible lines passing nearest to `at` (chart coordinates), within kHoverReach px, the
    // nearest first, with those no more than a pixel further (lines drawn on top of each other: a
    // comparison that agrees with the scene's model named only one of them). A line's distance
    // is to the segments either side of the sample nearest in time.
    if (m_frames.isEmpty() || !m_chart->plotArea().contains(at))
        return {};
    std::vector<std::pair<double, const QLineSeries *>> near;
    for (QAbstractSeries *abstract : m_chart->series()) {
        const auto *series = qobject_cast<const QLineSeries *>(abstract);
        if (!series || !series->isVisible())
            continue;
        const std::size_t sample = nearestSample(m_chart->mapToValue(at, abstract).x());
        auto pointAt = [&](std::size_t k) -> std::optional<QPointF> {
            const std::optional<PlottedValue> plotted = plottedValue(series, k);
            if (!plotted || !std::isfinite(plotted->value)) // a gap: the marble was not plotted then
                return std::nullopt;
            return m_chart->mapToPosition(QPointF(xOf(m_frames.at(k)), plotted->value), abstract);
        };
        const std::optional<QPointF> here = pointAt(sample);
        if (!here)
            continue;
        double distance = QLineF(*here, at).length();
        for (const std::size_t k : {sample - 1, sample + 1}) {
            if (k >= static_cast<std::size_t>(m_frames.size()))
                continue; // also sample - 1 from 0, which wraps
            if (const std::optional<QPointF> there = pointAt(k))
                distance = std::min(distance, distanceToSegment(at, *here, *there));
        }
        if (distance <= kHoverReach)
            near.emplace_back(distance, series);
    }
    std::stable_sort(near.begin(), near.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
    QList<const QLineSeries *> out;
    for (const auto &[distance, series] : near) {
        if (distance <= near.front().first + 1.0)
            out.append(series);
    }
    return out;
}

void PlotDock::hoverAt(QPoint viewportPos)
{
    const QPointF at = m_chart->mapFromScene(m_chartView->mapToScene(viewportPos));
    const QList<const QLineSeries *> lines = seriesNear(at);
    const QString text = lines.isEmpty() ? QString() : describePoints(lines, m_chart->mapToValue(at).x());
    if (text == m_hoverLabel->fullText())
        return;
    m_hoverLabel->setFullText(text);
    if (text.isEmpty())
        QToolTip::hideText();
    else
        QToolTip::showText(m_chartView->viewport()->mapToGlobal(viewportPos), text, m_chartView);
}

QString PlotDock::hoverText() const
{
    return m_hoverLabel->fullText();
}

QString PlotDock::exportCsv(const QString &path) const
{
    // Each column names its unit as time_s does, so that a spreadsheet's reader need not guess
    // (the speeds are per frame whatever the time axis shows).
    const QByteArray speedUnit = "_px_per_frame";
    const QByteArray energyUnit = "_mass_px2_per_frame2";
    const QByteArray momentumUnit = "_mass_px_per_frame";
    QByteArray text = "frame,time_s";
    for (const Track &t : m_tracks)
        text += ",speed_" + QByteArray::number(t.marble) + speedUnit;
    text += ",kinetic_energy" + energyUnit + ",momentum_x" + momentumUnit + ",momentum_y" + momentumUnit;
    const QByteArray compareSuffix = '_' + m_compareModel.toUtf8();
    for (const Track &t : m_tracks) {
        if (t.compareSeries)
            text += ",speed_" + QByteArray::number(t.marble) + compareSuffix + speedUnit;
    }
    if (m_compareKineticSeries)
        text += ",kinetic_energy" + compareSuffix + energyUnit + ",momentum_x" + compareSuffix + momentumUnit + ",momentum_y"
                + compareSuffix + momentumUnit;
    // The plot's marks, 1 on their frame's row: a spreadsheet's line jumps there as the plot's
    // does, and said nothing of why.
    text += ",scene_edited";
    if (m_compareKineticSeries)
        text += ",comparison_restarted";
    text += '\n';
    for (std::size_t i = 0; i < m_frames.size(); ++i) {
        const std::int64_t f = m_frames.at(i);
        QString row = QString::number(f) + QLatin1Char(',') + csvNumber(secondsAt(f));
        for (const Track &t : m_tracks)
            row += QLatin1Char(',') + csvNumber(t.speed.at(i));
        row += QLatin1Char(',') + csvNumber(m_kinetic.at(i)) + QLatin1Char(',') + csvNumber(m_momentum[0].at(i))
               + QLatin1Char(',') + csvNumber(m_momentum[1].at(i));
        for (const Track &t : m_tracks) {
            if (t.compareSeries)
                row += QLatin1Char(',') + csvNumber(t.compareSpeed.at(i));
        }
        if (m_compareKineticSeries) {
            row += QLatin1Char(',') + csvNumber(m_compareKinetic.at(i)) + QLatin1Char(',')
                   + csvNumber(m_compareMomentum[0].at(i)) + QLatin1Char(',') + csvNumber(m_compareMomentum[1].at(i));
        }
        const bool edited = std::any_of(m_editMarks.begin(), m_editMarks.end(), [f](const EditMark &m) { return m.frame == f; });
        row += edited ? QStringLiteral(",1") : QStringLiteral(",0");
        if (m_compareKineticSeries) {
            const bool restarted = std::find(m_compareRestarts.begin(), m_compareRestarts.end(), f) != m_compareRestarts.end();
            row += restarted ? QStringLiteral(",1") : QStringLiteral(",0");
        }
        text += row.toLatin1() + '\n';
    }
    if (const QString failure = writeWholeFile(path, text); !failure.isEmpty())
        return tr("%1: %2").arg(path, failure);
    return QString();
}

QString PlotDock::solidModels() const
{
    return m_models.join(tr(", then "));
}

QString PlotDock::exportCaption() const
{
    QStringList parts;
    if (!m_sceneName.isEmpty())
        parts << m_sceneName;
    if (m_sceneEdited)
        parts << tr("edited");
    const QString models = solidModels();
    parts << (m_compareModel.isEmpty() ? tr("model: %1").arg(models)
                                       : tr("model: %1 (solid), %2 (dashed)").arg(models, m_compareModel));
    // A picture of twelve lines from a crowd says that the others are not on it.
    if (!m_capNote->text().isEmpty())
        parts << m_capNote->text();
    if (!m_frames.isEmpty()) {
        const std::int64_t first = m_frames.at(0);
        const std::int64_t last = m_frames.last();
        // Two decimals, or three digits where the run is shorter than a tenth of a second (frames
        // of 0.05 ms read "0.00 to 0.00 s").
        const bool brief = std::abs(secondsAt(last) - secondsAt(first)) < 0.1;
        const auto seconds = [brief](double t) {
            return brief ? shownNumber(t, 'g', 3) : shownNumber(t, 'f', 2);
        };
        parts << tr("frames %1 to %2, %3 to %4 s").arg(first).arg(last).arg(seconds(secondsAt(first)), seconds(secondsAt(last)));
    }
    return parts.join(QStringLiteral(" \u2014 "));
}

QString PlotDock::exportPng(const QString &path)
{
    if (m_dirty)
        refreshChart();
    // Drawn at least kMinPngSize: the view is made that large for the picture, less a strip at
    // the top for the caption, and given its size back at once (no event is handled in between,
    // so nothing else sees it).
    const QSize onScreen = m_chartView->size();
    const QSize size = onScreen.expandedTo(kMinPngSize);
    QFont font = m_chartView->font();
    font.setPointSizeF(font.pointSizeF() * 1.1);
    const int strip = QFontMetrics(font).height() + 12;
    const QSize chartSize(size.width(), size.height() - strip);
    // The totals' axes with their units, which the window gives in the status bar and the
    // tooltips alone: a picture in seconds did not say mass·px²/s² from mass·px²/frame² (a
    // helper's finding). The picture is tall enough for them.
    const QString energyTitle = m_axisTotals->titleText();
    const QString momentumTitle = m_axisMomentum->titleText();
    m_axisTotals->setTitleText(tr("kinetic energy (%1)").arg(energyUnit()));
    m_axisMomentum->setTitleText(tr("momentum (%1)").arg(momentumUnit()));
    m_chartView->resize(chartSize);
    const QPixmap chart = m_chartView->grab();
    m_chartView->resize(onScreen);
    m_axisTotals->setTitleText(energyTitle);
    m_axisMomentum->setTitleText(momentumTitle);
    if (chart.isNull())
        return tr("%1: the chart could not be drawn").arg(path);
    QPixmap image(size * chart.devicePixelRatio());
    image.setDevicePixelRatio(chart.devicePixelRatio());
    image.fill(Qt::white);
    {
        QPainter painter(&image);
        painter.setRenderHint(QPainter::TextAntialiasing);
        painter.setFont(font);
        painter.setPen(QColor(0x22, 0x22, 0x22));
        const QRect captionRect(10, 0, size.width() - 20, strip);
        painter.drawText(captionRect, Qt::AlignLeft | Qt::AlignVCenter | Qt::TextSingleLine,
                         QFontMetrics(font).elidedText(exportCaption(), Qt::ElideRight, captionRect.width()));
        painter.drawPixmap(0, strip, chart);
    }
    // Written whole or not at all, as the scene files are.
    QByteArray png;
    QBuffer buffer(&png);
    if (!buffer.open(QIODevice::WriteOnly) || !image.save(&buffer, "PNG"))
        return tr("%1: could not be encoded as PNG").arg(path);
    if (const QString failure = writeWholeFile(path, png); !failure.isEmpty())
        return tr("%1: %2").arg(path, failure);
    return QString();
}

void PlotDock::rebuildTracks()
{
    // The chart lists its lines in the order they were added, and the legend follows it. A line
    // kept from before (marble 3, selected a moment ago) would lead the lines added now (marbles
    // 0 to 2): every plotted marble gets a new line, in marble order, and a marble plotted before
    // keeps its samples (refreshChart() hands the samples to the lines). Taking a line out and
    // adding it again instead made Qt Charts paint a deleted item (a crash).
    const QList<int> wanted = wantedMarbles();
    std::vector<Track> tracks;
    tracks.reserve(static_cast<std::size_t>(wanted.size()));
    for (int marble : wanted) {
        Track t;
        t.marble = marble;
        const auto isMarble = [marble](const Track &k) { return k.marble == marble; };
        auto old = std::find_if(m_tracks.begin(), m_tracks.end(), isMarble);
        auto parked = std::find_if(m_parked.begin(), m_parked.end(), isMarble);
        const bool kept = old != m_tracks.end();
        if (kept) {
            t.speed = std::move(old->speed);
            t.compareSpeed = std::move(old->compareSpeed);
            old->marble = -1;
        } else if (parked != m_parked.end()) {
            // Sampled while it was not plotted; gaps it had (a line started late) are filled
            // from the run's history where that knows them now.
            t.speed = std::move(parked->speed);
            t.compareSpeed = std::move(parked->compareSpeed);
            m_parked.erase(parked);
            fillGaps(t.speed, marble, m_documentVelocities);
            if (!m_compareModel.isEmpty())
                fillGaps(t.compareSpeed, marble, m_compareVelocities);
        } else {
            // A marble plotted from now on: its speeds for the samples already held, as far as
            // the run still knows them.
            startFrom(t.speed, marble, m_documentVelocities);
            if (!m_compareModel.isEmpty())
                startFrom(t.compareSpeed, marble, m_compareVelocities);
        }
        t.series = addSpeedSeries();
        if (!m_compareModel.isEmpty())
            t.compareSeries = addSpeedSeries();
        tracks.push_back(std::move(t));
    }
    for (Track &t : m_tracks) {
        deleteSeries(t.series);
        deleteSeries(t.compareSeries);
        if (t.marble >= 0 && t.marble < std::min(m_marbleCount, kMaxPlottedMarbles))
            m_parked.push_back(std::move(t));
    }
    std::erase_if(m_parked, [this](const Track &t) { return t.marble >= m_marbleCount; });
    m_tracks = std::move(tracks);
    remakeOverlays(); // back over the new lines, and after them in the legend

    const int plotted = static_cast<int>(m_tracks.size());
    const int candidates = m_selected.isEmpty() ? m_marbleCount : static_cast<int>(m_selected.size());
    m_capNote->setText(plotted < candidates ? tr("%1 of %2 marbles plotted").arg(plotted).arg(candidates) : QString());
    m_capNote->setToolTip(m_selected.isEmpty() ? tr("Select marbles on the stage to choose which ones are plotted.")
                                               : tr("At most %1 marbles are plotted at once.").arg(kMaxPlottedMarbles));
    emit plottedChanged();
}

QList<QPair<int, QColor>> PlotDock::plottedColours() const
{
    QList<QPair<int, QColor>> out;
    for (const Track &t : m_tracks)
        out.append({t.marble, marbleColor(t.marble)});
    return out;
}

void PlotDock::updateMarbleInfo(const World &world)
{
    if (world.info.size() != m_names.size())
        return; // marbles added or removed: appendFrame() follows the new count
    bool changed = false;
    for (std::size_t i = 0; i < world.info.size(); ++i) {
        const QString name = QString::fromStdString(world.info[i].name);
        const QString colour = QString::fromStdString(world.info[i].color);
        if (name != m_names[i] || colour != m_colors[i]) {
            m_names[i] = name;
            m_colors[i] = colour;
            changed = true;
        }
    }
    if (!changed)
        return;
    styleSeries();
    emit plottedChanged(); // the stage's colours follow the lines'
}

QList<QPair<int, QColor>> PlotDock::stageColours() const
{
    QList<QPair<int, QColor>> out = plottedColours();
    // In a crowd the marbles a selection leaves unplotted go back to the stage's blue: eleven
    // coloured among the Brownian preset's 804 small marbles would say nothing.
    if (m_marbleCount > kMaxPlottedMarbles)
        return out;
    QSet<QRgb> taken;
    for (const auto &[marble, colour] : out)
        taken.insert(colour.rgb());
    for (int marble = 0; marble < std::min(m_marbleCount, kMaxPlottedMarbles); ++marble) {
        const QColor colour = marbleColor(marble);
        if (!trackOf(marble) && !taken.contains(colour.rgb()))
            out.append({marble, colour});
    }
    std::sort(out.begin(), out.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
    return out;
}

QLineSeries *PlotDock::addSpeedSeries()
{
    auto *series = new QLineSeries;
    m_chart->addSeries(series);
    series->attachAxis(m_axisX);
    series->attachAxis(m_axisSpeed);
    return series;
}

void PlotDock::addCompareTrack(Track &t)
{
    if (t.compareSeries)
        return;
    // The comparison's speeds for the samples already held, as far as it keeps them (a
    // comparison that starts now has only the newest).
    startFrom(t.compareSpeed, t.marble, m_compareVelocities);
    t.compareSeries = addSpeedSeries();
}

void PlotDock::startFrom(RingBuffer<double> &values, int marble, const VelocityLookup &lookup) const
{
    // A line plotted from now on: a value for every sample already held (a gap where the lookup
    // does not know the frame), so that it stays aligned sample for sample with m_frames.
    values.setCapacity(m_capacity); // also drops what it held
    for (std::size_t k = 0; k < m_frames.size(); ++k)
        values.push(kNaN);
    fillGaps(values, marble, lookup);
}

void PlotDock::fillGaps(RingBuffer<double> &values, int marble, const VelocityLookup &lookup) const
{
    if (!lookup)
        return;
    const auto i = static_cast<std::size_t>(marble);
    for (std::size_t k = 0; k < m_frames.size() && k < values.size(); ++k) {
        if (!std::isnan(values.at(k)))
            continue;
        if (const std::vector<Vec2> *velocities = lookup(m_frames.at(k)); velocities && i < velocities->size())
            values.at(k) = magnitude((*velocities)[i]);
    }
}

void PlotDock::setVelocityLookup(VelocityLookup document, VelocityLookup compare)
{
    m_documentVelocities = std::move(document);
    m_compareVelocities = std::move(compare);
}

void PlotDock::removeCompareTrack(Track &t)
{
    t.compareSpeed.clear();
    deleteSeries(t.compareSeries);
}

bool PlotDock::drawRuns(QLineSeries *line, std::vector<QList<QPointF>> runs, const SampleValue &asStepped,
                        double &yMin, double &yMax)
{
    for (QList<QPointF> &run : runs)
        addEditJumps(run, asStepped, yMin, yMax);
    // A run of one sample (the frame a run starts from) is no line at all: its point is drawn.
    const auto give = [](QLineSeries *series, const QList<QPointF> &points) {
        series->replace(points);
        if (series->pointsVisible() != (points.size() == 1))
            series->setPointsVisible(points.size() == 1);
    };
    give(line, runs.empty() ? QList<QPointF>() : runs.back());
    if (!runs.empty())
        runs.pop_back();
    if (runs.empty() && !m_earlierRuns.contains(line))
        return false;
    std::vector<QLineSeries *> &earlier = m_earlierRuns[line];
    while (earlier.size() > runs.size()) {
        deleteSeries(earlier.back());
        earlier.pop_back();
    }
    const bool added = earlier.size() < runs.size();
    while (earlier.size() < runs.size()) {
        auto *series = new QLineSeries;
        m_chart->addSeries(series);
        for (QAbstractAxis *axis : line->attachedAxes())
            series->attachAxis(axis);
        showKey(series, false); // the line's own entry stands for it
        earlier.push_back(series);
    }
    for (std::size_t k = 0; k < runs.size(); ++k)
        give(earlier[k], runs[k]);
    followLine(line);
    if (earlier.empty())
        m_earlierRuns.erase(line);
    return added;
}

void PlotDock::followLine(const QLineSeries *line)
{
    const auto it = m_earlierRuns.find(line);
    if (it == m_earlierRuns.end())
        return;
    for (QLineSeries *series : it->second) {
        if (series->pen() != line->pen())
            series->setPen(line->pen());
        if (series->isVisible() != line->isVisible()) {
            series->setVisible(line->isVisible());
            // Qt Charts shows a line's legend entry again with the line (a helper's blank
            // entries, the energy ticked off and on between two refreshes).
            showKey(series, false);
        }
    }
}

QList<QLineSeries *> PlotDock::earlierRuns(const QLineSeries *line) const
{
    const auto it = m_earlierRuns.find(line);
    return it == m_earlierRuns.end() ? QList<QLineSeries *>() : QList<QLineSeries *>(it->second.begin(), it->second.end());
}

void PlotDock::deleteSeries(QLineSeries *&series)
{
    if (!series)
        return;
    if (const auto it = m_earlierRuns.find(series); it != m_earlierRuns.end()) {
        for (QLineSeries *&run : it->second)
            deleteSeries(run); // a line of its own, with no earlier runs
        m_earlierRuns.erase(it);
    }
    m_chart->removeSeries(series);
    delete series;
    series = nullptr;
}

QLineSeries *PlotDock::addTotalSeries(QColor colour, QValueAxis *axis)
{
    // Hidden, legend entry included, until its checkbox is ticked; named and dashed by styleSeries().
    auto *series = new QLineSeries;
    series->setPen(QPen(colour, 2.0));
    m_chart->addSeries(series);
    series->attachAxis(m_axisX);
    series->attachAxis(axis);
    showTotal(series, false);
    return series;
}

QLineSeries *PlotDock::addKeySeries(bool dashed)
{
    // While comparing, the legend names the two models once, as a solid and a dashed grey line,
    // instead of listing every marble twice; these two series never hold points. Light: the
    // kinetic energy's line beside them is a dark grey.
    auto *series = new QLineSeries;
    const QColor grey(0x9e, 0x9e, 0x9e);
    QPen pen = dashed ? comparePen(grey) : QPen(grey, 2.0);
    pen.setCapStyle(Qt::FlatCap);
    series->setPen(pen);
    m_chart->addSeries(series);
    series->attachAxis(m_axisX);
    series->attachAxis(m_axisSpeed);
    return series;
}

QLineSeries *PlotDock::addMarkSeries(Qt::PenStyle style, Key key, bool listed)
{
    // Vertical lines across the chart in the marks' grey, told apart by their dashes; listed in
    // the legend from their first mark on (refreshChart()).
    auto *series = new QLineSeries;
    QPen pen(kMarkColour, 1.5, style);
    pen.setCapStyle(Qt::FlatCap);
    series->setPen(pen);
    series->setName(keyName(key, m_compactLegend));
    m_chart->addSeries(series);
    series->attachAxis(m_axisX);
    series->attachAxis(m_axisSpeed);
    showKey(series, listed);
    return series;
}

void PlotDock::remakeOverlays()
{
    // Over the marbles' speed lines, and after them in the legend, always in this order: the
    // scene's totals, the comparison's, the two models' keys, the restart marks. The chart draws
    // and lists its lines in the order they were added, and a line cannot be moved (taking one
    // out and adding it again made Qt Charts paint a deleted item: see rebuildTracks()), so
    // these are made anew after any new speed line; refreshChart() gives them their points.
    // Without this a selection change while comparing put the comparison's energy and momentum
    // under the speed lines, which had covered them before, and "comparison restarted" at the
    // head of the legend.
    deleteSeries(m_kineticSeries);
    deleteSeries(m_compareKineticSeries);
    for (int c : {0, 1}) {
        deleteSeries(m_momentumSeries[c]);
        deleteSeries(m_compareMomentumSeries[c]);
    }
    deleteSeries(m_modelKey);
    deleteSeries(m_compareKey);
    deleteSeries(m_restartMarks);
    deleteSeries(m_editMarkSeries);
    const bool comparing = !m_compareModel.isEmpty();
    m_kineticSeries = addTotalSeries(kKineticColour, m_axisTotals);
    if (comparing)
        m_compareKineticSeries = addTotalSeries(kKineticColour, m_axisTotals);
    for (int c : {0, 1}) {
        m_momentumSeries[c] = addTotalSeries(kMomentumColour, m_axisMomentum);
        if (comparing)
            m_compareMomentumSeries[c] = addTotalSeries(kMomentumColour, m_axisMomentum);
    }
    // Shown once they are the members showTotal() tells the legend's from.
    for (QLineSeries *series : {m_kineticSeries, m_compareKineticSeries})
        showTotal(series, m_showKinetic->isChecked());
    for (int c : {0, 1}) {
        showTotal(m_momentumSeries[c], m_showMomentum->isChecked());
        showTotal(m_compareMomentumSeries[c], m_showMomentum->isChecked());
    }
    if (comparing) {
        m_modelKey = addKeySeries(false);
        m_compareKey = addKeySeries(true);
        m_restartMarks = addMarkSeries(Qt::DotLine, Key::Restart, !m_compareRestarts.empty());
    }
    m_editMarkSeries = addMarkSeries(Qt::DashDotLine, Key::Edit, false);
    styleSeries();
    m_dirty = true;
}

void PlotDock::showTotal(QLineSeries *series, bool shown)
{
    if (!series)
        return;
    series->setVisible(shown);
    followLine(series);
    // The comparison model's totals stay out of the legend: its "(dashed)" entry stands for them.
    const std::array<QLineSeries *, 3> listed = sceneTotals();
    const bool isListed = std::find(listed.begin(), listed.end(), series) != listed.end();
    showKey(series, shown && isListed);
    updateLegendLabels();
}

void PlotDock::styleSeries()
{
    // While comparing, a marble's two lines share its colour: solid for the scene's model, dashed
    // for the comparison model, whose name the dashed line carries ("large (marble 0), exact").
    // The legend lists each marble once and the two models once.
    for (Track &t : m_tracks) {
        const QColor colour = marbleColor(t.marble);
        t.series->setName(marbleLabel(t.marble));
        t.series->setPen(QPen(colour, 2.0));
        if (t.compareSeries) {
            t.compareSeries->setName(tr("%1, %2").arg(marbleLabel(t.marble), m_compareModel));
            t.compareSeries->setPen(comparePen(colour));
            showKey(t.compareSeries, false);
        }
    }
    // The totals: solid in colours of their own; dashed is kept for the comparison model's lines
    // (a dashed energy line without a comparison read as another model's), as for speeds, whose
    // legend entries ("book (solid)", "exact (dashed)") stand for the totals too.
    const bool comparing = m_compareKineticSeries != nullptr;
    // (The scene's totals are named by updateLegendLabels(), in full or short.)
    m_kineticSeries->setPen(QPen(kKineticColour, 2.0));
    for (int c : {0, 1})
        m_momentumSeries[c]->setPen(momentumPen(c, false));
    if (comparing) {
        m_compareKineticSeries->setPen(comparePen(kKineticColour));
        m_compareKineticSeries->setName(tr("%1, %2").arg(totalName(0), m_compareModel));
        for (int c : {0, 1}) {
            m_compareMomentumSeries[c]->setPen(momentumPen(c, true));
            m_compareMomentumSeries[c]->setName(tr("%1, %2").arg(totalName(1 + c), m_compareModel));
        }
    }
    updateLegendLabels();
}

void PlotDock::updateLegendLabels()
{
    // The legend is one row under the chart, and Qt cuts a label that does not fit its share of
    // the row ("marb…"): a crowd's twelve marbles and a comparison's two keys no longer told
    // which line was which. Where the full labels do not fit, the marbles get short ones ("#3",
    // or a named marble's name); hovering a line still gives its full label.
    // A view not on screen has no width worth measuring; it is measured again when shown.
    const bool shown = m_chartView && m_chartView->isVisible();
    m_compactLegend = shown && !legendFits(false);
    // Short, and still too long (a named crowd compared, restarted and edited, at 1024 x 768:
    // "he…", "ex…", "re…", "e…"): the marks' keys give their room to the lines', whose names a
    // class needs to tell the lines apart; the marks are still drawn.
    m_markKeysHidden = m_compactLegend && !legendFits(true);
    // Still too long (a crowd's twelve marbles with both totals at 1024 x 768 were swatches
    // without a word, the totals' "KE", "p x" and "p y" gone too; a helper's finding): the
    // unnamed marbles' keys go, so that the totals and the named marbles keep theirs. Hovering
    // a line names its marble.
    m_marbleKeysHidden = m_markKeysHidden && !legendFits(true, false);
    for (Track &t : m_tracks)
        t.series->setName(m_compactLegend ? compactMarbleLabel(t.marble) : marbleLabel(t.marble));
    // The totals too: "momentum x" and "momentum y" were both cut to "mome…".
    const std::array<QLineSeries *, 3> totals = sceneTotals();
    for (std::size_t k = 0; k < totals.size(); ++k) {
        if (totals[k]) // (not yet, as the dock is built)
            totals[k]->setName(m_compactLegend ? totalShortName(static_cast<int>(k)) : totalName(static_cast<int>(k)));
    }
    // And the models' keys and the marks, whose line samples show solid, dashed or dotted: at
    // 1024 x 768 "book (s…" and "exact (…" were cut, and a named marble with them ("heavy …").
    if (m_modelKey && m_compareKey) {
        m_modelKey->setName(keyName(Key::Model, m_compactLegend));
        m_compareKey->setName(keyName(Key::Compare, m_compactLegend));
    }
    if (m_restartMarks)
        m_restartMarks->setName(keyName(Key::Restart, m_compactLegend));
    if (m_editMarkSeries)
        m_editMarkSeries->setName(keyName(Key::Edit, m_compactLegend));
    bool keysChanged = false;
    for (const Track &t : m_tracks)
        keysChanged = showKey(t.series, !(m_marbleKeysHidden && !isNamed(t.marble))) || keysChanged;
    if (keysChanged) {
        // Laid out again, or a marker shown afterwards is drawn over its neighbour (refreshChart()).
        m_chart->legend()->hide();
        m_chart->legend()->show();
    }
}

bool PlotDock::showKey(QLineSeries *series, bool shown)
{
    bool changed = false;
    for (QLegendMarker *marker : series ? m_chart->legend()->markers(series) : QList<QLegendMarker *>{}) {
        changed = changed || marker->isVisible() != shown;
        marker->setVisible(shown);
    }
    return changed;
}

QString PlotDock::keyName(Key key, bool compact) const
{
    switch (key) {
    case Key::Model:
        return compact ? solidModels() : tr("%1 (solid)").arg(solidModels());
    case Key::Compare:
        return compact ? m_compareModel : tr("%1 (dashed)").arg(m_compareModel);
    case Key::Restart:
        return compact ? tr("restarted") : tr("comparison restarted");
    case Key::Edit:
        return compact ? tr("edited") : tr("scene edited");
    }
    return QString();
}

std::array<QLineSeries *, 3> PlotDock::sceneTotals() const
{
    return {m_kineticSeries, m_momentumSeries[0], m_momentumSeries[1]};
}

QString PlotDock::totalName(int k) const
{
    const QString names[] = {tr("kinetic energy"), tr("momentum x"), tr("momentum y")};
    return names[k];
}

QString PlotDock::totalShortName(int k) const
{
    const QString names[] = {tr("KE"), tr("p x"), tr("p y")};
    return names[k];
}

QString PlotDock::compactMarbleLabel(int marble) const
{
    const auto i = static_cast<std::size_t>(marble);
    return i < m_names.size() && !m_names[i].isEmpty() ? m_names[i] : tr("#%1").arg(marble);
}

bool PlotDock::isNamed(int marble) const
{
    const auto i = static_cast<std::size_t>(marble);
    return i < m_names.size() && !m_names[i].isEmpty();
}

bool PlotDock::legendFits(bool compact, bool markKeys) const
{
    const QFontMetrics metrics(m_chart->legend()->font());
    int needed = 0;
    // Each entry is its label, its marker (about a line high) and Qt 6.4's margins and gap (about
    // 16 px): twelve "marble N" fit a 1040-px plot, fourteen with the comparison's keys do not.
    // (With 10 px, five named marbles, both totals and both models' keys were taken to fit a
    // 1240-px plot, and Qt cut one label: "heavy mover (mar…"; a regression tester's finding.)
    // Each label as it would be, whatever the legend shows now.
    const auto entry = [&](const QString &label) { needed += metrics.horizontalAdvance(label) + metrics.height() + 16; };
    for (const Track &t : m_tracks)
        entry(compact ? compactMarbleLabel(t.marble) : marbleLabel(t.marble));
    if (m_modelKey && m_compareKey) {
        entry(keyName(Key::Model, compact));
        entry(keyName(Key::Compare, compact));
    }
    // The restarts' key while there is one (with it the legend's labels were cut: "compari…",
    // "kinetic e…", "moment…"; a teacher's finding). The first to go where even short labels do
    // not fit.
    if (markKeys && m_restartMarks && !m_compareRestarts.empty())
        entry(keyName(Key::Restart, compact));
    if (markKeys && m_editMarkSeries && !m_editMarks.empty())
        entry(keyName(Key::Edit, compact));
    const std::array<QLineSeries *, 3> totals = sceneTotals();
    for (std::size_t k = 0; k < totals.size(); ++k) {
        if (totals[k] && totals[k]->isVisible())
            entry(compact ? totalShortName(static_cast<int>(k)) : totalName(static_cast<int>(k)));
    }
    return needed <= m_chartView->width() - 2 * metrics.height();
}

qsizetype PlotDock::pointsPerLine() const
{
    const double pixels = m_chart->plotArea().width() * m_chartView->devicePixelRatioF();
    if (!(pixels >= 1.0))
        return kMaxPointsPerLine;
    return std::clamp(static_cast<qsizetype>(std::ceil(pixels)), kMinPointsPerLine, kMaxPointsPerLine);
}

bool PlotDock::eventFilter(QObject *watched, QEvent *event)
{
    if (watched == m_chartView->viewport()) {
        if (event->type() == QEvent::MouseMove) {
            hoverAt(static_cast<QMouseEvent *>(event)->position().toPoint());
        } else if (event->type() == QEvent::Leave) {
            hoverAt(QPoint(-1, -1));
        } else if (event->type() == QEvent::ToolTip && !hoverText().isEmpty()) {
            // The view's own help event, a moment after the pointer stops, found no item's tooltip
            // and hid the readout's: it vanished about a second after it was shown (a regression
            // tester's finding). The readout's is shown again instead.
            const auto *help = static_cast<QHelpEvent *>(event);
            QToolTip::showText(help->globalPos(), hoverText(), m_chartView);
            return true;
        }
    }
    if (watched == m_chartView && (event->type() == QEvent::Resize || event->type() == QEvent::Show)) {
        updateLegendLabels();
        m_dirty = true; // the lines are thinned to the plot's width
    }
    return QDockWidget::eventFilter(watched, event);
}

QList<int> PlotDock::wantedMarbles() const
{
    QList<int> out;
    if (m_selected.isEmpty()) {
        for (int i = 0; i < std::min(m_marbleCount, kMaxPlottedMarbles); ++i)
            out.append(i);
        return out;
    }
    for (int i : m_selected) {
        if (i < m_marbleCount && out.size() < kMaxPlottedMarbles)
            out.append(i);
    }
    return out;
}

QColor PlotDock::marbleColor(int marble) const
{
    const auto i = static_cast<std::size_t>(marble);
    if (i < m_colors.size() && !m_colors[i].isEmpty()) {
        const QColor colour = QColor::fromString(m_colors[i]);
        if (colour.isValid())
            return colour;
    }
    return defaultMarbleColor(i < m_hues.size() ? m_hues[i] : marble);
}

namespace {

/// Which places in the colour list `hues` take, with room for `more` marbles beyond them (so that
/// one is always free).
std::vector<bool> takenHues(const std::vector<int> &hues, std::size_t more)
{
    std::vector<bool> taken(hues.size() + more, false);
    for (const int hue : hues) {
        if (hue >= 0 && static_cast<std::size_t>(hue) < taken.size())
            taken[static_cast<std::size_t>(hue)] = true;
    }
    return taken;
}

/// The first place from `next` on that `taken` leaves free, marked taken. Linear in all: a search
/// of the list for each candidate place was cubic, 3.5 s for a 5,000-marble scene's first delete
/// and about 4 minutes for a 20,000-marble crowd's.
int takeFreeHue(std::vector<bool> &taken, std::size_t &next)
{
    while (taken[next])
        ++next;
    taken[next] = true;
    return static_cast<int>(next);
}

} // namespace

void PlotDock::ensureColourOrder(int count)
{
    if (static_cast<int>(m_hues.size()) >= count)
        return;
    std::vector<bool> taken = takenHues(m_hues, static_cast<std::size_t>(count) - m_hues.size());
    std::size_t next = 0;
    while (static_cast<int>(m_hues.size()) < count)
        m_hues.push_back(takeFreeHue(taken, next));
}

void PlotDock::addEditJumps(QList<QPointF> &points, const SampleValue &asStepped, double &yMin, double &yMax) const
{
    for (const EditMark &m : m_editMarks) {
        // The point of the mark's frame, where the line has one (a thinned line may not), after
        // the line's first: a line that starts at the mark has nothing to jump from.
        const double x = xOf(m.frame);
        const auto at = std::find_if(points.begin(), points.end(), [x](const QPointF &p) { return p.x() >= x; });
        if (at == points.begin() || at == points.end() || at->x() != x)
            continue;
        // From a value as stepped that is no number (a comparison not running at the mark has NaN),
        // no jump.
        const std::optional<double> stepped = m.asSteppedKnown ? asStepped(m.asStepped) : std::nullopt;
        const double from = stepped ? *stepped : std::prev(at)->y();
        if (!std::isfinite(from) || from == at->y())
            continue;
        yMin = std::min(yMin, from);
        yMax = std::max(yMax, from);
        points.insert(at, QPointF(x, from));
    }
}

void PlotDock::noteMasses(const World &world)
{
    // Samples from this frame on are taken again (stepped on after Step Back, or an edit there):
    // their masses with them. Entries no sample needs any more go.
    while (!m_massesFrom.empty() && m_massesFrom.back().frame >= world.frame)
        m_massesFrom.pop_back();
    if (m_massesFrom.empty() || m_massesFrom.back().mass != world.mass)
        m_massesFrom.push_back({world.frame, world.mass});
    const std::int64_t oldest = m_frames.size() > 0 ? m_frames.at(0) : world.frame;
    const auto stillNeeded = std::find_if(m_massesFrom.begin() + 1, m_massesFrom.end(),
                                          [oldest](const MassesFrom &e) { return e.frame > oldest; });
    m_massesFrom.erase(m_massesFrom.begin(), stillNeeded - 1);
}

const std::vector<double> *PlotDock::massesAt(const std::vector<MassesFrom> &eras, std::int64_t frame, int count)
{
    const auto after = std::upper_bound(eras.begin(), eras.end(), frame,
                                        [](std::int64_t f, const MassesFrom &e) { return f < e.frame; });
    if (after == eras.begin())
        return nullptr;
    const std::vector<double> &mass = std::prev(after)->mass;
    return mass.size() == static_cast<std::size_t>(count) ? &mass : nullptr;
}

void PlotDock::marbleRemovedAt(int i, int countBefore)
{
    for (EditMark &m : m_editMarks)
        m.asSteppedKnown = false;
    std::vector<std::pair<std::int64_t, double>> removed;
    for (MassesFrom &e : m_massesFrom) {
        if (static_cast<std::size_t>(i) < e.mass.size() && e.mass.size() == static_cast<std::size_t>(countBefore)) {
            removed.emplace_back(e.frame, e.mass[static_cast<std::size_t>(i)]);
            e.mass.erase(e.mass.begin() + i);
        }
    }
    m_removedMasses.emplace_back(i, std::move(removed));
    ensureColourOrder(countBefore);
    const auto at = static_cast<std::size_t>(i);
    if (at >= m_hues.size())
        return;
    m_removedHues.emplace_back(i, m_hues[at]);
    m_hues.erase(m_hues.begin() + static_cast<std::ptrdiff_t>(at));
}

void PlotDock::marbleInsertedAt(int i, int countAfter, double mass)
{
    for (EditMark &m : m_editMarks)
        m.asSteppedKnown = false;
    // A delete undone: each entry gets the mass the marble had there (the latest from its
    // frame or before); a marble added, its mass of now.
    std::vector<std::pair<std::int64_t, double>> removed;
    if (!m_removedMasses.empty() && m_removedMasses.back().first == i) {
        removed = std::move(m_removedMasses.back().second);
        m_removedMasses.pop_back();
    }
    for (MassesFrom &e : m_massesFrom) {
        if (i < 0 || static_cast<std::size_t>(i) > e.mass.size() || e.mass.size() + 1 != static_cast<std::size_t>(countAfter))
            continue;
        double had = mass;
        for (const auto &[frame, m] : removed) {
            if (frame <= e.frame)
                had = m;
        }
        e.mass.insert(e.mass.begin() + i, had);
    }
    ensureColourOrder(countAfter - 1);
    if (i < 0 || i > static_cast<int>(m_hues.size()))
        return;
    int hue = -1;
    if (!m_removedHues.empty() && m_removedHues.back().first == i) {
        hue = m_removedHues.back().second; // a delete undone: its colour back
        m_removedHues.pop_back();
    }
    if (hue < 0 || std::find(m_hues.begin(), m_hues.end(), hue) != m_hues.end()) {
        std::vector<bool> taken = takenHues(m_hues, 1);
        std::size_t next = 0;
        hue = takeFreeHue(taken, next);
    }
    m_hues.insert(m_hues.begin() + i, hue);
}

void PlotDock::forgetColourOrder()
{
    m_hues.clear();
    m_removedHues.clear();
    m_removedMasses.clear();
}

QString PlotDock::marbleLabel(int marble) const
{
    const auto i = static_cast<std::size_t>(marble);
    if (i < m_names.size() && !m_names[i].isEmpty())
        return tr("%1 (marble %2)").arg(m_names[i]).arg(marble);
    return tr("marble %1").arg(marble);
}

double PlotDock::xOf(std::int64_t frame) const
{
    return m_timeInSeconds ? secondsAt(frame) : static_cast<double>(frame);
}

const PlotDock::Track *PlotDock::trackOf(int marble) const
{
    for (const Track &t : m_tracks) {
        if (t.marble == marble)
            return &t;
    }
    return nullptr;
}

void PlotDock::updateTotalsAxis()
{
    // Each total's axis is shown with it (the legend gives the colours).
    m_axisTotals->setVisible(m_showKinetic->isChecked());
    m_axisMomentum->setVisible(m_showMomentum->isChecked());
}

void PlotDock::updateAxisTitles()
{
    const auto title = [](QAbstractAxis *axis, const QString &text) {
        if (axis->titleText() != text)
            axis->setTitleText(text);
    };
    title(m_axisX, m_timeInSeconds ? tr("time (s)") : tr("frame"));
    // The titles up the chart's sides in short where the chart is less high than the speed's
    // is long (at a scale of 1.5 on a 1280 x 720 projector: "speed (px/fr…", "kinetic ener…").
    // Shorter still where even that is too long (the window made to fit 480 px): "speed".
    const QString speed = m_timeInSeconds ? tr("speed (px/s)") : tr("speed (px/frame)");
    const QString shortSpeed = m_timeInSeconds ? tr("v (px/s)") : tr("v (px/frame)");
    const double height = m_chart->plotArea().height();
    const auto fits = [this, height](const QString &text) {
        return !(height > 0.0) || QFontMetrics(m_axisSpeed->titleFont()).horizontalAdvance(text) <= height;
    };
    const bool full = fits(speed);
    title(m_axisSpeed, full ? speed : fits(shortSpeed) ? shortSpeed : tr("speed")); // a "v" turned up read as ">"
    title(m_axisTotals, full ? tr("kinetic energy") : tr("KE"));
    title(m_axisMomentum, full ? tr("momentum") : tr("p"));
}

double PlotDock::perSecond() const
{
    return m_timeInSeconds && m_frameMs > 0.0 ? 1000.0 / m_frameMs : 1.0;
}

QString PlotDock::energyUnit() const
{
    // Mass is the scene's own unit.
    return m_timeInSeconds ? tr("mass·px²/s²") : tr("mass·px²/frame²");
}

QString PlotDock::momentumUnit() const
{
    return m_timeInSeconds ? tr("mass·px/s") : tr("mass·px/frame");
}

QString PlotDock::suggestedExportPath(const QString &extension) const
{
    // Every export was offered as "marbles-plot.csv" in the working folder, whatever the scene.
    const QString base = sceneFileStem(m_sceneFile.isEmpty() ? m_sceneName : QFileInfo(m_sceneFile).fileName());
    const QString name = (base.isEmpty() ? QStringLiteral("marbles") : base) + QStringLiteral("-plot.") + extension;
    return m_sceneFile.isEmpty() ? name : QFileInfo(m_sceneFile).dir().filePath(name);
}

void PlotDock::exportCsvInteractive()
{
    const QString path = askFileName(this, FileDialogMode::Save, tr("Export Plot Data (CSV)"),
                                     suggestedExportPath(QStringLiteral("csv")), tr("CSV files (*.csv)"), QStringLiteral("csv"));
    if (path.isEmpty())
        return;
    const QString error = exportCsv(path);
    if (!error.isEmpty())
        QMessageBox::warning(this, tr("Export Plot Data (CSV)"), error);
    else
        emit exported(path);
}

void PlotDock::exportPngInteractive()
{
    const QString path = askFileName(this, FileDialogMode::Save, tr("Export Plot Image (PNG)"),
                                     suggestedExportPath(QStringLiteral("png")), tr("PNG images (*.png)"), QStringLiteral("png"));
    if (path.isEmpty())
        return;
    const QString error = exportPng(path);
    if (!error.isEmpty())
        QMessageBox::warning(this, tr("Export Plot Image (PNG)"), error);
    else
        emit exported(path);
}

} // namespace marbles
