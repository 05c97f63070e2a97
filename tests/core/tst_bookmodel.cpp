// The book model (PHYSICS.md, model "book") step by step, against values worked out by hand.

#include "core/bookmodel.h"
#include "core/world.h"

#include <QtTest>

#include <cmath>
#include <limits>
#include <numbers>

using namespace marbles;

namespace {

constexpr double tol = 1e-12;

// A world with no walls, no friction and no threshold unless a test asks for them, so that each
// test sees the one step it is about.
World bareWorld(double friction = 0.0, double zero = 0.0, bool walls = false)
{
    World w;
    w.stage = {800, 600, walls};
    w.params.friction = friction;
    w.params.zeroThreshold = zero;
    return w;
}

} // namespace

class TestBookModel : public QObject {
    Q_OBJECT

private slots:
    void frictionDecay_data();
    void frictionDecay();
    void frictionAboveTwoBlowsUp();
    void zeroThreshold_data();
    void zeroThreshold();
    void pushFormula_data();
    void pushFormula();
    void scriptedPushActsOnItsFrame();
    void gravityEveryFrame();
    void walls_data();
    void walls();
    void wallCornerUsesRestoredPosition();
    void wallsOff();
    void pinReflectionAngle_data();
    void pinReflectionAngle();
    void pinHitUsesLessOrEqual();
    void massRatioSharing_data();
    void massRatioSharing();
    void marbleHitUsesStrictLess();
    void inPlaceOrderDependence();
    void shortCircuit_data();
    void shortCircuit();
    void nanGuard_data();
    void nanGuard();
    void restingMarbleIsUntouched();
    void lastHitRecordsFigure1112();
};

void TestBookModel::frictionDecay_data()
{
    QTest::addColumn<double>("k");
    QTest::addColumn<double>("v0");
    QTest::addColumn<int>("frames");
    QTest::addColumn<double>("v");
    QTest::addColumn<double>("x");

    // a = -v k, v += a: v(n) = v0 (1 - k)^n, x(n) = sum of v(1..n).
    QTest::addRow("k=0.1, 1 frame") << 0.1 << 10.0 << 1 << 9.0 << 109.0;
    QTest::addRow("k=0.1, 2 frames") << 0.1 << 10.0 << 2 << 8.1 << 117.1;
    QTest::addRow("k=0.1, 3 frames") << 0.1 << 10.0 << 3 << 7.29 << 124.39;
    QTest::addRow("k=0.5, 2 frames") << 0.5 << 8.0 << 2 << 2.0 << 106.0;
    QTest::addRow("k=0, keeps speed") << 0.0 << 3.0 << 5 << 3.0 << 115.0;
    QTest::addRow("k=1, stops at once") << 1.0 << 7.0 << 1 << 0.0 << 100.0;
    // k = 1.5: factor -0.5, the velocity flips sign every frame.
    QTest::addRow("k=1.5, flips") << 1.5 << 4.0 << 2 << 1.0 << 99.0;
}

void TestBookModel::frictionDecay()
{
    QFETCH(double, k);
    QFETCH(double, v0);
    QFETCH(int, frames);
    QFETCH(double, v);
    QFETCH(double, x);
    World w = bareWorld(k);
    w.addMarble({100, 300}, 10, {v0, 0});
    for (int f = 0; f < frames; ++f)
        QVERIFY(w.step().finite);
    QCOMPARE_LE(std::abs(w.velocity[0].x - v), tol);
    QCOMPARE_LE(std::abs(w.position[0].x - x), 1e-10);
    QCOMPARE(w.velocity[0].y, 0.0);
    QCOMPARE(w.frame, std::int64_t(frames));
}

void TestBookModel::frictionAboveTwoBlowsUp()
{
    // |1 - k| = 1.5 > 1: the speed grows by half every frame until it overflows.
    World w = bareWorld(2.5);
    w.addMarble({400, 300}, 10, {1, 0});
    int frames = 0;
    StepResult r;
    while ((r = w.step()).finite && frames < 5000)
        ++frames;
    QVERIFY(!r.finite);
    QCOMPARE(r.badMarble, 0);
    QVERIFY(frames > 100);
    QVERIFY(frames < 5000);
}

