// The book model's broad phase and skips (issue "Scale"): the uniform grid, the sleeping marbles
// and the skipped zero terms must give bit-identical results to the plain all-pairs transcription,
// the book's in-place order included.

#include "core/bookmodel.h"
#include "core/presets.h"
#include "core/world.h"

#include <QtTest>

using namespace marbles;

namespace {

struct SceneShape {
    int marbles;
    int pins;
    double maxSpeed;
    double restingFraction;
    double friction;
    double zero;
    Vec2 gravity;
    bool walls;
    bool shortCircuit;
    bool overlapping;
};

World randomScene(const SceneShape &s, std::uint64_t seed)
{
    SplitMix64 rng(seed);
    World w;
    w.stage = {600, 400, s.walls};
    w.params.friction = s.friction;
    w.params.zeroThreshold = s.zero;
    w.params.gravity = s.gravity;
    w.params.shortCircuit = s.shortCircuit;
    // Dense enough that marbles meet every few frames; radii vary tenfold (mass sharing matters).
    for (int i = 0; i < s.marbles; ++i) {
        const double r = rng.uniform(2.0, s.overlapping ? 20.0 : 9.0);
        const bool resting = rng.uniform() < s.restingFraction;
        const double speed = resting ? 0.0 : rng.uniform(0.0, s.maxSpeed);
        const double angle = rng.uniform(0.0, 6.283185307179586);
        // One draw per statement: a call's arguments are evaluated in no specified order.
        const double extra = rng.uniform() < 0.2 ? rng.uniform(0.5, 50.0) : 0.0;
        const double x = rng.uniform(r, 600 - r);
        const double y = rng.uniform(r, 400 - r);
        w.addMarble({x, y}, r, {speed * std::cos(angle), speed * std::sin(angle)}, extra);
    }
    for (int j = 0; j < s.pins; ++j)
        w.addPin({rng.uniform(0, 600), rng.uniform(0, 400)});
    return w;
}

// Steps `w` with `model`, applying a click to a random marble now and then (as World::step does
// for scripted pushes), and returns the first frame where the two runs differ, or -1.
int firstDifference(World a, World b, int frames, std::uint64_t seed)
{
    BookModel fast;
    BookModel reference;
    reference.setReferenceMode(true);
    SplitMix64 rng(seed ^ 0x5eed);
    for (int f = 1; f <= frames; ++f) {
        if (a.marbleCount() > 0 && rng.uniform() < 0.1) {
            const int i = static_cast<int>(rng.uniform() * a.marbleCount());
            const Vec2 at{a.position[i].x + rng.uniform(-5, 5), a.position[i].y + rng.uniform(-5, 5)};
            a.push(i, at);
            b.push(i, at);
        }
        fast.step(a);
        reference.step(b);
        ++a.frame;
        ++b.frame;
        if (a.position != b.position || a.velocity != b.velocity || a.acceleration != b.acceleration
            || a.lastHit != b.lastHit)
            return f;
    }
    return -1;
}

} // namespace

Q_DECLARE_METATYPE(SceneShape)

class TestBookGrid : public QObject {
    Q_OBJECT

private slots:
    void gridMatchesAllPairs_data();
    void gridMatchesAllPairs();
    void gridWithCrowdedCells();
    void gridWithOversizeMarbles_data();
    void gridWithOversizeMarbles();
    void gridFollowsEditsBetweenFrames();
    void sleepingMarblesStayAsleep();
};

void TestBookGrid::gridMatchesAllPairs_data()
{
    QTest::addColumn<SceneShape>("shape");
    //                                   marbles pins speed rest   k     Z     gravity     walls  short  overlap
    QTest::addRow("crowd, walls") << SceneShape{300, 0, 4.0, 0.0, 0.0, 0.0, {0, 0}, true, false, false};
    QTest::addRow("crowd, friction, threshold") << SceneShape{300, 0, 6.0, 0.0, 0.1, 0.01, {0, 0}, true, false, false};
    QTest::addRow("pins and marbles") << SceneShape{200, 150, 5.0, 0.2, 0.05, 0.01, {0, 0}, true, false, false};
    QTest::addRow("short circuit") << SceneShape{250, 60, 5.0, 0.0, 0.0, 0.0, {0, 0}, true, true, false};
    QTest::addRow("gravity") << SceneShape{200, 100, 2.0, 0.0, 0.02, 0.0, {0, 0.3}, true, false, false};
    QTest::addRow("mostly resting") << SceneShape{400, 30, 4.0, 0.9, 0.1, 0.01, {0, 0}, true, false, false};
    QTest::addRow("overlapping start") << SceneShape{150, 40, 3.0, 0.3, 0.1, 0.01, {0, 0}, true, false, true};
    QTest::addRow("fast, no walls (marbles leave)") << SceneShape{120, 40, 60.0, 0.0, 0.0, 0.0, {0, 0}, false, false, false};
    QTest::addRow("book friction 1.5") << SceneShape{150, 20, 4.0, 0.0, 1.5, 0.01, {0, 0}, true, false, false};
}

void TestBookGrid::gridMatchesAllPairs()
{
    QFETCH(SceneShape, shape);
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        const World w = randomScene(shape, seed);
        QVERIFY(w.marbleCount() >= BookModel::kGridMinMarbles);
        const int diff = firstDifference(w, w, 150, seed);
        QVERIFY2(diff < 0, qPrintable(QString("seed %1: first difference at frame %2").arg(seed).arg(diff)));
    }
}

