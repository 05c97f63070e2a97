// CompareRun: a second model run beside the document's. The oracle is an independent World
// of the comparison model stepped frame by frame from the same state: the comparison must match
// it bit for bit, and the gap must be the largest distance between the two worlds' marbles.
// The last tests drive the main window's "Compare with" box with QTest keys.

#include "core/presets.h"
#include "ui/comparerun.h"
#include "ui/mainwindow.h"
#include "ui/marblefielditem.h"
#include "ui/plotdock.h"
#include "ui/prompts.h"
#include "ui/scenedocument.h"
#include "ui/stageview.h"
#include "tests/ui/bothruns.h"

#include <QAction>
#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QGraphicsScene>
#include <QLabel>
#include <QChart>
#include <QChartView>
#include <QLegend>
#include <QLegendMarker>
#include <QLineSeries>
#include <QMenu>
#include <QSettings>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

using namespace marbles;

Q_DECLARE_METATYPE(marbles::ModelKind)

namespace {

World presetWorld(const char *id, ModelKind model)
{
    World world;
    if (!makePreset(id, world))
        qFatal("no preset %s", id);
    world.params.model = model;
    return world;
}

/// The gap as the brief defines it: max over marbles of |p_a - p_b|, px; -1 when none differ.
struct Gap {
    double px = 0.0;
    int marble = -1;
};

Gap gapBetween(const World &a, const World &b)
{
    Gap gap;
    for (int i = 0; i < a.marbleCount(); ++i) {
        const double dx = a.position[i].x - b.position[i].x;
        const double dy = a.position[i].y - b.position[i].y;
        const double d = std::sqrt(dx * dx + dy * dy);
        if (d > gap.px) {
            gap.px = d;
            gap.marble = i;
        }
    }
    return gap;
}

/// True when `compare` is `document` with only the model changed (the state a restart copies).
bool isCopyOf(const World &compare, const World &document, ModelKind model)
{
    Params params = document.params;
    params.model = model;
    return compare.params == params && compare.stage == document.stage && compare.frame == document.frame
        && compare.position == document.position && compare.velocity == document.velocity
        && compare.acceleration == document.acceleration && compare.radius == document.radius
        && compare.mass == document.mass && compare.pins == document.pins && compare.pushes == document.pushes;
}

bool sameDynamics(const World &a, const World &b)
{
    return a.frame == b.frame && a.position == b.position && a.velocity == b.velocity
        && a.acceleration == b.acceleration;
}

int ghostCount(QGraphicsScene *scene)
{
    int n = 0;
    for (QGraphicsItem *item : scene->items()) {
        if (item->type() == MarbleFieldItem::Type
            && static_cast<MarbleFieldItem *>(item)->style() == MarbleFieldItem::Style::Ghost)
            ++n;
    }
    return n;
}

/// Answers the window's questions without a dialog (closing with unsaved edits discards them).
class DiscardPrompts : public Prompts {
public:
    SaveChoice askSaveChanges(QWidget *, const QString &, std::int64_t, const QString &) override
    {
        return SaveChoice::Discard;
    }
    SaveFrame askSaveFrame(QWidget *, const QString &, std::int64_t, std::int64_t, const QString &) override
    {
        return SaveFrame::Cancel;
    }
    bool askRecover(QWidget *, const QString &) override { return false; }
    QString askOpenFileName(QWidget *, const QString &) override { return {}; }
    QString askSaveFileName(QWidget *, const QString &) override { return {}; }
    void showError(QWidget *, const QString &, const QString &) override {}
};

} // namespace

class TestCompareRun : public QObject {
    Q_OBJECT

private Q_SLOTS:
    void initTestCase();

    void offByDefault();
    void sameModelGapIsZero_data();
    void sameModelGapIsZero();
    void matchesIndependentRun_data();
    void matchesIndependentRun();
    void bookDriftsAwayFromExact();
    void restartsFromDocument_data();
    void restartsFromDocument();
    void stepsBackWithTheDocument();
    void stepsBackPastADeletedMarble();
    void deleteRedoneAfterStepBackKeepsItsFrame();
    void addUndoneGivesBackTheComparison();
    void randomSessionFollowsTheRules_data();
    void randomSessionFollowsTheRules();
    void forgottenFramesKeepOnlyTheLargestGap();
    void clickPushesBothModels();
    void heldMarbleIsFollowed();
    void waitsWhileParamsInvalid();
    void stopsWhenComparisonLeavesFiniteNumbers();
    void ghostsFollowTheComparison();
    void ghostsSurviveStageDestroyedFirst();
    void plotGetsCompareSeries();
    void plotLegendListsMarblesThenModels();
    void plotExportsAndDescribesCompareLines();

    void boxOffersTheOtherModels_data();
    void boxOffersTheOtherModels();
    void choosingWithKeysShowsGhostsReadoutAndPlot();
    void menuActionsAndBoxAgree();
    void sceneSwitchingToComparedModelEndsComparison();

private:
    std::unique_ptr<MainWindow> makeWindow();
};

void TestCompareRun::initTestCase()
{
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setOrganizationName(QStringLiteral("MarblesTests"));
    QCoreApplication::setApplicationName(QStringLiteral("tst_comparerun"));
    QSettings().clear();
    QDir(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)).removeRecursively();
}

void TestCompareRun::offByDefault()
{
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    QGraphicsScene scene;
    compare.setStage(&scene);
    QSignalSpy advanced(&compare, &CompareRun::advanced);
    doc.advance(30);
    doc.stepBack();
    QVERIFY(!compare.isActive());
    QVERIFY(!compare.isTracking());
    QVERIFY(compare.world() == nullptr);
    QVERIFY(compare.ghostItem() == nullptr);
    QCOMPARE(ghostCount(&scene), 0);
    QCOMPARE(advanced.count(), 0);
    QVERIFY(compare.summary().isEmpty());
}

void TestCompareRun::sameModelGapIsZero_data()
{
    QTest::addColumn<QString>("preset");
    QTest::addColumn<ModelKind>("model");
    QTest::addRow("four-marbles, book") << "four-marbles" << ModelKind::Book;
    QTest::addRow("four-marbles, exact") << "four-marbles" << ModelKind::Exact;
    QTest::addRow("pins, impulse") << "pins" << ModelKind::Impulse;
    QTest::addRow("masses, exact") << "masses" << ModelKind::Exact;
    QTest::addRow("newtons-cradle, book") << "newtons-cradle" << ModelKind::Book;
    QTest::addRow("pachinko, impulse") << "pachinko" << ModelKind::Impulse;
}

void TestCompareRun::sameModelGapIsZero()
{
    QFETCH(QString, preset);
    QFETCH(ModelKind, model);
    SceneDocument doc;
    doc.resetScene(presetWorld(qPrintable(preset), model));
    CompareRun compare(&doc);
    compare.setModel(model);
    QVERIFY(compare.isTracking());

    // Every frame, whether simulated one at a time or in a batch as the run loop does.
    constexpr int kFrames = 400;
    std::vector<double> gaps;
    connect(&compare, &CompareRun::advanced, &compare, [&] { gaps.push_back(compare.currentGapPx()); });
    for (int f = 0; f < kFrames / 2; ++f)
        doc.advance(1);
    doc.advance(kFrames / 2);

    QCOMPARE(static_cast<int>(gaps.size()), kFrames);
    for (std::size_t f = 0; f < gaps.size(); ++f)
        QVERIFY2(gaps[f] == 0.0, qPrintable(QStringLiteral("frame %1: gap %2").arg(f + 1).arg(gaps[f])));
    QVERIFY(sameDynamics(*compare.world(), doc.world()));
    QVERIFY(compare.largestGapPx() == 0.0);
    QCOMPARE(compare.largestGapMarble(), -1);
}