void TestBookModel::zeroThreshold_data()
{
    QTest::addColumn<double>("zero");
    QTest::addColumn<double>("v0");
    QTest::addColumn<double>("expected");
    const double z = 0.01;
    QTest::addRow("exactly +Z") << z << z << 0.0;
    QTest::addRow("exactly -Z") << z << -z << 0.0;
    QTest::addRow("just above +Z") << z << std::nextafter(z, 1.0) << std::nextafter(z, 1.0);
    QTest::addRow("just below -Z") << z << std::nextafter(-z, -1.0) << std::nextafter(-z, -1.0);
    QTest::addRow("inside") << z << 0.004 << 0.0;
    QTest::addRow("Z = 0 keeps tiny") << 0.0 << 1e-300 << 1e-300;
    QTest::addRow("Z = 100 stops fast marble") << 100.0 << 99.5 << 0.0;
    // The book's -Z <= v <= Z at the edges of the doubles (the model writes it |v| <= Z).
    QTest::addRow("-0 becomes +0") << z << -0.0 << 0.0;
    QTest::addRow("Z = 0: -0 becomes +0") << 0.0 << -0.0 << 0.0;
    QTest::addRow("Z = -0: -0 becomes +0") << -0.0 << -0.0 << 0.0;
    QTest::addRow("negative Z stops nothing") << -0.5 << 0.25 << 0.25;
    QTest::addRow("negative Z keeps -0.25") << -0.5 << -0.25 << -0.25;
    const double inf = std::numeric_limits<double>::infinity();
    QTest::addRow("infinite Z stops any finite speed") << inf << -1e300 << 0.0;
    QTest::addRow("infinite Z stops an infinite speed") << inf << inf << 0.0;
}

void TestBookModel::zeroThreshold()
{
    QFETCH(double, zero);
    QFETCH(double, v0);
    QFETCH(double, expected);
    World w = bareWorld(0.0, zero);
    w.addMarble({400, 300}, 10, {v0, v0});
    w.step();
    // Bit-identical: the threshold either leaves the component alone or makes it exactly 0.
    QCOMPARE(w.velocity[0].x, expected);
    QCOMPARE(w.velocity[0].y, expected);
    QVERIFY(!std::signbit(w.velocity[0].x) || expected != 0.0);
    QCOMPARE(w.position[0].x, 400 + expected);
}

void TestBookModel::pushFormula_data()
{
    QTest::addColumn<double>("radius");
    QTest::addColumn<double>("mass");
    QTest::addColumn<double>("pushScale");
    QTest::addColumn<double>("cx");
    QTest::addColumn<double>("cy");
    QTest::addColumn<double>("ax");
    QTest::addColumn<double>("ay");
    // a = (p - c) * pushScale / m, p = (100, 100); m = 1.25 r unless given.
    QTest::addRow("r=20, left-up click") << 20.0 << 0.0 << 10.0 << 90.0 << 95.0 << 4.0 << 2.0;
    QTest::addRow("r=40, right click") << 40.0 << 0.0 << 10.0 << 130.0 << 100.0 << -6.0 << 0.0;
    QTest::addRow("explicit mass 2") << 20.0 << 2.0 << 10.0 << 99.0 << 101.0 << 5.0 << -5.0;
    QTest::addRow("pushScale 3") << 8.0 << 0.0 << 3.0 << 95.0 << 105.0 << 1.5 << -1.5;
    QTest::addRow("centre click") << 20.0 << 0.0 << 10.0 << 100.0 << 100.0 << 0.0 << 0.0;
}

void TestBookModel::pushFormula()
{
    QFETCH(double, radius);
    QFETCH(double, mass);
    QFETCH(double, pushScale);
    QFETCH(double, cx);
    QFETCH(double, cy);
    QFETCH(double, ax);
    QFETCH(double, ay);
    World w = bareWorld(0.1);
    w.params.pushScale = pushScale;
    w.addMarble({100, 100}, radius, {}, mass);
    w.push(0, {cx, cy});
    QCOMPARE_LE(std::abs(w.acceleration[0].x - ax), tol);
    QCOMPARE_LE(std::abs(w.acceleration[0].y - ay), tol);
    w.step();
    // Friction acts on the old velocity (zero), so the first frame's velocity is the push.
    QCOMPARE_LE(std::abs(w.velocity[0].x - ax), tol);
    QCOMPARE_LE(std::abs(w.velocity[0].y - ay), tol);
    QCOMPARE_LE(std::abs(w.position[0].x - (100 + ax)), tol);
    QCOMPARE(w.acceleration[0].x, 0.0);
    QCOMPARE(w.acceleration[0].y, 0.0);
}

