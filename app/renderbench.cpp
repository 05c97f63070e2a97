// marbles-renderbench: how fast the stage draws a crowd. Builds the crowd reference scene
// (core/presets.h) for each N, shows the real StageView (or the whole MainWindow) at a fixed
// size, and for every frame simulates one step and repaints the viewport synchronously, so
// the time measured is the time the pixels took. Prints frames per second of physics + paint
// and of paint alone (the same frame repainted), medians over the run.
//
// Runs on any Qt platform: QT_QPA_PLATFORM=offscreen marbles-renderbench, or under xvfb-run.

#include "core/presets.h"
#include "ui/comparerun.h"
#include "ui/mainwindow.h"
#include "ui/plotdock.h"
#include "ui/scenedocument.h"
#include "ui/stageview.h"

#include <QApplication>
#include <QChartView>
#include <QXYSeries>
#include <QCommandLineParser>
#include <QElapsedTimer>
#include <QGraphicsScene>
#include <QTextStream>
#include <QWindow>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <memory>
#include <optional>
#include <vector>

namespace {

using namespace marbles;

struct Options {
    std::vector<int> counts;
    int frames = 120;
    int warmup = 10;
    bool vectors = true;
    bool trails = false;
    double zoom = 1.0;
    QSize size{1280, 800};
    bool mainWindow = false;
    double moving = 1.0;
    std::uint64_t seed = 1;
    bool overrideModel = false;
    ModelKind model = ModelKind::Exact;
    std::optional<ModelKind> compare; ///< a second model run beside the first (main window only)
    int selected = -1;                ///< marble selected (its long trail drawn with trails on)
    bool csv = false;
};

struct Result {
    int n = 0;
    int items = 0;
    QSize viewport;
    bool antialias = false;
    /// Trails drawn: "on" (every marble's), "selected" (above the crowd size for all, the
    /// selected marble's alone) or "off".
    QString trails = QStringLiteral("off");
    bool vectorsDrawn = false; ///< vectors asked for and long enough on screen to be drawn
    double scale = 1.0;        ///< view px per stage px
    double modelMs = 0.0;     ///< median World::step() alone, on a copy of the scene (no document, no view)
    double physicsMs = 0.0;   ///< median simulation + item sync per frame
    double paintMs = 0.0;     ///< median event delivery and paint after a step
    double frameMs = 0.0;     ///< median physics + paint per frame
    double paintOnlyMs = 0.0; ///< median repaint of an unchanged frame
    double frameCpuMs = 0.0;     ///< median processor time of physics + paint (not inflated by other processes)
    double paintOnlyCpuMs = 0.0; ///< median processor time of a repaint
    double paintsPerFrame = 0.0;
    int hitMarbles = 0; ///< marbles with a Figure 11.12 overlay at the end of the run
    std::size_t historyFrames = 0; ///< frames the step-back history keeps at the end of the run
    std::size_t historyBytes = 0;
    double plotRefreshMs = -1.0; ///< median refresh of the Plot dock, chart drawn (main window only)
    int plotLines = 0;           ///< lines the Plot dock draws (a comparison's included)
    qsizetype plotSamples = 0;   ///< samples (frames) each line holds
};

/// Wall-clock and processor time together: on a shared machine the wall clock also counts
/// the time other processes ran, the processor time only ours.
class Stopwatch {
public:
    Stopwatch() { m_wall.start(); }
    /// Wall-clock ms since the start.
    double wallMs() const { return static_cast<double>(m_wall.nsecsElapsed()) / 1.0e6; }
    /// Processor ms used by this process (all its threads) since the start.
    double cpuMs() const { return 1000.0 * static_cast<double>(std::clock() - m_cpuStart) / CLOCKS_PER_SEC; }

private:
    QElapsedTimer m_wall;
    std::clock_t m_cpuStart = std::clock();
};

double median(std::vector<double> values)
{
    if (values.empty())
        return 0.0;
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
}

double fps(double ms)
{
    return ms > 0.0 ? 1000.0 / ms : 0.0;
}


/// Waits (processing events) until `widget`'s window is on screen, at most two seconds.
void waitExposed(QWidget *widget)
{
    QElapsedTimer clock;
    clock.start();
    while (clock.elapsed() < 2000) {
        QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
        if (widget->windowHandle() && widget->windowHandle()->isExposed())
            break;
    }
    QCoreApplication::processEvents();
}

/// Lets the event loop deliver the frame's updates (the scene's changes reach the view through
/// queued calls, and the view paints on them, as in the application); repaints synchronously
/// when nothing was painted, so that every measured frame is drawn exactly once.
void paintFrame(StageView *view)
{
    const qint64 before = view->paintCount();
    QCoreApplication::processEvents();
    if (view->paintCount() == before)
        view->viewport()->repaint();
}

Result measure(int n, const Options &options)
{
    World world = makeCrowd(n, options.seed, options.moving);
    if (options.overrideModel)
        world.params.model = options.model;

    // The model alone, for reference: what the document and the view add to it is theirs.
    std::vector<double> model;
    {
        World copy = world;
        for (int f = 0; f < options.frames; ++f) {
            const Stopwatch clock;
            copy.step();
            model.push_back(clock.wallMs());
        }
    }

    std::unique_ptr<MainWindow> window;
    std::unique_ptr<SceneDocument> ownDocument;
    std::unique_ptr<StageView> ownView;
    SceneDocument *document = nullptr;
    StageView *view = nullptr;
    QWidget *top = nullptr;
    if (options.mainWindow) {
        window = std::make_unique<MainWindow>();
        document = window->document();
        view = window->stageView();
        top = window.get();
    } else {
        ownDocument = std::make_unique<SceneDocument>();
        ownView = std::make_unique<StageView>(ownDocument.get());
        document = ownDocument.get();
        view = ownView.get();
        top = view;
    }
    document->resetScene(world);
    if (options.compare)
        window->compareRun()->setModel(*options.compare);
    view->setVectorsVisible(options.vectors);
    view->setTrailsVisible(options.trails);
    view->selectMarble(options.selected);
    top->resize(options.size);
    top->show();
    waitExposed(top);
    view->fitToStage();
    if (options.zoom != 1.0)
        view->zoomBy(options.zoom);

    for (int f = 0; f < options.warmup; ++f) {
        document->advance(1);
        paintFrame(view);
    }

    Result result;
    std::vector<double> physics;
    std::vector<double> paint;
    std::vector<double> frame;
    std::vector<double> frameCpu;
    const qint64 paintsBefore = view->paintCount();
    for (int f = 0; f < options.frames; ++f) {
        const Stopwatch clock;
        document->advance(1);
        const double t1 = clock.wallMs();
        paintFrame(view);
        const double t2 = clock.wallMs();
        frameCpu.push_back(clock.cpuMs());
        physics.push_back(t1);
        paint.push_back(t2 - t1);
        frame.push_back(t2);
    }
    const qint64 paints = view->paintCount() - paintsBefore;

    // The Plot dock's refresh, which its timer runs about five times a second while the run
    // plays: the buffered samples handed to the chart and the chart drawn.
    if (options.mainWindow) {
        PlotDock *plot = window->plotDock();
        std::vector<double> refresh;
        for (int f = 0; f < std::min(options.frames, 30); ++f) {
            const Stopwatch clock;
            plot->refreshChart();
            plot->chartView()->viewport()->repaint();
            refresh.push_back(clock.wallMs());
        }
        result.plotRefreshMs = median(refresh);
        for (const QAbstractSeries *series : plot->chartView()->chart()->series()) {
            const auto *line = qobject_cast<const QXYSeries *>(series);
            result.plotLines += line && line->count() > 0 ? 1 : 0;
        }
        result.plotSamples = plot->sampleCount();
    }

    std::vector<double> paintOnly;
    std::vector<double> paintOnlyCpu;
    for (int f = 0; f < options.frames; ++f) {
        const Stopwatch clock;
        view->viewport()->repaint();
        paintOnly.push_back(clock.wallMs());
        paintOnlyCpu.push_back(clock.cpuMs());
    }

    result.n = n;
    result.items = static_cast<int>(view->scene()->items().size());
    result.viewport = view->viewport()->size();
    result.antialias = view->renderHints().testFlag(QPainter::Antialiasing);
    result.trails = !view->trailsVisible()     ? QStringLiteral("off")
                    : !view->trailsSuppressed() ? QStringLiteral("on")
                    : view->selectedMarble() >= 0 ? QStringLiteral("selected")
                                                  : QStringLiteral("off");
    result.vectorsDrawn = view->vectorsVisible() && !view->vectorsHiddenByZoom();
    result.scale = view->transform().m11();
    result.modelMs = median(model);
    result.physicsMs = median(physics);
    result.paintMs = median(paint);
    result.frameMs = median(frame);
    result.paintOnlyMs = median(paintOnly);
    result.frameCpuMs = median(frameCpu);
    result.paintOnlyCpuMs = median(paintOnlyCpu);
    for (const HitRecord &hit : document->world().lastHit)
        result.hitMarbles += hit.frame >= 0 ? 1 : 0;
    result.paintsPerFrame = options.frames > 0 ? static_cast<double>(paints) / options.frames : 0.0;
    result.historyFrames = document->history().size();
    result.historyBytes = document->history().byteSize();
    top->hide();
    return result;
}

bool parseOptions(const QCoreApplication &app, Options &options, QString &error)
{
    QCommandLineParser parser;
    parser.setApplicationDescription(QStringLiteral(
        "Render benchmark: the crowd scene on the real stage view, physics + synchronous repaint per frame."));
    parser.addHelpOption();
    const QCommandLineOption countOption(QStringLiteral("n"), QStringLiteral("Marble counts, comma-separated."),
                                         QStringLiteral("list"), QStringLiteral("2000,20000"));
    const QCommandLineOption framesOption(QStringLiteral("frames"), QStringLiteral("Frames measured per count."),
                                          QStringLiteral("N"), QStringLiteral("120"));
    const QCommandLineOption warmupOption(QStringLiteral("warmup"),
                                          QStringLiteral("Frames run before measuring (sprite caches fill)."),
                                          QStringLiteral("N"), QStringLiteral("10"));
    const QCommandLineOption vectorsOption(QStringLiteral("vectors"),
                                           QStringLiteral("Figure 11.12 vectors on or off."), QStringLiteral("on|off"),
                                           QStringLiteral("on"));
    const QCommandLineOption trailsOption(QStringLiteral("trails"),
                                          QStringLiteral("Fading trails on or off (off above 2,000 marbles anyway)."),
                                          QStringLiteral("on|off"), QStringLiteral("off"));
    const QCommandLineOption zoomOption(QStringLiteral("zoom"),
                                        QStringLiteral("Zoom relative to the whole stage fitting the view (> 1 zooms in)."),
                                        QStringLiteral("F"), QStringLiteral("1"));
    const QCommandLineOption sizeOption(QStringLiteral("size"), QStringLiteral("Window size, px."),
                                        QStringLiteral("WxH"), QStringLiteral("1280x800"));
    const QCommandLineOption windowOption(QStringLiteral("window"),
                                          QStringLiteral("The stage view alone, or the whole main window."),
                                          QStringLiteral("stage|main"), QStringLiteral("stage"));
    const QCommandLineOption movingOption(QStringLiteral("moving"),
                                          QStringLiteral("Fraction of the crowd that moves at the start."),
                                          QStringLiteral("F"), QStringLiteral("1"));
    const QCommandLineOption seedOption(QStringLiteral("seed"), QStringLiteral("Crowd seed."), QStringLiteral("S"),
                                        QStringLiteral("1"));
    const QCommandLineOption modelOption(QStringLiteral("model"),
                                         QStringLiteral("Physics model (default: the crowd's own, exact)."),
                                         QStringLiteral("book|impulse|exact"));
    const QCommandLineOption compareOption(
        QStringLiteral("compare"),
        QStringLiteral("Compare with a second model, its marbles drawn as ghosts (Simulation > Compare With; needs --window main)."),
        QStringLiteral("book|impulse|exact"));
    const QCommandLineOption selectOption(
        QStringLiteral("select"), QStringLiteral("Select marble I (with trails on, its trail is kept long and drawn)."),
        QStringLiteral("I"));
    const QCommandLineOption csvOption(QStringLiteral("csv"), QStringLiteral("Print CSV rows instead of text."));
    parser.addOptions({countOption, framesOption, warmupOption, vectorsOption, trailsOption, zoomOption, sizeOption, windowOption, movingOption,
                       seedOption, modelOption, compareOption, selectOption, csvOption});
    parser.process(app);

    bool ok = true;
    for (const QString &part : parser.value(countOption).split(QLatin1Char(','), Qt::SkipEmptyParts)) {
        const int n = part.trimmed().toInt(&ok);
        if (!ok || n < 0) {
            error = QStringLiteral("--n: marble counts must be whole numbers >= 0, got '%1'").arg(part);
            return false;
        }
        options.counts.push_back(n);
    }
    options.frames = parser.value(framesOption).toInt(&ok);
    if (!ok || options.frames < 1) {
        error = QStringLiteral("--frames: must be a whole number >= 1");
        return false;
    }
    options.warmup = parser.value(warmupOption).toInt(&ok);
    if (!ok || options.warmup < 0) {
        error = QStringLiteral("--warmup: must be a whole number >= 0");
        return false;
    }
    const QString vectors = parser.value(vectorsOption);
    if (vectors != QLatin1String("on") && vectors != QLatin1String("off")) {
        error = QStringLiteral("--vectors: must be on or off");
        return false;
    }
    options.vectors = vectors == QLatin1String("on");
    const QString trails = parser.value(trailsOption);
    if (trails != QLatin1String("on") && trails != QLatin1String("off")) {
        error = QStringLiteral("--trails: must be on or off");
        return false;
    }
    options.trails = trails == QLatin1String("on");
    options.zoom = parser.value(zoomOption).toDouble(&ok);
    if (!ok || options.zoom < 0.1 || options.zoom > 100.0) {
        error = QStringLiteral("--zoom: must be a number in [0.1, 100]");
        return false;
    }
    const QStringList size = parser.value(sizeOption).split(QLatin1Char('x'));
    int width = 0;
    int height = 0;
    if (size.size() == 2)
        width = size[0].toInt(&ok);
    if (ok && size.size() == 2)
        height = size[1].toInt(&ok);
    if (!ok || width < 320 || height < 240) {
        error = QStringLiteral("--size: must be WxH, at least 320x240");
        return false;
    }
    options.size = QSize(width, height);
    const QString window = parser.value(windowOption);
    if (window != QLatin1String("stage") && window != QLatin1String("main")) {
        error = QStringLiteral("--window: must be stage or main");
        return false;
    }
    options.mainWindow = window == QLatin1String("main");
    options.moving = parser.value(movingOption).toDouble(&ok);
    if (!ok || options.moving < 0.0 || options.moving > 1.0) {
        error = QStringLiteral("--moving: must be a number in [0, 1]");
        return false;
    }
    options.seed = parser.value(seedOption).toULongLong(&ok);
    if (!ok) {
        error = QStringLiteral("--seed: must be a whole number >= 0");
        return false;
    }
    if (parser.isSet(selectOption)) {
        options.selected = parser.value(selectOption).toInt(&ok);
        if (!ok || options.selected < 0) {
            error = QStringLiteral("--select: must be a marble index >= 0");
            return false;
        }
    }
    if (parser.isSet(modelOption)) {
        options.overrideModel = true;
        if (!parseModelName(parser.value(modelOption).toStdString(), options.model)) {
            error = QStringLiteral("--model: must be book, impulse or exact");
            return false;
        }
    }
    if (parser.isSet(compareOption)) {
        ModelKind compare = ModelKind::Exact;
        if (!parseModelName(parser.value(compareOption).toStdString(), compare)) {
            error = QStringLiteral("--compare: must be book, impulse or exact");
            return false;
        }
        if (!options.mainWindow) {
            error = QStringLiteral("--compare: needs --window main (the comparison belongs to the main window)");
            return false;
        }
        options.compare = compare;
    }
    options.csv = parser.isSet(csvOption);
    return true;
}

} // namespace