void TestCompareRun::matchesIndependentRun_data()
{
    QTest::addColumn<QString>("preset");
    QTest::addColumn<ModelKind>("sceneModel");
    QTest::addColumn<ModelKind>("compareModel");
    QTest::addColumn<int>("frames");
    QTest::addRow("four-marbles, book vs exact") << "four-marbles" << ModelKind::Book << ModelKind::Exact << 300;
    QTest::addRow("four-marbles, book vs impulse") << "four-marbles" << ModelKind::Book << ModelKind::Impulse << 300;
    QTest::addRow("pins, exact vs book") << "pins" << ModelKind::Exact << ModelKind::Book << 250;
    QTest::addRow("masses, impulse vs exact") << "masses" << ModelKind::Impulse << ModelKind::Exact << 250;
    QTest::addRow("pachinko, book vs exact") << "pachinko" << ModelKind::Book << ModelKind::Exact << 200;
}

void TestCompareRun::matchesIndependentRun()
{
    QFETCH(QString, preset);
    QFETCH(ModelKind, sceneModel);
    QFETCH(ModelKind, compareModel);
    QFETCH(int, frames);
    const World start = presetWorld(qPrintable(preset), sceneModel);
    SceneDocument doc;
    doc.resetScene(start);
    CompareRun compare(&doc);
    compare.setModel(compareModel);
    QVERIFY(compare.isTracking());
    QVERIFY(isCopyOf(*compare.world(), doc.world(), compareModel));

    World oracle = start;
    oracle.params.model = compareModel;
    Gap largest;
    std::int64_t largestFrame = 0;
    for (int f = 1; f <= frames; ++f) {
        doc.advance(1);
        QVERIFY(oracle.step().finite);
        QVERIFY2(sameDynamics(*compare.world(), oracle), qPrintable(QStringLiteral("frame %1").arg(f)));
        const Gap now = gapBetween(doc.world(), oracle);
        QCOMPARE_LE(std::abs(compare.currentGapPx() - now.px), 1e-12);
        QCOMPARE(compare.currentGapMarble(), now.marble);
        if (now.px > largest.px) {
            largest = now;
            largestFrame = f;
        }
    }
    QCOMPARE_LE(std::abs(compare.largestGapPx() - largest.px), 1e-12);
    QCOMPARE(compare.largestGapMarble(), largest.marble);
    QCOMPARE(compare.largestGapFrame(), largestFrame);
    QCOMPARE(compare.startFrame(), 0);
    // Two different models on these scenes do drift apart: the oracle is not trivially zero.
    QCOMPARE_GT(largest.px, 0.5);
}

void TestCompareRun::bookDriftsAwayFromExact()
{
    // The chapter's four marbles. Already in frame 1 the two disagree: the book moves the pushed
    // marble by its whole new velocity (7 px), the exact model lets drag act during the frame
    // (7 (1 - e^-lambda) / lambda = 7 * 0.1 / 0.1054 = 6.64 px). Then the book's collision shares
    // the speed its own way, the exact model by momentum and energy, and the gap grows until
    // friction stops the marbles; the second scripted push (frame 150) makes it grow again.
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    std::vector<double> largest;
    connect(&compare, &CompareRun::advanced, &compare, [&] { largest.push_back(compare.largestGapPx()); });
    doc.advance(300);
    QCOMPARE(static_cast<int>(largest.size()), 300);
    for (std::size_t f = 1; f < largest.size(); ++f)
        QCOMPARE_GE(largest[f], largest[f - 1]);
    QCOMPARE_LE(std::abs(largest[0] - (7.0 - 7.0 * 0.1 / -std::log(1.0 - 0.1))), 1e-9);
    QCOMPARE_GT(largest[59], 5.0 * largest[4]);
    QCOMPARE_GT(largest[299], largest[149] + 1.0);
    QVERIFY(compare.summary().startsWith(QStringLiteral("Compare: exact - largest gap ")));
    QVERIFY2(compare.summary().contains(QStringLiteral("(marble %1, frame %2)")
                                            .arg(compare.largestGapMarble())
                                            .arg(compare.largestGapFrame())),
             qPrintable(compare.summary()));
}

void TestCompareRun::restartsFromDocument_data()
{
    QTest::addColumn<QString>("action");
    QTest::addRow("rewind") << "rewind";
    QTest::addRow("new scene") << "new scene";
    QTest::addRow("parameter edit") << "parameter edit";
    QTest::addRow("marble moved") << "marble moved";
    QTest::addRow("undo") << "undo";
    QTest::addRow("pin dragged") << "pin dragged";
}

void TestCompareRun::stepsBackWithTheDocument()
{
    // Step Back takes the comparison back to the document's frame in its own state there (not a
    // copy of the document's), with the gaps of that frame; running on repeats the same frames.
    SceneDocument doc;
    doc.resetScene(presetWorld("masses", ModelKind::Book));
    CompareRun compare(&doc);
    QGraphicsScene scene;
    compare.setStage(&scene);
    compare.setModel(ModelKind::Exact);
    struct Seen {
        World world;
        double gap;
        int gapMarble;
        double largest;
        std::int64_t largestFrame;
    };
    std::vector<Seen> seen; // seen[f]: the comparison after frame f
    seen.push_back({*compare.world(), 0.0, -1, 0.0, 0});
    for (int f = 1; f <= 90; ++f) {
        doc.advance(1);
        seen.push_back({*compare.world(), compare.currentGapPx(), compare.currentGapMarble(), compare.largestGapPx(),
                        compare.largestGapFrame()});
    }
    QCOMPARE_GT(seen[90].largest, 0.0);
    QSignalSpy restarted(&compare, &CompareRun::restarted);
    for (int back = 89; back >= 30; back -= 1) {
        QVERIFY(doc.stepBack());
        if (back % 20 != 0 && back != 89)
            continue;
        QVERIFY(compare.isTracking());
        QVERIFY(sameDynamics(*compare.world(), seen[static_cast<std::size_t>(back)].world));
        QVERIFY(!isCopyOf(*compare.world(), doc.world(), ModelKind::Exact) || seen[static_cast<std::size_t>(back)].gap == 0.0);
        QCOMPARE(compare.startFrame(), std::int64_t(0));
        QVERIFY(compare.currentGapPx() == seen[static_cast<std::size_t>(back)].gap);
        QCOMPARE(compare.currentGapMarble(), seen[static_cast<std::size_t>(back)].gapMarble);
        QVERIFY(compare.largestGapPx() == seen[static_cast<std::size_t>(back)].largest);
        QCOMPARE(compare.largestGapFrame(), seen[static_cast<std::size_t>(back)].largestFrame);
        QCOMPARE(ghostCount(&scene), 1);
    }
    QCOMPARE(restarted.count(), 0);
    QCOMPARE(doc.world().frame, std::int64_t(30));
    doc.advance(60);
    QVERIFY(sameDynamics(*compare.world(), seen[90].world));
    QVERIFY(compare.largestGapPx() == seen[90].largest);
    QCOMPARE(compare.largestGapFrame(), seen[90].largestFrame);

    // Back to the start: a restart there, which is the same state.
    QVERIFY(doc.rewind());
    QCOMPARE(restarted.count(), 1);
    QVERIFY(sameDynamics(*compare.world(), seen[0].world));
    QVERIFY(compare.largestGapPx() == 0.0);
}