void TestBookGrid::gridWithCrowdedCells()
{
    // Large marbles, too many to be left out of the grid (RadiusSplit), make the cells
    // 2 rMax = 120 px wide, so each holds a dozen small marbles or more: most of a bucket's
    // bodies are past the few it holds inline, in its overflow list, and bodies move in and out
    // of those lists every frame.
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        World w = randomScene({300, 20, 5.0, 0.2, 0.0, 0.0, {0, 0}, true, false, false}, seed);
        for (int k = 0; k <= RadiusSplit::maxOversize; ++k)
            w.setRadius(k, 60.0);
        QCOMPARE(splitRadii(w.radius).oversize, 0);
        const int diff = firstDifference(w, w, 120, seed);
        QVERIFY2(diff < 0, qPrintable(QString("seed %1: first difference at frame %2").arg(seed).arg(diff)));
    }
}

void TestBookGrid::gridWithOversizeMarbles_data()
{
    QTest::addColumn<SceneShape>("shape");
    QTest::addColumn<int>("giants");
    QTest::addColumn<double>("giantSpeed");
    //                                   marbles pins speed rest   k     Z     gravity     walls  short  overlap
    QTest::addRow("one giant") << SceneShape{300, 0, 4.0, 0.0, 0.0, 0.0, {0, 0}, true, false, false} << 1 << 6.0;
    QTest::addRow("16 giants, pins") << SceneShape{400, 80, 4.0, 0.2, 0.05, 0.01, {0, 0}, true, false, false}
                                     << RadiusSplit::maxOversize << 4.0;
    QTest::addRow("giants, short circuit") << SceneShape{300, 60, 5.0, 0.0, 0.0, 0.0, {0, 0}, true, true, false} << 3 << 8.0;
    QTest::addRow("giants, gravity") << SceneShape{250, 40, 2.0, 0.0, 0.02, 0.0, {0, 0.3}, true, false, false} << 2 << 3.0;
    QTest::addRow("giants at rest among sleepers") << SceneShape{400, 20, 4.0, 0.9, 0.1, 0.01, {0, 0}, true, false, false} << 4 << 0.0;
    QTest::addRow("fast giants, no walls") << SceneShape{200, 40, 30.0, 0.0, 0.0, 0.0, {0, 0}, false, false, false} << 2 << 80.0;
}

void TestBookGrid::gridWithOversizeMarbles()
{
    QFETCH(SceneShape, shape);
    QFETCH(int, giants);
    QFETCH(double, giantSpeed);
    // A few marbles far larger than the rest are left out of the grid, whose cells are sized
    // from the others; every marble is then tested against them and they against every marble,
    // in the same order as all pairs.
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        World w = randomScene(shape, seed);
        SplitMix64 rng(seed + 100);
        for (int k = 0; k < giants; ++k) {
            const int i = k * (w.marbleCount() / giants);
            w.setRadius(i, rng.uniform(40.0, 120.0));
            const double angle = rng.uniform(0.0, 6.283185307179586);
            w.velocity[i] = {giantSpeed * std::cos(angle), giantSpeed * std::sin(angle)};
        }
        QCOMPARE(splitRadii(w.radius).oversize, giants);
        const int diff = firstDifference(w, w, 150, seed);
        QVERIFY2(diff < 0, qPrintable(QString("seed %1: first difference at frame %2").arg(seed).arg(diff)));
    }
}

void TestBookGrid::gridFollowsEditsBetweenFrames()
{
    // The grid is a cache: moving, adding and removing marbles between frames must not leave it stale.
    World a = randomScene({200, 50, 4.0, 0.0, 0.0, 0.0, {0, 0}, true, false, false}, 9);
    World b = a;
    BookModel fast;
    BookModel reference;
    reference.setReferenceMode(true);
    for (int f = 0; f < 60; ++f) {
        if (f % 10 == 5) {
            // Drag marble f onto marble f + 1, add one, remove one: what the app's editing does.
            for (World *w : {&a, &b}) {
                w->position[f] = w->position[f + 1];
                w->addMarble({300, 200}, 8, {1, 1});
                w->removeMarble(f + 3);
            }
        }
        // A marble grown far larger than the rest (left out of the grid), then shrunk back.
        if (f == 25 || f == 45) {
            for (World *w : {&a, &b})
                w->setRadius(7, f == 25 ? 90.0 : 5.0);
        }
        fast.step(a);
        reference.step(b);
        QCOMPARE(a.position, b.position);
        QCOMPARE(a.velocity, b.velocity);
    }
}

void TestBookGrid::sleepingMarblesStayAsleep()
{
    // With friction and the threshold, a crowd comes to rest; from then on a frame changes nothing.
    // (Equal masses: the book's sharing then never raises the largest speed. With unequal masses
    // it can pump speed into overlapping pairs for ever, one of the book's flaws.)
    World w = makeCrowd(300, 3);
    w.params.model = ModelKind::Book;
    w.params.friction = 0.2;
    w.params.zeroThreshold = 0.05;
    for (int i = 0; i < w.marbleCount(); ++i)
        w.setExplicitMass(i, 1.0);
    for (int f = 0; f < 400; ++f)
        w.step();
    int moving = 0;
    for (const Vec2 &v : w.velocity)
        moving += (v.x != 0.0 || v.y != 0.0);
    QCOMPARE(moving, 0);
    const World before = w;
    w.step();
    QCOMPARE(w.position, before.position);
    // A click wakes one marble; it moves and may wake others.
    w.push(0, {w.position[0].x - 0.01, w.position[0].y});
    w.step();
    QCOMPARE_LE(std::abs(w.velocity[0].x - 0.1), 1e-12); // a = 0.01 * 10 / 1
    QVERIFY(w.position[0].x > before.position[0].x);
}

QTEST_GUILESS_MAIN(TestBookGrid)
#include "tst_bookgrid.moc"