void TestBookModel::scriptedPushActsOnItsFrame()
{
    World w = bareWorld();
    w.addMarble({100, 100}, 20);         // m = 25
    w.pushes.push_back({2, 0, {90, 100}, {}}); // a = 10 * 10 / 25 = 4 on the update 2 -> 3
    w.step();
    w.step();
    QCOMPARE(w.velocity[0].x, 0.0);
    QCOMPARE(w.frame, std::int64_t(2));
    w.step();
    QCOMPARE_LE(std::abs(w.velocity[0].x - 4.0), tol);
    w.step();
    QCOMPARE_LE(std::abs(w.velocity[0].x - 4.0), tol); // no friction: keeps going
}

void TestBookModel::gravityEveryFrame()
{
    World w = bareWorld(0.1);
    w.params.gravity = {0, 0.5};
    w.addMarble({100, 100}, 5);
    w.step(); // a = 0.5, v = 0.5, y = 100.5
    w.step(); // a = -0.05 + 0.5 = 0.45, v = 0.95, y = 101.45
    QCOMPARE_LE(std::abs(w.velocity[0].y - 0.95), tol);
    QCOMPARE_LE(std::abs(w.position[0].y - 101.45), tol);
    // Terminal speed of the book's update: v = (1-k) v + g  =>  v* = g / k = 5.
    for (int f = 0; f < 2000; ++f)
        w.step();
    QCOMPARE_LE(std::abs(w.velocity[0].y - 5.0), 1e-9);
}

void TestBookModel::walls_data()
{
    QTest::addColumn<double>("x");
    QTest::addColumn<double>("y");
    QTest::addColumn<double>("vx");
    QTest::addColumn<double>("vy");
    // Stage 800 x 600, r = 10: each moves past one edge in one frame.
    QTest::addRow("left") << 12.0 << 300.0 << -5.0 << 0.0;
    QTest::addRow("right") << 788.0 << 300.0 << 5.0 << 0.0;
    QTest::addRow("top") << 400.0 << 12.0 << 0.0 << -5.0;
    QTest::addRow("bottom") << 400.0 << 588.0 << 0.0 << 5.0;
}

void TestBookModel::walls()
{
    QFETCH(double, x);
    QFETCH(double, y);
    QFETCH(double, vx);
    QFETCH(double, vy);
    World w = bareWorld(0.0, 0.0, true);
    w.addMarble({x, y}, 10, {vx, vy});
    w.step();
    // Back to the old position, the component across the wall reversed.
    QCOMPARE(w.position[0].x, x);
    QCOMPARE(w.position[0].y, y);
    QCOMPARE(w.velocity[0].x, -vx);
    QCOMPARE(w.velocity[0].y, -vy);
    w.step();
    QCOMPARE(w.position[0].x, x - vx);
    QCOMPARE(w.position[0].y, y - vy);
}

void TestBookModel::wallCornerUsesRestoredPosition()
{
    // Crossing the right and the bottom edge in the same frame: the x test restores the old
    // position, and the y test then looks at that old position, which is inside: only v.x flips.
    World w = bareWorld(0.0, 0.0, true);
    w.addMarble({788, 588}, 10, {5, 5});
    w.step();
    QCOMPARE(w.position[0].x, 788.0);
    QCOMPARE(w.position[0].y, 588.0);
    QCOMPARE(w.velocity[0].x, -5.0);
    QCOMPARE(w.velocity[0].y, 5.0);
    // Moving outwards but not past the edge is not a hit; past the edge but moving inwards neither.
    World inward = bareWorld(0.0, 0.0, true);
    inward.addMarble({5, 300}, 10, {1, 0});
    inward.step();
    QCOMPARE(inward.position[0].x, 6.0);
    QCOMPARE(inward.velocity[0].x, 1.0);
}

void TestBookModel::wallsOff()
{
    World w = bareWorld(0.0, 0.0, false);
    w.addMarble({12, 300}, 10, {-50, 0});
    w.step();
    QCOMPARE(w.position[0].x, -38.0);
    QCOMPARE(w.velocity[0].x, -50.0);
}