void TestCompareRun::stepsBackPastADeletedMarble()
{
    // A marble deleted mid-run: the comparison starts again there, and Step Back past the delete
    // returns to it as it was at each frame, without that marble, as the document's frames are
    // (it had started again from the document's state there: "gap 0", both models' totals
    // alike). The delete undone puts the marble back into its frames too.
    SceneDocument doc;
    doc.resetScene(presetWorld("masses", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    auto [ours, theirs] = test::runBoth(doc, compare, 60);
    const int gone = 0; // the marble with the largest gap (the book's light marble 0)
    QCOMPARE(compare.largestGapMarble(), gone);
    const auto without = [gone](World w) {
        w.removeMarble(gone);
        return w;
    };
    // The largest gap from frame 1 to `last` over the marbles of `a` and `b`.
    const auto largestUpTo = [](const std::vector<World> &a, const std::vector<World> &b, int last) {
        double largest = 0.0;
        for (int f = 1; f <= last; ++f)
            largest = std::max(largest, gapBetween(a[f], b[f]).px);
        return largest;
    };
    doc.removeMarble(gone);
    QVERIFY(compare.isTracking());
    QCOMPARE(compare.startFrame(), std::int64_t(60));
    QVERIFY(isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    QCOMPARE(compare.largestGapPx(), 0.0);

    for (int f = 59; f >= 40; --f)
        QVERIFY(doc.stepBack());
    QVERIFY(compare.isTracking());
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), without(theirs[40])));
    QVERIFY(!isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    const Gap at40 = gapBetween(doc.world(), *compare.world());
    QCOMPARE_GT(at40.px, 1.0);
    QVERIFY(compare.currentGapPx() == at40.px);
    QCOMPARE(compare.currentGapMarble(), at40.marble);
    std::vector<World> oursWithout;
    std::vector<World> theirsWithout;
    for (int f = 0; f <= 40; ++f) {
        oursWithout.push_back(without(ours[f]));
        theirsWithout.push_back(without(theirs[f]));
    }
    const double largest = largestUpTo(oursWithout, theirsWithout, 40);
    QCOMPARE_LE(std::abs(compare.largestGapPx() - largest), 1e-9 * largest);

    // Undone here: the marble comes back as it was at frame 40, in both models (the comparison
    // had started again from the scene's state there, its own lost), and Step Back returns to
    // the comparison's frames with the marble in them.
    doc.undoStack()->undo();
    QCOMPARE(doc.world().frame, std::int64_t(40));
    QVERIFY(sameDynamics(doc.world(), ours[40]));
    QVERIFY(compare.isTracking());
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), theirs[40]));
    QVERIFY(compare.currentGapPx() == gapBetween(ours[40], theirs[40]).px);
    QCOMPARE_LE(std::abs(compare.largestGapPx() - largestUpTo(ours, theirs, 40)), 1e-9 * largestUpTo(ours, theirs, 40));
    for (int f = 39; f >= 30; --f)
        QVERIFY(doc.stepBack());
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), theirs[30]));
    QVERIFY(compare.currentGapPx() == gapBetween(ours[30], theirs[30]).px);
    QCOMPARE_LE(std::abs(compare.largestGapPx() - largestUpTo(ours, theirs, 30)), 1e-9 * largestUpTo(ours, theirs, 30));
    // And on from there, the same run as before the delete.
    doc.advance(30);
    QVERIFY(sameDynamics(doc.world(), ours[60]));
    QVERIFY(sameDynamics(*compare.world(), theirs[60]));

    // Deleted and undone at once: the comparison is as it was, its start and gaps too.
    const double largest60 = compare.largestGapPx();
    const int largestMarble = compare.largestGapMarble();
    doc.removeMarble(2);
    QCOMPARE(compare.startFrame(), std::int64_t(60));
    doc.undoStack()->undo();
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), theirs[60]));
    QVERIFY(compare.largestGapPx() == largest60);
    QCOMPARE(compare.largestGapMarble(), largestMarble);
    QVERIFY(compare.currentGapPx() == gapBetween(ours[60], theirs[60]).px);
    doc.advance(1);
    World next = theirs[60];
    QVERIFY(next.step().finite);
    QVERIFY(sameDynamics(*compare.world(), next));
}

void TestCompareRun::addUndoneGivesBackTheComparison()
{
    // A marble added mid-run starts the comparison again there (the marble is in both models);
    // the add undone later goes back to its frame with the comparison as it was there, its start
    // and gaps too, and Step Back goes on through the comparison's own frames before it (it had
    // started again at the add, "gap 0", and Step Back stopped there).
    SceneDocument doc;
    doc.resetScene(presetWorld("masses", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    auto [ours, theirs] = test::runBoth(doc, compare, 60);
    const double largest60 = compare.largestGapPx();
    const int largestMarble = compare.largestGapMarble();
    const std::int64_t largestFrame = compare.largestGapFrame();
    QCOMPARE_GT(largest60, 1.0);
    QVERIFY(doc.addMarble({60.0, 60.0}, 12.0).isEmpty());
    QVERIFY(compare.isTracking());
    QCOMPARE(compare.startFrame(), std::int64_t(60));
    QVERIFY(isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    QCOMPARE(compare.largestGapPx(), 0.0);
    doc.advance(20);
    QCOMPARE(compare.world()->marbleCount(), doc.world().marbleCount());

    doc.undoStack()->undo();
    QCOMPARE(doc.world().frame, std::int64_t(60));
    QVERIFY(sameDynamics(doc.world(), ours[60]));
    QVERIFY(compare.isTracking());
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), theirs[60]));
    QVERIFY(compare.largestGapPx() == largest60);
    QCOMPARE(compare.largestGapMarble(), largestMarble);
    QCOMPARE(compare.largestGapFrame(), largestFrame);
    QVERIFY(compare.currentGapPx() == gapBetween(ours[60], theirs[60]).px);
    for (int f = 59; f >= 30; --f) {
        QVERIFY2(doc.stepBack(), qPrintable(QStringLiteral("frame %1").arg(f)));
        QVERIFY2(sameDynamics(*compare.world(), theirs[static_cast<std::size_t>(f)]), qPrintable(QStringLiteral("frame %1").arg(f)));
        QVERIFY(compare.currentGapPx() == gapBetween(ours[static_cast<std::size_t>(f)], theirs[static_cast<std::size_t>(f)]).px);
    }
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    // And on from there, the same run as before the add.
    doc.advance(30);
    QVERIFY(sameDynamics(doc.world(), ours[60]));
    QVERIFY(sameDynamics(*compare.world(), theirs[60]));
    QVERIFY(compare.largestGapPx() == largest60);
    doc.advance(1);
    World next = theirs[60];
    QVERIFY(next.step().finite);
    QVERIFY(sameDynamics(*compare.world(), next));

    // Added at once and undone at once: as it was.
    doc.undoStack()->redo(); // added again at frame 60: back there first
    QCOMPARE(doc.world().frame, std::int64_t(60));
    QCOMPARE(compare.startFrame(), std::int64_t(60));
    doc.undoStack()->undo();
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), theirs[60]));
    QVERIFY(compare.largestGapPx() == largest60);

    // Another marble deleted after the add, both undone: the gaps of the frames before the add,
    // set aside while the delete measured the kept frames' gaps again, are as they were (they
    // had become 0: "largest gap 0 px" at frame 55; a regression tester's finding).
    doc.undoStack()->redo();
    doc.advance(10);
    doc.removeMarble(1);
    doc.advance(5);
    doc.undoStack()->undo();
    doc.undoStack()->undo();
    QCOMPARE(doc.world().frame, std::int64_t(60));
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(compare.largestGapPx() == largest60);
    QCOMPARE(compare.largestGapMarble(), largestMarble);
    QCOMPARE(compare.largestGapFrame(), largestFrame);
    for (int f = 59; f >= 55; --f)
        QVERIFY(doc.stepBack());
    double largest55 = 0.0;
    for (std::size_t f = 1; f <= 55; ++f)
        largest55 = std::max(largest55, gapBetween(ours[f], theirs[f]).px);
    QCOMPARE_GT(largest55, 1.0);
    QVERIFY(compare.largestGapPx() == largest55);
    QVERIFY(compare.currentGapPx() == gapBetween(ours[55], theirs[55]).px);
}