int main(int argc, char *argv[])
{
    QApplication app(argc, argv);
    // Settings of the benchmark's main window stay apart from the user's.
    QCoreApplication::setOrganizationName(QStringLiteral("Marbles"));
    QCoreApplication::setApplicationName(QStringLiteral("marbles-renderbench"));

    Options options;
    QString error;
    if (!parseOptions(app, options, error)) {
        std::fprintf(stderr, "marbles-renderbench: %s\n", qPrintable(error));
        return 2;
    }

    QTextStream out(stdout);
    if (options.csv) {
        out << "n,vectors,vectors_drawn,hit_marbles,scale,trails,window,items,antialias,frames,model_ms,physics_ms,paint_ms,frame_ms,paint_only_ms,"
               "frame_cpu_ms,paint_only_cpu_ms,physics_paint_fps,paint_fps,paints_per_frame,plot_refresh_ms\n";
    } else {
        out << "marbles-renderbench: platform " << QGuiApplication::platformName() << ", "
            << (options.mainWindow ? "main window " : "stage view ") << options.size.width() << "x"
            << options.size.height() << ", crowd seed " << options.seed << ", " << options.frames
            << " frames per count (medians)";
        if (options.compare)
            out << ", compared with " << QString::fromStdString(std::string(modelName(*options.compare)));
        out << "\n";
    }
    out.flush();
    for (int n : options.counts) {
        const Result r = measure(n, options);
        if (options.csv) {
            out << r.n << "," << (options.vectors ? "on" : "off") << "," << (r.vectorsDrawn ? "yes" : "no") << ","
                << r.hitMarbles << "," << QString::number(r.scale, 'f', 4) << ","
                << r.trails << ","
                << (options.mainWindow ? "main" : "stage")
                << "," << r.items << "," << (r.antialias ? "on" : "off") << "," << options.frames << ","
                << QString::number(r.modelMs, 'f', 3) << "," << QString::number(r.physicsMs, 'f', 3) << "," << QString::number(r.paintMs, 'f', 3) << ","
                << QString::number(r.frameMs, 'f', 3) << "," << QString::number(r.paintOnlyMs, 'f', 3) << ","
                << QString::number(r.frameCpuMs, 'f', 3) << "," << QString::number(r.paintOnlyCpuMs, 'f', 3) << ","
                << QString::number(fps(r.frameMs), 'f', 1) << "," << QString::number(fps(r.paintOnlyMs), 'f', 1)
                << "," << QString::number(r.paintsPerFrame, 'f', 2) << ","
                << (r.plotRefreshMs >= 0.0 ? QString::number(r.plotRefreshMs, 'f', 3) : QString()) << "\n";
        } else {
            out << "n=" << r.n << " vectors=" << (options.vectors ? "on" : "off")
                << (options.vectors && !r.vectorsDrawn ? " (too short to draw at this zoom)" : "") << " hit="
                << r.hitMarbles << " scale=" << QString::number(r.scale, 'f', 3) << " viewport="
                << r.viewport.width() << "x" << r.viewport.height() << " items=" << r.items
                << " antialias=" << (r.antialias ? "on" : "off")
                << " trails=" << r.trails
                << (options.selected >= 0 ? QStringLiteral(" selected=%1").arg(options.selected) : QString()) << "\n"
                << "  physics+paint " << QString::number(fps(r.frameMs), 'f', 1) << " fps ("
                << QString::number(r.frameMs, 'f', 2) << " ms: physics+sync " << QString::number(r.physicsMs, 'f', 2)
                << " (model alone " << QString::number(r.modelMs, 'f', 2) << ")"
                << ", events+paint " << QString::number(r.paintMs, 'f', 2) << "); processor time "
                << QString::number(r.frameCpuMs, 'f', 2) << " ms = " << QString::number(fps(r.frameCpuMs), 'f', 1)
                << " fps\n"
                << "  paint alone   " << QString::number(fps(r.paintOnlyMs), 'f', 1) << " fps ("
                << QString::number(r.paintOnlyMs, 'f', 2) << " ms); processor time "
                << QString::number(r.paintOnlyCpuMs, 'f', 2) << " ms = " << QString::number(fps(r.paintOnlyCpuMs), 'f', 1)
                << " fps\n"
                << "  paints per frame " << QString::number(r.paintsPerFrame, 'f', 2) << "\n"
                << "  step-back history " << r.historyFrames << " frames ("
                << QString::number(static_cast<double>(r.historyBytes) / (1024.0 * 1024.0), 'f', 1) << " MiB)\n";
            if (r.plotRefreshMs >= 0.0) {
                out << "  plot refresh " << QString::number(r.plotRefreshMs, 'f', 2) << " ms (" << r.plotLines
                    << " lines of " << r.plotSamples << " samples, chart drawn; every "
                    << PlotDock::kRefreshIntervalMs << " ms while running)\n";
            }
        }
        out.flush();
    }
    return 0;
}