void TestBookModel::pinReflectionAngle_data()
{
    QTest::addColumn<double>("thetaDeg");
    // The pin sits at angle theta from the direction of motion, at distance 8 < r = 10 from the
    // new centre. With v = (1, 0) and c = (cos t, sin t): v' = v - 2 (v.c) c = (-cos 2t, -sin 2t).
    QTest::addRow("head-on") << 0.0;
    QTest::addRow("30 deg") << 30.0;
    QTest::addRow("45 deg") << 45.0;
    QTest::addRow("60 deg") << 60.0;
    QTest::addRow("-45 deg") << -45.0;
    QTest::addRow("80 deg") << 80.0;
}

void TestBookModel::pinReflectionAngle()
{
    QFETCH(double, thetaDeg);
    const double t = thetaDeg * std::numbers::pi / 180;
    const double speed = 3.0;
    World w = bareWorld();
    w.addMarble({100, 100}, 10, {speed, 0});
    // c is measured from the restored (old) position: put the pin on the ray at angle t from
    // the old centre, close enough to the new centre to be inside the marble.
    const Vec2 pin{100 + 9 * std::cos(t), 100 + 9 * std::sin(t)};
    QVERIFY(distance(pin, {103, 100}) <= 10);
    w.addPin(pin);
    w.step();
    QCOMPARE(w.position[0].x, 100.0);
    QCOMPARE(w.position[0].y, 100.0);
    QCOMPARE_LE(std::abs(w.velocity[0].x - speed * -std::cos(2 * t)), 1e-12);
    QCOMPARE_LE(std::abs(w.velocity[0].y - speed * -std::sin(2 * t)), 1e-12);
    QCOMPARE_LE(std::abs(length(w.velocity[0]) - speed), 1e-12);
}

void TestBookModel::pinHitUsesLessOrEqual()
{
    // Exactly on the rim (distance == r) is a hit for pins.
    World w = bareWorld();
    w.addMarble({100, 100}, 10, {5, 0});
    w.addPin({115, 100}); // new centre 105: distance 10 == r
    w.step();
    QCOMPARE(w.position[0].x, 100.0);
    QCOMPARE(w.velocity[0].x, -5.0);
}

void TestBookModel::massRatioSharing_data()
{
    QTest::addColumn<double>("ri");
    QTest::addColumn<double>("rj");
    QTest::addColumn<double>("speed");
    QTest::addRow("equal") << 10.0 << 10.0 << 4.0;
    QTest::addRow("light hits heavy") << 10.0 << 40.0 << 4.0;
    QTest::addRow("heavy hits light") << 30.0 << 10.0 << 6.0;
    QTest::addRow("slow") << 15.0 << 20.0 << 0.5;
}

void TestBookModel::massRatioSharing()
{
    QFETCH(double, ri);
    QFETCH(double, rj);
    QFETCH(double, speed);
    // Head-on: i moves +x into j at rest. c = (1, 0), unit v = (1, 0), d = 1:
    //   v_i' = (-1, 0) scaled to (m_j/m_i) * speed/2;  v_j' = (0,0) + 2 (1, 0) scaled to (m_i/m_j) * speed/2.
    World w = bareWorld();
    w.addMarble({100, 300}, ri, {speed, 0});
    // j's centre just inside reach after the move.
    w.addMarble({100 + speed + ri + rj - 0.25, 300}, rj);
    const double mi = 1.25 * ri;
    const double mj = 1.25 * rj;
    w.step();
    QCOMPARE(w.position[0].x, 100.0); // restored
    QCOMPARE_LE(std::abs(w.velocity[0].x - -(mj / mi) * speed / 2), tol);
    QCOMPARE_LE(std::abs(w.velocity[0].y), tol);
    // Marble j then moved with its new velocity in its own update (it comes after i).
    const double vj = (mi / mj) * speed / 2;
    QCOMPARE_LE(std::abs(w.velocity[1].x - vj), tol);
    QCOMPARE_LE(std::abs(w.position[1].x - (100 + speed + ri + rj - 0.25 + vj)), 1e-10);
    // The book does not conserve momentum: with equal masses the total even drops to zero.
    const double before = mi * speed;
    const double after = mi * w.velocity[0].x + mj * w.velocity[1].x;
    QVERIFY(std::abs(after - before) > 1e-6);
}

void TestBookModel::marbleHitUsesStrictLess()
{
    // Exactly touching (distance == r_i + r_j) is not a hit between marbles.
    World w = bareWorld();
    w.addMarble({100, 300}, 10, {5, 0});
    w.addMarble({125, 300}, 10);
    w.step();
    QCOMPARE(w.position[0].x, 105.0);
    QCOMPARE(w.velocity[0].x, 5.0);
    QCOMPARE(w.velocity[1].x, 0.0);
}