void TestCompareRun::deleteRedoneAfterStepBackKeepsItsFrame()
{
    // Delete at 60, Step Back to 50, undo, redo: the redo runs on to frame 60 and deletes there
    // (it deleted at 50 while the Undo History said 60, and its undo from later in the run went
    // back to 60, where the kept frames had no place for the marble: the plot and the comparison
    // started again; a regression tester's finding). Undone from frame 80, the comparison is its
    // own again at 60.
    SceneDocument doc;
    doc.resetScene(presetWorld("masses", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    const std::vector<World> theirs = test::runBoth(doc, compare, 60).theirs;
    const double largest60 = compare.largestGapPx();
    doc.removeMarble(2);
    QCOMPARE(doc.undoStack()->undoText(), QStringLiteral("Delete marble 2 (heavy mover) at frame 60"));
    for (int f = 59; f >= 50; --f)
        QVERIFY(doc.stepBack());
    doc.undoStack()->undo();
    QCOMPARE(doc.world().frame, std::int64_t(50));
    QCOMPARE(doc.world().marbleCount(), 5);
    doc.undoStack()->redo();
    QCOMPARE(doc.world().frame, std::int64_t(60));
    QCOMPARE(doc.world().marbleCount(), 4);
    QCOMPARE(doc.undoStack()->undoText(), QStringLiteral("Delete marble 2 (heavy mover) at frame 60"));
    QCOMPARE(compare.startFrame(), std::int64_t(60));
    doc.advance(20);
    doc.undoStack()->undo();
    QCOMPARE(doc.world().frame, std::int64_t(60));
    QCOMPARE(doc.world().marbleCount(), 5);
    QVERIFY(compare.isTracking());
    QCOMPARE(compare.startFrame(), std::int64_t(0));
    QVERIFY(sameDynamics(*compare.world(), theirs[60]));
    QVERIFY(compare.largestGapPx() == largest60);
    QVERIFY(doc.stepBack()); // and the frames before it are still kept
    QVERIFY(sameDynamics(*compare.world(), theirs[59]));
}

void TestCompareRun::randomSessionFollowsTheRules_data()
{
    QTest::addColumn<QString>("preset");
    QTest::addColumn<ModelKind>("own");
    QTest::addColumn<ModelKind>("compared");
    QTest::addColumn<int>("seed");
    QTest::addRow("masses, book against exact") << "masses" << ModelKind::Book << ModelKind::Exact << 1;
    QTest::addRow("pins, book against impulse") << "pins" << ModelKind::Book << ModelKind::Impulse << 2;
    QTest::addRow("newtons-cradle, exact against book") << "newtons-cradle" << ModelKind::Exact << ModelKind::Book << 3;
    QTest::addRow("pachinko, impulse against exact") << "pachinko" << ModelKind::Impulse << ModelKind::Exact << 4;
    QTest::addRow("four-marbles, book against exact") << "four-marbles" << ModelKind::Book << ModelKind::Exact << 5;
}

void TestCompareRun::randomSessionFollowsTheRules()
{
    // A teacher's session with the comparison on: runs of a few frames, Step Back, Back to
    // Start, clicks on marbles, edits and undos, in a random order. The oracle applies the
    // class's rules itself (comparerun.h): the comparison is its own model's World stepped
    // with the document's frames, given the same clicks; Step Back returns it to its own state
    // at that frame, or restarts it there from the document's when it started later; an edit
    // or undo starts it again from the document's state at that frame, keeping its earlier
    // frames, to which Step Back returns past the edit, except an undo at the edit's frame with
    // the comparison still on the start the edit made there (or on later ones made there), which
    // gives back the comparison before the edit and its starts, and an undo that leaves the scene
    // as the run shown had it (an edit it never had: stepped back before the edit's frame), which
    // changes nothing. After every action the comparison must hold the oracle's bits, and its
    // largest gap must be the largest since its latest start.
    QFETCH(QString, preset);
    QFETCH(ModelKind, own);
    QFETCH(ModelKind, compared);
    QFETCH(int, seed);
    SceneDocument doc;
    doc.resetScene(presetWorld(qPrintable(preset), own));
    CompareRun compare(&doc);
    compare.setModel(compared);
    SplitMix64 rng(static_cast<std::uint64_t>(seed));

    World oracle;
    std::map<std::int64_t, World> oracleAt; // the oracle after each frame of its current run
    std::map<std::int64_t, double> gapAt;   // the gap after each of those frames
    std::vector<std::int64_t> starts;       // the frames it started at, the latest last
    const auto restartOracle = [&] {
        oracle = doc.world();
        oracle.params.model = compared;
        oracleAt = {{oracle.frame, oracle}};
        starts = {oracle.frame};
        gapAt.clear();
    };
    restartOracle();
    // For each edit command (its index in the undo stack), the comparison and its starts before it.
    struct OracleEdit {
        int command = 0;
        std::int64_t frame = 0;
        World before;
        std::vector<std::int64_t> startsBefore;
    };
    std::vector<OracleEdit> edits;
    // The document at each frame of the run shown, as it was run or edited there.
    std::map<std::int64_t, World> docAt{{doc.world().frame, doc.world()}};
    const auto sameScene = [](const World &a, const World &b) {
        return sameDynamics(a, b) && a.radius == b.radius && a.mass == b.mass && a.params == b.params && a.pushes == b.pushes;
    };
    int unchanged = 0;
    // The document went back to an earlier frame of its run (Step Back, or an undo that goes to
    // its edit's frame first): the comparison too.
    const auto backTo = [&] {
        const World &w = doc.world();
        docAt.erase(docAt.upper_bound(w.frame), docAt.end());
        while (starts.size() > 1 && w.frame < starts.back())
            starts.pop_back();
        const auto kept = oracleAt.find(w.frame);
        if (w.frame < starts.front() || (w.frame == starts.front() && starts.size() == 1) || kept == oracleAt.end()) {
            restartOracle();
            edits.clear(); // (a restart forgets what the undos of edits would give back)
        } else {
            // Its state then, with the parameters of now (Step Back does not undo edits).
            oracle = kept->second;
            oracle.params = w.params;
            oracle.params.model = compared;
            oracleAt.erase(oracleAt.upper_bound(w.frame), oracleAt.end());
            gapAt.erase(gapAt.upper_bound(w.frame), gapAt.end());
        }
    };
    int restarts = 0;
    int backs = 0;
    int takenBack = 0;
    bool lastWasEdit = false;
    for (int action = 0; action < 300; ++action) {
        const World &w = doc.world();
        const int marble = rng.below(w.marbleCount());
        QString what;
        // (Right after an edit, often its undo, where the undo gives the comparison back.)
        switch (lastWasEdit && rng.below(3) == 0 ? 7 : rng.below(8)) {
        case 0:
        case 1:
        case 2: {
            const int frames = 1 + rng.below(15);
            what = QStringLiteral("%1 frames").arg(frames);
            for (int f = 0; f < frames; ++f) {
                doc.step();
                docAt[w.frame] = w;
                QVERIFY(oracle.step().finite);
                oracleAt[oracle.frame] = oracle;
                gapAt[oracle.frame] = gapBetween(w, oracle).px;
            }
            break;
        }
        case 3:
        case 4: {
            const int frames = 1 + rng.below(20);
            what = QStringLiteral("back %1 frames").arg(frames);
            for (int f = 0; f < frames && doc.stepBack(); ++f) {
                ++backs;
                backTo();
            }
            break;
        }
        case 5: {
            // A click: the same push for the comparison marble.
            what = QStringLiteral("click on marble %1").arg(marble);
            const Vec2 p = w.position[static_cast<std::size_t>(marble)];
            doc.pushMarble(marble, {p.x + rng.uniform(-10.0, 10.0), p.y + rng.uniform(-10.0, 10.0)});
            oracle.acceleration = w.acceleration;
            oracleAt[oracle.frame] = oracle;
            docAt[w.frame] = w;
            break;
        }
        case 6:
            what = QStringLiteral("back to start");
            if (doc.rewind()) {
                restartOracle(); // the start is before any frame the comparison ran
                edits.clear();
                docAt = {{w.frame, w}};
            }
            break;
        default: {
            QString error;
            const OracleEdit before{0, w.frame, oracle, starts};
            if (doc.undoStack()->canUndo() && (lastWasEdit || rng.below(3) == 0)) {
                what = QStringLiteral("undo");
                const int command = doc.undoStack()->index() - 1;
                const std::int64_t frameBefore = w.frame;
                const World live = w;
                doc.undoStack()->undo();
                // A marble's edit undone later in the run takes the scene back to its frame first,
                // as Step Back would, and the comparison with it.
                if (w.frame < frameBefore)
                    backTo();
                const auto found = std::find_if(edits.rbegin(), edits.rend(),
                                                [command](const OracleEdit &e) { return e.command == command; });
                if (found != edits.rend()) {
                    const OracleEdit e = *found;
                    edits.erase(std::prev(found.base()), edits.end());
                    const std::size_t n = e.startsBefore.size();
                    const bool onItsStart = w.frame == e.frame && starts.size() > n && starts[n - 1] == e.startsBefore.back()
                        && std::all_of(starts.begin() + static_cast<std::ptrdiff_t>(n), starts.end(),
                                       [&e](std::int64_t start) { return start == e.frame; });
                    if (onItsStart) {
                        oracle = e.before;
                        oracle.params = w.params;
                        oracle.params.model = compared;
                        oracle.acceleration = w.acceleration;
                        oracleAt[oracle.frame] = oracle;
                        starts = e.startsBefore;
                        if (oracle.frame > starts.front())
                            gapAt[oracle.frame] = gapBetween(w, oracle).px;
                        ++takenBack;
                        docAt[w.frame] = w;
                        break;
                    }
                }
                // Unchanged: the scene as it was just before the undo applied the edit's values (at
                // the frame it went back to, with the parameters of now).
                const auto shown = docAt.find(w.frame);
                World base = w.frame < frameBefore && shown != docAt.end() ? shown->second : live;
                base.params = live.params;
                if (sameScene(base, w)) {
                    ++unchanged; // the comparison runs on as it was
                    break;
                }
            } else if (rng.below(2) == 0) {
                what = QStringLiteral("velocity of marble %1").arg(marble);
                error = doc.setMarbleVelocity(marble, {rng.uniform(-6.0, 6.0), rng.uniform(-6.0, 6.0)});
            } else {
                what = QStringLiteral("friction");
                error = doc.setParam(QStringLiteral("friction"), QString::number(rng.uniform(0.0, 0.2), 'g', 17));
            }
            QVERIFY2(error.isEmpty(), qPrintable(error));
            // An edit (not one merged into the one before) keeps what its undo gives back.
            const int command = doc.undoStack()->index() - 1;
            if (what != QLatin1String("undo") && (edits.empty() || edits.back().command != command)) {
                edits.push_back(before);
                edits.back().command = command;
            }
            docAt[w.frame] = w;
            // Started again from the document's state at this frame, its earlier frames kept.
            oracle = doc.world();
            oracle.params.model = compared;
            oracleAt[oracle.frame] = oracle;
            gapAt.erase(oracle.frame);
            starts.push_back(oracle.frame);
            ++restarts;
            break;
        }
        }
        lastWasEdit = what.startsWith(QLatin1String("velocity")) || what == QLatin1String("friction");
        const QString where = QStringLiteral("action %1 (%2), frame %3").arg(action).arg(what).arg(w.frame);
        QVERIFY2(compare.isTracking(), qPrintable(where + QStringLiteral(": ") + compare.problem()));
        QVERIFY2(sameDynamics(*compare.world(), oracle), qPrintable(where));
        QVERIFY2(compare.world()->lastHit == oracle.lastHit, qPrintable(where));
        QCOMPARE(compare.startFrame(), starts.back());
        double largest = 0.0;
        for (const auto &[frame, gap] : gapAt) {
            if (frame > starts.back())
                largest = std::max(largest, gap);
        }
        QVERIFY2(std::abs(compare.largestGapPx() - largest) <= 1e-9 * std::max(1.0, largest),
                 qPrintable(where + QStringLiteral(": largest gap %1, expected %2").arg(compare.largestGapPx()).arg(largest)));
    }
    QVERIFY(backs > 20);
    QVERIFY(restarts > 5);
    QVERIFY(takenBack > 2);
}

void TestCompareRun::forgottenFramesKeepOnlyTheLargestGap()
{
    // A long run of a large scene: the comparison's history forgets its oldest frames past its
    // byte budget, and so does its list of gaps, but Step Back still finds the gaps it had.
    SceneDocument doc;
    World crowd = makeCrowd(20000, 3);
    crowd.params.model = ModelKind::Book;
    doc.resetScene(crowd);
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    struct Seen {
        double gap;
        double largest;
        std::int64_t largestFrame;
    };
    std::vector<Seen> seen(1, Seen{0.0, 0.0, 0});
    constexpr int frames = 330;
    for (int f = 1; f <= frames; ++f) {
        doc.advance(1);
        seen.push_back({compare.currentGapPx(), compare.largestGapPx(), compare.largestGapFrame()});
    }
    QVERIFY(compare.isTracking());
    const auto kept = static_cast<std::int64_t>(doc.history().size());
    QCOMPARE_LT(kept, frames); // the document's history forgot some frames (the comparison's too)
    // Its own history keeps more frames than the document's (the book model's frames carry
    // more collision records), but not all of them, and neither does the list of gaps.
    QCOMPARE_GE(compare.keptGapCount(), std::size_t(kept));
    QCOMPARE_LT(compare.keptGapCount(), std::size_t(frames));
    QSignalSpy restarted(&compare, &CompareRun::restarted);
    for (std::int64_t f = frames - 1; f >= frames - kept + 5; --f) {
        QVERIFY(doc.stepBack());
        QVERIFY(compare.currentGapPx() == seen[static_cast<std::size_t>(f)].gap);
        QVERIFY(compare.largestGapPx() == seen[static_cast<std::size_t>(f)].largest);
        QCOMPARE(compare.largestGapFrame(), seen[static_cast<std::size_t>(f)].largestFrame);
    }
    QCOMPARE(restarted.count(), 0);
}

void TestCompareRun::restartsFromDocument()
{
    QFETCH(QString, action);
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    if (action == QLatin1String("undo"))
        QVERIFY(doc.setParam(QStringLiteral("friction"), QStringLiteral("0.05")).isEmpty());
    doc.advance(120);
    QCOMPARE_GT(compare.largestGapPx(), 0.0);
    QSignalSpy restarted(&compare, &CompareRun::restarted);

    if (action == QLatin1String("rewind")) {
        QVERIFY(doc.rewind());
    } else if (action == QLatin1String("new scene")) {
        doc.resetScene(presetWorld("masses", ModelKind::Book));
    } else if (action == QLatin1String("parameter edit")) {
        QVERIFY(doc.setParam(QStringLiteral("friction"), QStringLiteral("0.2")).isEmpty());
    } else if (action == QLatin1String("marble moved")) {
        QVERIFY(doc.setMarblePosition(3, {650, 500}).isEmpty());
    } else if (action == QLatin1String("undo")) {
        doc.undoStack()->undo();
    } else if (action == QLatin1String("pin dragged")) {
        QVERIFY(doc.addPin({400, 100}).isEmpty());
        doc.beginPinDrag(0);
        doc.movePinDrag({420, 110});
        QCOMPARE(doc.world().pins[0], (Vec2{420, 110}));
    }

    QVERIFY(restarted.count() >= 1);
    QVERIFY(compare.isTracking());
    QVERIFY(isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    QCOMPARE(compare.startFrame(), doc.world().frame);
    QCOMPARE(compare.largestGapFrame(), doc.world().frame);
    QVERIFY(compare.currentGapPx() == 0.0);
    QVERIFY(compare.largestGapPx() == 0.0);
    const QString since = doc.world().frame > 0 ? QStringLiteral(" since frame %1").arg(doc.world().frame) : QString();
    QCOMPARE(compare.summary(), QStringLiteral("Compare: exact - largest gap 0 px") + since);

    // From there both run again, the comparison exactly as its model runs from that state.
    World oracle = doc.world();
    oracle.params.model = ModelKind::Exact;
    for (int f = 0; f < 60; ++f) {
        doc.advance(1);
        oracle.step();
    }
    QVERIFY(sameDynamics(*compare.world(), oracle));
    QCOMPARE_LE(std::abs(compare.currentGapPx() - gapBetween(doc.world(), oracle).px), 1e-12);
}

void TestCompareRun::clickPushesBothModels()
{
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Impulse);
    World oracle = doc.world();
    oracle.params.model = ModelKind::Impulse;
    for (int f = 0; f < 40; ++f) {
        doc.advance(1);
        oracle.step();
    }
    // A click on the small marble, below-left of its centre: the document computes the push from
    // its own marble, and the comparison marble gets the very same one.
    const Vec2 at{doc.world().position[1].x - 8.0, doc.world().position[1].y + 6.0};
    World clicked = doc.world();
    clicked.push(1, at);
    doc.pushMarble(1, at);
    QCOMPARE(doc.world().acceleration[1], clicked.acceleration[1]);
    oracle.acceleration[1] = clicked.acceleration[1];
    for (int f = 0; f < 80; ++f) {
        doc.advance(1);
        oracle.step();
    }
    QVERIFY(sameDynamics(*compare.world(), oracle));
    QCOMPARE(compare.startFrame(), 0);
}

void TestCompareRun::heldMarbleIsFollowed()
{
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    compare.setModel(ModelKind::Exact);
    doc.advance(30);
    QCOMPARE_GT(compare.largestGapPx(), 0.0);
    doc.beginHold(2);
    doc.moveHeld({500, 250});
    doc.advance(5);
    // The hand moves the marble outside either model: the comparison follows the document.
    QVERIFY(isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    QVERIFY(compare.largestGapPx() == 0.0);
    QVERIFY(doc.endHold({500, 250}).isEmpty());
    QVERIFY(isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    World oracle = doc.world();
    oracle.params.model = ModelKind::Exact;
    for (int f = 0; f < 20; ++f) {
        doc.advance(1);
        oracle.step();
    }
    QVERIFY(sameDynamics(*compare.world(), oracle));
}

void TestCompareRun::waitsWhileParamsInvalid()
{
    // Friction 1.5 is the book model's instability on show; the exact model cannot run with it.
    World start = presetWorld("four-marbles", ModelKind::Book);
    start.params.friction = 1.5;
    SceneDocument doc;
    doc.resetScene(start);
    CompareRun compare(&doc);
    QGraphicsScene scene;
    compare.setStage(&scene);
    compare.setModel(ModelKind::Exact);
    QVERIFY(compare.isActive());
    QVERIFY(!compare.isTracking());
    QVERIFY(compare.world() == nullptr);
    QVERIFY2(compare.problem().contains(QStringLiteral("friction")), qPrintable(compare.problem()));
    QVERIFY2(compare.summary().contains(QStringLiteral("not running")), qPrintable(compare.summary()));
    // In a teacher's words, not the file format's ("params.friction: must be < 1 ...").
    QVERIFY2(compare.summary().endsWith(QStringLiteral("not running: it needs a friction below 1 (the scene's is %1)")
                                            .arg(doc.world().params.friction)),
             qPrintable(compare.summary()));
    QCOMPARE(ghostCount(&scene), 0);
    doc.advance(10);
    QVERIFY(!compare.isTracking());

    QVERIFY(doc.setParam(QStringLiteral("friction"), QStringLiteral("0.1")).isEmpty());
    QVERIFY(compare.isTracking());
    QVERIFY(compare.problem().isEmpty());
    QVERIFY(isCopyOf(*compare.world(), doc.world(), ModelKind::Exact));
    QCOMPARE(ghostCount(&scene), 1);
}

void TestCompareRun::stopsWhenComparisonLeavesFiniteNumbers()
{
    // Friction 2.5 makes the book model blow up (v *= 1 - k = -1.5 every frame).
    World start = presetWorld("four-marbles", ModelKind::Book);
    start.params.friction = 2.5;
    SceneDocument doc;
    doc.resetScene(start);
    CompareRun compare(&doc);
    QGraphicsScene scene;
    compare.setStage(&scene);
    compare.setModel(ModelKind::Book);
    QCOMPARE(ghostCount(&scene), 1);
    for (int f = 0; f < 3000 && compare.isTracking(); ++f)
        doc.advance(1);
    QVERIFY(compare.isActive());
    QVERIFY(!compare.isTracking());
    QVERIFY2(compare.problem().contains(QStringLiteral("left finite numbers")), qPrintable(compare.problem()));
    QCOMPARE(ghostCount(&scene), 0);
    // Stepping back restarts it from the document's (finite) state.
    QVERIFY(doc.stepBack());
    QVERIFY(compare.isTracking());
    QCOMPARE(ghostCount(&scene), 1);
}

void TestCompareRun::ghostsFollowTheComparison()
{
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    QGraphicsScene scene;
    compare.setStage(&scene);
    QCOMPARE(ghostCount(&scene), 0);

    compare.setModel(ModelKind::Exact);
    QCOMPARE(ghostCount(&scene), 1);
    const MarbleFieldItem *ghost = compare.ghostItem();
    QVERIFY(ghost);
    QCOMPARE(ghost->world(), compare.world());
    QCOMPARE(ghost->style(), MarbleFieldItem::Style::Ghost);
    QVERIFY(ghost->zValue() == CompareRun::kGhostZValue);
    QCOMPARE(ghost->acceptedMouseButtons(), Qt::NoButton);

    compare.setModel(ModelKind::Impulse);
    doc.advance(20);
    QCOMPARE(ghostCount(&scene), 1);
    QCOMPARE(compare.ghostItem()->world(), compare.world());

    compare.stop();
    QVERIFY(compare.ghostItem() == nullptr);
    QCOMPARE(ghostCount(&scene), 0);
    QVERIFY(compare.world() == nullptr);
    doc.advance(5);
    QCOMPARE(ghostCount(&scene), 0);
}

void TestCompareRun::ghostsSurviveStageDestroyedFirst()
{
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    {
        QGraphicsScene scene;
        compare.setStage(&scene);
        compare.setModel(ModelKind::Exact);
        QCOMPARE(ghostCount(&scene), 1);
    }
    // The scene deleted the ghost; the comparison runs on without one (ASan checks the rest).
    QVERIFY(compare.ghostItem() == nullptr);
    doc.advance(10);
    QVERIFY(compare.isTracking());
    compare.stop();
}

void TestCompareRun::plotGetsCompareSeries()
{
    // The main window's wiring, without the window: the plot samples both worlds each frame.
    SceneDocument doc;
    doc.resetScene(presetWorld("four-marbles", ModelKind::Book));
    CompareRun compare(&doc);
    PlotDock plot;
    connect(&doc, &SceneDocument::frameAdvanced, &plot, [&] { plot.appendFrame(doc.world(), compare.world()); });
    plot.reset(doc.world());
    doc.advance(10);
    QVERIFY(plot.compareSeries(0) == nullptr);

    compare.setModel(ModelKind::Exact);
    plot.setCompareModel(QStringLiteral("exact"));
    doc.advance(50);
    QCOMPARE(plot.sampleCount(), 60);
    for (int marble = 0; marble < 4; ++marble) {
        QLineSeries *dashed = plot.compareSeries(marble);
        QVERIFY(dashed);
        QCOMPARE(dashed->pen().style(), Qt::CustomDashLine);
        QCOMPARE(dashed->pen().color(), plot.speedSeries(marble)->pen().color());
        QVERIFY2(dashed->name().contains(QStringLiteral("exact")), qPrintable(dashed->name()));
        // No comparison before it was chosen; its speeds afterwards.
        QVERIFY(std::isnan(plot.sampleCompareSpeed(9, marble)));
        QVERIFY(plot.sampleCompareSpeed(59, marble) == length(compare.world()->velocity[marble]));
        QVERIFY(plot.sampleSpeed(59, marble) == length(doc.world().velocity[marble]));
    }
    plot.refreshChart();
    QCOMPARE(plot.compareSeries(0)->count(), 50);

    // The totals of both models: the comparison's dashed in the same colour, the document's solid
    // meanwhile; both follow the checkboxes.
    QLineSeries *kinetic = plot.compareKineticSeries();
    QLineSeries *momentum = plot.compareMomentumSeries(0);
    QVERIFY(kinetic && momentum && plot.compareMomentumSeries(1));
    QVERIFY(std::isnan(plot.sampleCompareKineticEnergy(9)));
    QVERIFY(plot.sampleCompareKineticEnergy(59) == compare.world()->kineticEnergy());
    QVERIFY(plot.sampleCompareMomentum(59) == compare.world()->momentum());
    QVERIFY(plot.sampleKineticEnergy(59) == doc.world().kineticEnergy());
    QCOMPARE(kinetic->pen().style(), Qt::CustomDashLine);
    QCOMPARE(kinetic->pen().color(), plot.kineticSeries()->pen().color());
    QCOMPARE(plot.kineticSeries()->pen().style(), Qt::SolidLine);
    QCOMPARE(kinetic->name(), QStringLiteral("kinetic energy, exact"));
    QCOMPARE(plot.kineticSeries()->name(), QStringLiteral("kinetic energy"));
    QVERIFY(!kinetic->isVisible());
    QCOMPARE(kinetic->count(), 0);
    plot.setKineticEnergyShown(true);
    plot.refreshChart();
    QVERIFY(kinetic->isVisible() && plot.kineticSeries()->isVisible());
    QVERIFY(!momentum->isVisible());
    // The legend lists the totals once: the "exact (dashed)" entry stands for the dashed ones.
    plot.show();
    QVERIFY(QTest::qWaitForWindowExposed(&plot));
    for (QLegendMarker *marker : plot.chartView()->chart()->legend()->markers(kinetic))
        QVERIFY(!marker->isVisible());
    for (QLegendMarker *marker : plot.chartView()->chart()->legend()->markers(plot.kineticSeries()))
        QVERIFY(marker->isVisible());
    QCOMPARE(kinetic->count(), 50); // the frames since the comparison started
    QCOMPARE(plot.kineticSeries()->count(), 60);
    plot.setMomentumShown(true);
    plot.refreshChart();
    QVERIFY(momentum->isVisible() && plot.compareMomentumSeries(1)->isVisible());
    QCOMPARE(momentum->count(), 50);
    QCOMPARE(momentum->name(), QStringLiteral("momentum x, exact"));
    QCOMPARE(plot.compareMomentumSeries(1)->name(), QStringLiteral("momentum y, exact"));

    compare.stop();
    plot.setCompareModel(QString());
    QVERIFY(plot.compareSeries(0) == nullptr);
    QVERIFY(plot.compareKineticSeries() == nullptr && plot.compareMomentumSeries(0) == nullptr
            && plot.compareMomentumSeries(1) == nullptr);
    QVERIFY(std::isnan(plot.sampleCompareKineticEnergy(59)));
    QCOMPARE(plot.kineticSeries()->pen().style(), Qt::SolidLine); // dashed is the compared model's
    // In full, or "KE" where the legend gives short names.
    QCOMPARE(plot.kineticSeries()->name(), plot.legendIsCompact() ? QStringLiteral("KE") : QStringLiteral("kinetic energy"));
    QVERIFY(plot.speedSeries(0));
}

void TestCompareRun::plotLegendListsMarblesThenModels()
{
    // Comparing, then a scene with more marbles (a preset opened): the new marbles' lines come
    // before the two models' entries in the legend, as on the first scene.
    PlotDock plot;
    World small = presetWorld("four-marbles", ModelKind::Book);
    plot.reset(small);
    plot.setCompareModel(QStringLiteral("exact"));
    plot.reset(presetWorld("pachinko", ModelKind::Book));
    QCOMPARE(plot.plottedMarbles().size(), 8);
    const QList<QAbstractSeries *> series = plot.chartView()->chart()->series();
    qsizetype lastMarble = -1;
    qsizetype firstKey = series.size();
    for (qsizetype k = 0; k < series.size(); ++k) {
        const QString name = series[k]->name();
        if (name == QStringLiteral("book (solid)") || name == QStringLiteral("exact (dashed)"))
            firstKey = std::min(firstKey, k);
        else if (name.startsWith(QStringLiteral("marble ")))
            lastMarble = k;
    }
    QVERIFY(lastMarble >= 0);
    QVERIFY2(lastMarble < firstKey && firstKey < series.size(),
             qPrintable(QStringLiteral("last marble line at %1, first model entry at %2").arg(lastMarble).arg(firstKey)));
    // The keys still draw against the axes (a series without axes would not be plotted).
    for (QAbstractSeries *s : series) {
        if (s->name() == QStringLiteral("exact (dashed)"))
            QCOMPARE(s->attachedAxes().size(), 2);
    }
}

void TestCompareRun::plotExportsAndDescribesCompareLines()
{
    World scene;
    scene.addMarble({100, 100}, 10.0, {3.0, 4.0});
    scene.addMarble({300, 100}, 20.0, {0.0, -2.0});
    World other = scene;
    other.velocity = {{0.0, 0.5}, {1.5, 2.0}};
    PlotDock plot;
    plot.reset(scene);
    scene.frame = other.frame = 1;
    plot.appendFrame(scene); // before the comparison: no dashed lines, no compare columns
    plot.setCompareModel(QStringLiteral("impulse"));
    scene.frame = other.frame = 2;
    plot.appendFrame(scene, &other);
    scene.frame = other.frame = 3;
    plot.appendFrame(scene, nullptr); // a frame the comparison did not run (it waits or stopped)

    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString path = dir.filePath(QStringLiteral("compare.csv"));
    QCOMPARE(plot.exportCsv(path), QString());
    QFile file(path);
    QVERIFY(file.open(QIODevice::ReadOnly | QIODevice::Text));
    const QStringList lines = QString::fromUtf8(file.readAll()).split(QLatin1Char('\n'));
    QCOMPARE(lines.size(), 5);
    QCOMPARE(lines[0], QStringLiteral("frame,time_s,speed_0_px_per_frame,speed_1_px_per_frame,"
                                      "kinetic_energy_mass_px2_per_frame2,momentum_x_mass_px_per_frame,momentum_y_mass_px_per_frame,"
                                      "speed_0_impulse_px_per_frame,speed_1_impulse_px_per_frame,"
                                      "kinetic_energy_impulse_mass_px2_per_frame2,momentum_x_impulse_mass_px_per_frame,"
                                      "momentum_y_impulse_mass_px_per_frame,scene_edited,comparison_restarted"));
    QVERIFY2(lines[1].startsWith(QStringLiteral("1,0.02,5,2,")) && lines[1].endsWith(QStringLiteral(",,,,,,0,0")),
             qPrintable(lines[1]));
    const QStringList second = lines[2].split(QLatin1Char(','));
    QCOMPARE(second.size(), 14);
    QCOMPARE(second.mid(7, 2), QStringList({QStringLiteral("0.5"), QStringLiteral("2.5")}));
    // Shortest round-trip text: the totals read back as the same doubles.
    QVERIFY(second[9].toDouble() == other.kineticEnergy());
    QVERIFY(second[10].toDouble() == other.momentum().x);
    QVERIFY(second[11].toDouble() == other.momentum().y);
    QVERIFY2(lines[3].endsWith(QStringLiteral(",,,,,,0,0")), qPrintable(lines[3]));
    // A restart of the comparison is marked on its frame's row, as on the plot.
    plot.markCompareRestart(3);
    QCOMPARE(plot.compareRestarts(), std::vector<std::int64_t>{3});
    QCOMPARE(plot.exportCsv(path), QString());
    QFile again(path);
    QVERIFY(again.open(QIODevice::ReadOnly | QIODevice::Text));
    const QStringList marked = QString::fromUtf8(again.readAll()).split(QLatin1Char('\n'));
    QVERIFY2(marked.value(2).endsWith(QStringLiteral(",0,0")) && marked.value(3).endsWith(QStringLiteral(",0,1")),
             qPrintable(marked.join(QLatin1Char('|'))));

    // The legend lists the marbles once and the two models once; the dashed line names its model.
    plot.refreshChart();
    QLineSeries *dashed = plot.compareSeries(1);
    QVERIFY(dashed);
    QCOMPARE(dashed->name(), QStringLiteral("marble 1, impulse"));
    QCOMPARE(plot.speedSeries(1)->name(), QStringLiteral("marble 1"));
    QCOMPARE(dashed->count(), 1);
    const QString hover = plot.describePoint(dashed, QPointF(2.0, 2.5));
    QVERIFY2(hover.contains(QStringLiteral("frame 2")) && hover.contains(QStringLiteral("impulse"))
                 && hover.contains(QStringLiteral("speed 2.5 px/frame")),
             qPrintable(hover));
    const QString energyHover = plot.describePoint(plot.compareKineticSeries(), QPointF(2.0, 0.0));
    QVERIFY2(energyHover.contains(QStringLiteral("frame 2")) && energyHover.contains(QStringLiteral("kinetic energy, impulse"))
                 && energyHover.contains(QString::number(other.kineticEnergy(), 'g', 6) + QStringLiteral(" mass·px²/frame²")),
             qPrintable(energyHover));
}

std::unique_ptr<MainWindow> TestCompareRun::makeWindow()
{
    auto window = std::make_unique<MainWindow>();
    window->setPrompts(std::make_unique<DiscardPrompts>());
    // Qt's offscreen screen is smaller than the window's first size, which opens maximized there.
    window->setWindowState(Qt::WindowNoState);
    window->resize(1400, 900);
    window->show();
    if (!QTest::qWaitForWindowExposed(window.get()))
        return nullptr;
    window->activateWindow();
    if (!QTest::qWaitForWindowActive(window.get()))
        return nullptr;
    return window;
}

void TestCompareRun::boxOffersTheOtherModels_data()
{
    QTest::addColumn<QString>("sceneModel");
    QTest::addColumn<QStringList>("offered");
    QTest::addRow("book") << "book" << QStringList{"none", "exact", "impulse"};
    QTest::addRow("exact") << "exact" << QStringList{"none", "book", "impulse"};
    QTest::addRow("impulse") << "impulse" << QStringList{"none", "book", "exact"};
}

void TestCompareRun::boxOffersTheOtherModels()
{
    QFETCH(QString, sceneModel);
    QFETCH(QStringList, offered);
    std::unique_ptr<MainWindow> window = makeWindow();
    QVERIFY(window);
    QVERIFY(window->document()->setParam(QStringLiteral("model"), sceneModel).isEmpty());
    auto *box = window->findChild<QComboBox *>(QStringLiteral("compareBox"));
    QVERIFY(box);
    QStringList items;
    for (int k = 0; k < box->count(); ++k)
        items << box->itemText(k).remove(QStringLiteral("Compare: "));
    QCOMPARE(items, offered);
    QCOMPARE(box->currentIndex(), 0);

    auto *menu = window->findChild<QMenu *>(QStringLiteral("compareMenu"));
    QVERIFY(menu);
    QStringList visible;
    for (QAction *action : menu->actions()) {
        if (action->isVisible())
            visible << action->text().remove(QLatin1Char('&')).toLower();
    }
    QCOMPARE(visible, offered);
}

void TestCompareRun::choosingWithKeysShowsGhostsReadoutAndPlot()
{
    std::unique_ptr<MainWindow> window = makeWindow();
    QVERIFY(window);
    CompareRun *compare = window->compareRun();
    QGraphicsScene *stage = window->stageView()->scene();
    auto *box = window->findChild<QComboBox *>(QStringLiteral("compareBox"));
    auto *readout = window->findChild<QLabel *>(QStringLiteral("compareLabel"));
    QVERIFY(box && readout);
    QVERIFY(!compare->isActive());
    QVERIFY(readout->isHidden());
    QCOMPARE(ghostCount(stage), 0);

    // Book scene: the box reads none, exact, impulse; one step down chooses exact.
    box->setFocus();
    QTest::keyClick(box, Qt::Key_Down);
    QVERIFY(compare->isActive());
    QCOMPARE(compare->model(), ModelKind::Exact);
    QCOMPARE(ghostCount(stage), 1);
    QVERIFY(readout->isVisible());
    QTRY_VERIFY2(readout->text().startsWith(QStringLiteral("Compare: exact - largest gap 0")), qPrintable(readout->text()));

    // Frames with the step key, on the stage as a user would.
    window->stageView()->setFocus();
    for (int f = 0; f < 120; ++f)
        QTest::keyClick(window->stageView(), Qt::Key_Right);
    QCOMPARE(window->document()->world().frame, 120);
    QCOMPARE(compare->world()->frame, 120);
    QCOMPARE_GT(compare->largestGapPx(), 0.0);
    QTRY_COMPARE(readout->text(), compare->summary()); // once the status bar has laid it out
    QVERIFY2(readout->text().contains(QStringLiteral("(marble ")), qPrintable(readout->text()));

    PlotDock *plot = window->plotDock();
    QCOMPARE(plot->compareModel(), QStringLiteral("exact"));
    QVERIFY(plot->compareSeries(0));
    const qsizetype last = plot->sampleCount() - 1;
    QCOMPARE(plot->sampleFrame(last), 120);
    QVERIFY(plot->sampleCompareSpeed(last, 0) == length(compare->world()->velocity[0]));

    // Step back takes the comparison back too, to its own frame 119: the dashed line goes on
    // from there, and stepping on gives frame 120 again.
    const World at120 = *compare->world();
    QTest::keyClick(window->stageView(), Qt::Key_Left);
    QCOMPARE(compare->startFrame(), 0);
    QCOMPARE(compare->world()->frame, 119);
    QCOMPARE(readout->text(), compare->summary());
    QCOMPARE(plot->sampleFrame(plot->sampleCount() - 1), 119);
    QTest::keyClick(window->stageView(), Qt::Key_Right);
    QVERIFY(compare->world()->velocity == at120.velocity && compare->world()->position == at120.position);
    QVERIFY(plot->sampleCompareSpeed(plot->sampleCount() - 1, 0) == length(at120.velocity[0]));

    // Back up to "none": the ghosts go, the readout hides, the plot drops the dashed lines.
    box->setFocus();
    QTest::keyClick(box, Qt::Key_Up);
    QVERIFY(!compare->isActive());
    QCOMPARE(ghostCount(stage), 0);
    QVERIFY(readout->isHidden());
    QVERIFY(plot->compareSeries(0) == nullptr);
    QCOMPARE(plot->compareModel(), QString());
}

void TestCompareRun::menuActionsAndBoxAgree()
{
    std::unique_ptr<MainWindow> window = makeWindow();
    QVERIFY(window);
    auto *box = window->findChild<QComboBox *>(QStringLiteral("compareBox"));
    auto *impulse = window->findChild<QAction *>(QStringLiteral("actionCompareImpulse"));
    auto *none = window->findChild<QAction *>(QStringLiteral("actionCompareNone"));
    QVERIFY(box && impulse && none);
    impulse->trigger();
    QCOMPARE(window->compareRun()->model(), ModelKind::Impulse);
    QCOMPARE(box->currentText(), QStringLiteral("Compare: impulse"));
    QVERIFY(impulse->isChecked());
    QCOMPARE(ghostCount(window->stageView()->scene()), 1);
    none->trigger();
    QVERIFY(!window->compareRun()->isActive());
    QCOMPARE(box->currentText(), QStringLiteral("Compare: none"));
    QCOMPARE(ghostCount(window->stageView()->scene()), 0);
}

void TestCompareRun::sceneSwitchingToComparedModelEndsComparison()
{
    std::unique_ptr<MainWindow> window = makeWindow();
    QVERIFY(window);
    window->findChild<QAction *>(QStringLiteral("actionCompareExact"))->trigger();
    QVERIFY(window->compareRun()->isActive());
    QVERIFY(window->document()->setParam(QStringLiteral("model"), QStringLiteral("exact")).isEmpty());
    QVERIFY(!window->compareRun()->isActive());
    QCOMPARE(ghostCount(window->stageView()->scene()), 0);
    auto *box = window->findChild<QComboBox *>(QStringLiteral("compareBox"));
    QCOMPARE(box->currentText(), QStringLiteral("Compare: none"));
    QCOMPARE(box->findText(QStringLiteral("Compare: exact")), -1);
    QVERIFY(box->findText(QStringLiteral("Compare: book")) >= 0);
}

QTEST_MAIN(TestCompareRun)
#include "tst_comparerun.moc"