void TestBookModel::inPlaceOrderDependence()
{
    // Two equal marbles closing at 5 px/frame each. Worked by hand:
    // order [X, Y]: X moves to 105, hits Y (distance 19 < 20), goes back to 100 and reflects:
    //   v_X = (-1, 0) * 2.5, v_Y = (-5 + 2, 0) scaled to 2.5 = (-2.5, 0); then Y moves to 121.5.
    // order [Y, X]: Y moves first, hits X and both end up moving right at 2.5.
    World xy = bareWorld();
    xy.addMarble({100, 100}, 10, {5, 0});
    xy.addMarble({124, 100}, 10, {-5, 0});
    xy.step();
    QCOMPARE(xy.position[0].x, 100.0);
    QCOMPARE(xy.velocity[0].x, -2.5);
    QCOMPARE(xy.position[1].x, 121.5);
    QCOMPARE(xy.velocity[1].x, -2.5);

    World yx = bareWorld();
    yx.addMarble({124, 100}, 10, {-5, 0});
    yx.addMarble({100, 100}, 10, {5, 0});
    yx.step();
    QCOMPARE(yx.position[0].x, 124.0);
    QCOMPARE(yx.velocity[0].x, 2.5);
    QCOMPARE(yx.position[1].x, 102.5);
    QCOMPARE(yx.velocity[1].x, 2.5);
}

void TestBookModel::shortCircuit_data()
{
    QTest::addColumn<bool>("shortCircuit");
    QTest::addColumn<double>("v0y");
    QTest::addColumn<double>("v2y");
    // Marble 0 at (100,100), r = 10, moving (5, 0) to (105, 100). Pin A at 45 degrees, 9 px from
    // the old centre, is hit first: back to (100,100), (5,0) reflects into (0,-5). Pin B, 9 px
    // straight below, is also inside: (0,-5) reflects about (0,1) into (0,5). Marble 2 (r = 5,
    // 13 px below) is then hit head-on: d = 1, v0 -> (0,-1) scaled to (m2/m0) * 5/2 = 1.25 up,
    // v2 -> (0,2) scaled to (m0/m2) * 5/2 = 5 down.
    // With short circuit only pin A acts; marble 2's own test finds pin B but |v| = 0 there.
    QTest::addRow("off") << false << -1.25 << 5.0;
    QTest::addRow("on") << true << -5.0 << 0.0;
}

void TestBookModel::shortCircuit()
{
    QFETCH(bool, shortCircuit);
    QFETCH(double, v0y);
    QFETCH(double, v2y);
    World w = bareWorld();
    w.params.shortCircuit = shortCircuit;
    w.addMarble({100, 100}, 10, {5, 0});
    w.addPin({100 + 9 / std::sqrt(2.0), 100 + 9 / std::sqrt(2.0)});
    w.addPin({100, 109});
    w.addMarble({400, 400}, 10); // far away, never touched
    w.addMarble({100, 113}, 5);
    w.step();
    QCOMPARE_LE(std::abs(w.velocity[0].x - 0.0), 1e-12);
    QCOMPARE_LE(std::abs(w.velocity[0].y - v0y), 1e-12);
    QCOMPARE_LE(std::abs(w.velocity[2].x - 0.0), 1e-12);
    QCOMPARE_LE(std::abs(w.velocity[2].y - v2y), 1e-12);

    // A wall hit is a hit too: with short circuit, the y wall test and the pins are skipped
    // after the x wall. Without it, the pin below reflects (-5,5) into (-5,-5).
    World c = bareWorld(0.0, 0.0, true);
    c.params.shortCircuit = shortCircuit;
    c.addMarble({788, 588}, 10, {5, 5});
    c.addPin({788, 597});
    c.step();
    QCOMPARE(c.velocity[0].x, -5.0);
    QCOMPARE_LE(std::abs(c.velocity[0].y - (shortCircuit ? 5.0 : -5.0)), 1e-12);
}

void TestBookModel::nanGuard_data()
{
    QTest::addColumn<int>("caseId");
    QTest::addRow("resting marble on a pin (|v| = 0)") << 0;
    QTest::addRow("pin at the restored centre (|c| = 0)") << 1;
    QTest::addRow("concentric marbles (|c| = 0)") << 2;
    QTest::addRow("other marble's new speed 0 (cur = 0)") << 3;
    QTest::addRow("moving marble hits resting one from behind at rest") << 4;
}

void TestBookModel::nanGuard()
{
    QFETCH(int, caseId);
    World w = bareWorld();
    switch (caseId) {
    case 0:
        w.addMarble({100, 100}, 10);
        w.addPin({104, 100});
        break;
    case 1:
        w.addMarble({100, 100}, 10, {3, 0});
        w.addPin({100, 100});
        break;
    case 2:
        w.addMarble({100, 100}, 10, {0, 0});
        w.addMarble({100, 100}, 5, {2, 0});
        break;
    case 3:
        // i moves (4, 0) into j moving (-2, 0): unit v_i = (1, 0), c = (1, 0), d = 1,
        // v_j + 2 d c = (0, 0): the book would divide by zero scaling it.
        w.addMarble({100, 100}, 10, {4, 0});
        w.addMarble({122, 100}, 10, {-2, 0});
        break;
    case 4:
        // j is behind i and at rest, touching; i is at rest and j's update finds i: |v_j| = 0.
        w.addMarble({100, 100}, 10);
        w.addMarble({115, 100}, 10);
        break;
    }
    const World before = w;
    const StepResult r = w.step();
    QVERIFY(r.finite);
    for (int i = 0; i < w.marbleCount(); ++i) {
        QVERIFY(isFinite(w.position[i]));
        QVERIFY(isFinite(w.velocity[i]));
    }
    switch (caseId) {
    case 0:
        QCOMPARE(w.position[0], before.position[0]);
        QCOMPARE(w.velocity[0], Vec2{});
        break;
    case 1:
        QCOMPARE(w.position[0], before.position[0]); // restored
        QCOMPARE(w.velocity[0], before.velocity[0]); // unchanged for that hit
        break;
    case 2:
        // Marble 0 is at rest: its own hit has |v| = 0. Marble 1 moves to 102, hits marble 0,
        // goes back to 100, and then c = p0 - p1 = (0, 0): guard, velocity kept.
        QCOMPARE(w.velocity[0], Vec2{});
        QCOMPARE(w.position[1], before.position[1]);
        QCOMPARE(w.velocity[1], before.velocity[1]);
        break;
    case 3:
        QCOMPARE(w.position[0], before.position[0]);
        QCOMPARE(w.velocity[0], before.velocity[0]);
        // j then moves on its own (hits i on its update: v_j = (-2,0) into i at rest).
        QVERIFY(isFinite(w.velocity[1]));
        break;
    case 4:
        QCOMPARE(w.position[0], before.position[0]);
        QCOMPARE(w.position[1], before.position[1]);
        QCOMPARE(w.velocity[0], Vec2{});
        QCOMPARE(w.velocity[1], Vec2{});
        break;
    }
}

void TestBookModel::restingMarbleIsUntouched()
{
    // A marble at rest, with no push and no gravity, is bit-for-bit unchanged by a frame even when
    // it overlaps a pin and another resting marble: the skip of sleeping marbles relies on this.
    World w = bareWorld(0.1, 0.01, true);
    w.addMarble({100, 100}, 10);
    w.addMarble({110, 100}, 10);
    w.addPin({95, 100});
    const World before = w;
    for (int f = 0; f < 5; ++f)
        w.step();
    QCOMPARE(w.position, before.position);
    QCOMPARE(w.velocity, before.velocity);
    QCOMPARE(w.lastHit, before.lastHit);
}

void TestBookModel::lastHitRecordsFigure1112()
{
    World w = bareWorld();
    w.addMarble({100, 100}, 10, {3, 0});
    w.addPin({100 + 9 / std::sqrt(2.0), 100 + 9 / std::sqrt(2.0)});
    w.step();
    const HitRecord &h = w.lastHit[0];
    QCOMPARE(h.frame, std::int64_t(1));
    QCOMPARE_LE(std::abs(h.velocityIn.x - 1.0), tol);
    QCOMPARE_LE(std::abs(h.normal.x - std::sqrt(0.5)), tol);
    QCOMPARE_LE(std::abs(h.normal.y - std::sqrt(0.5)), tol);
    QCOMPARE_LE(std::abs(h.velocityOut.x - 0.0), tol);
    QCOMPARE_LE(std::abs(h.velocityOut.y - -1.0), tol);
}

QTEST_GUILESS_MAIN(TestBookModel)
#include "tst_bookmodel.moc"
