// The exact model (PHYSICS.md, model "exact") against closed-form solutions and conservation laws.

#include "core/exactmodel.h"
#include "core/presets.h"
#include "core/sceneio.h"
#include "core/world.h"

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>

using namespace marbles;

namespace {

// A world with no walls, no friction, no threshold and e = 1 unless a test asks otherwise.
World bareWorld(double friction = 0.0, bool walls = false, double restitution = 1.0)
{
    World w;
    w.stage = {800, 600, walls};
    w.params.model = ModelKind::Exact;
    w.params.friction = friction;
    w.params.zeroThreshold = 0.0;
    w.params.restitution = restitution;
    return w;
}

// `rows` rows of touching marbles of radius `r` resting on the floor of a `width` x `height`
// box, each row in the hollows of the one below, under gravity 0.5 px/frame^2.
World restingPile(double width, double height, double r, int rows, double friction, double restitution)
{
    World w = bareWorld(friction, true, restitution);
    w.stage = {width, height, true};
    w.params.gravity = {0.0, 0.5};
    w.params.zeroThreshold = 0.01;
    for (int row = 0; row < rows; ++row) {
        const double y = height - r - row * r * std::sqrt(3.0);
        for (double x = r + (row % 2) * r; x + r <= width; x += 2 * r)
            w.addMarble({x, y}, r, {0.0, 0.0});
    }
    return w;
}

void run(World &w, ExactModel &model, int frames)
{
    for (int f = 0; f < frames; ++f) {
        model.step(w);
        ++w.frame;
    }
}

double relativeError(double value, double reference)
{
    return std::abs(value - reference) / std::max(std::abs(reference), 1e-300);
}

// The smallest gap in the world: marble-marble, marble-pin and (with walls) marble-wall, px.
// Negative means overlap. O(n^2): for test-sized worlds.
double smallestGap(const World &w)
{
    double gap = std::numeric_limits<double>::infinity();
    const int n = w.marbleCount();
    for (int i = 0; i < n; ++i) {
        const Vec2 p = w.position[i];
        const double r = w.radius[i];
        if (w.stage.walls) {
            gap = std::min({gap, p.x - r, w.stage.width - r - p.x, p.y - r, w.stage.height - r - p.y});
        }
        for (Vec2 q : w.pins)
            gap = std::min(gap, distance(p, q) - r);
        for (int j = i + 1; j < n; ++j)
            gap = std::min(gap, distance(p, w.position[j]) - r - w.radius[j]);
    }
    return gap;
}

// Total |m v|, the scale against which momentum drift is measured.
double momentumScale(const World &w)
{
    double s = 0.0;
    for (int i = 0; i < w.marbleCount(); ++i)
        s += w.mass[i] * length(w.velocity[i]);
    return s;
}

// Closed-form free motion under drag and gravity from (p0, v0) over time t (long double).
struct Free {
    long double p;
    long double v;
};

Free freeMotion(long double p0, long double v0, long double g, long double k, long double t)
{
    if (k == 0.0L)
        return {p0 + v0 * t + g * t * t / 2, v0 + g * t};
    const long double lambda = -std::log1p(-k);
    const long double decay = std::exp(-lambda * t);
    const long double phi1 = -std::expm1(-lambda * t) / lambda;
    // phi2 = (t - phi1) / lambda cancels badly for small lambda t: there, its Taylor series
    // t^2 (1/2 - x/6 + x^2/24 - ...), x = lambda t.
    long double phi2 = (t - phi1) / lambda;
    const long double x = lambda * t;
    if (x < 1e-2L) {
        long double term = 0.5L;
        long double sum = 0.0L;
        for (int n = 0; n < 12; ++n) {
            sum += term;
            term *= -x / (n + 3);
        }
        phi2 = t * t * sum;
    }
    return {p0 + v0 * phi1 + g * phi2, v0 * decay + g * phi1};
}

} // namespace

class TestExactModel : public QObject {
    Q_OBJECT

private slots:
    void dragOnly_data();
    void dragOnly();
    void fallWithDragAndBounce_data();
    void fallWithDragAndBounce();
    void headOn_data();
    void headOn();
    void obliqueElasticEqualMasses_data();
    void obliqueElasticEqualMasses();
    void pinReflection_data();
    void pinReflection();
    void energyKeptInClosedBox();
    void momentumKeptWithoutWalls_data();
    void momentumKeptWithoutWalls();
    void noPassThrough_data();
    void noPassThrough();
    void pushesAndZeroThresholdAtFrameBoundary();
    void freshAndReusedModelsAgree_data();
    void freshAndReusedModelsAgree();
    void inelasticClusterNeverStalls_data();
    void inelasticClusterNeverStalls();
    void headOnAtAnySpeed_data();
    void headOnAtAnySpeed();
    void elasticAtExtremeSpeeds_data();
    void elasticAtExtremeSpeeds();
    void densePileBoundedWork_data();
    void densePileBoundedWork();
    void wedgedMarblesNeverStall_data();
    void wedgedMarblesNeverStall();
    void tooWideMarbleHeldBetweenWalls();
    void marblePastAWallIsNotMoved();
    void hugeGravityKeepsMarblesInside_data();
    void hugeGravityKeepsMarblesInside();
    void marginBelowResolutionNeverStalls_data();
    void marginBelowResolutionNeverStalls();
    void fewMovingAmongResting_data();
    void fewMovingAmongResting();
    void nonFiniteWorldCarriedAlong_data();
    void nonFiniteWorldCarriedAlong();
    void layerKeepsTiesInWedges();
    void finiteCheckIsTheModels_data();
    void finiteCheckIsTheModels();
    void sleepersLayerSameBits_data();
    void sleepersLayerSameBits();
    void sleepersLayerFollowsEdits();
    void sleepersLayerBreaksTiesAlike();
    void sleepersLayerUsedWhenMostRest();
    void oversizeMarblesLeftOutOfGrid_data();
    void oversizeMarblesLeftOutOfGrid();
    void oversizeMarbleReachesFarInOneFrame();
    void sparseFastGasWidensTheMargin();
    void oversizeMarbleFallsFarInOneFrame();
    void brownianPresetWanders();
};

void TestExactModel::dragOnly_data()
{
    QTest::addColumn<double>("friction");
    QTest::addColumn<double>("vx");
    QTest::addColumn<double>("vy");
    QTest::addColumn<int>("frames");
    QTest::addRow("k=0") << 0.0 << 3.0 << -1.5 << 40;
    QTest::addRow("k=0.1") << 0.1 << 3.0 << -1.5 << 40;
    QTest::addRow("k=0.5") << 0.5 << -7.0 << 2.0 << 30;
    QTest::addRow("k=1e-9") << 1e-9 << 5.0 << 5.0 << 25;
    QTest::addRow("k=0.9") << 0.9 << 100.0 << 0.25 << 10;
}

void TestExactModel::dragOnly()
{
    QFETCH(double, friction);
    QFETCH(double, vx);
    QFETCH(double, vy);
    QFETCH(int, frames);
    World w = bareWorld(friction);
    w.addMarble({100, 200}, 10, {vx, vy});
    ExactModel model;
    for (int f = 1; f <= frames; ++f) {
        run(w, model, 1);
        // v(n) = v0 (1 - k)^n, p(n) = p0 + v0 (1 - (1 - k)^n) / lambda (= v0 n when k = 0).
        const Free fx = freeMotion(100, vx, 0, friction, f);
        const Free fy = freeMotion(200, vy, 0, friction, f);
        QCOMPARE_LE(relativeError(w.velocity[0].x, double(fx.v)), 1e-12);
        QCOMPARE_LE(relativeError(w.velocity[0].y, double(fy.v)), 1e-12);
        QCOMPARE_LE(relativeError(w.position[0].x, double(fx.p)), 1e-12);
        QCOMPARE_LE(relativeError(w.position[0].y, double(fy.p)), 1e-12);
    }
    QCOMPARE(w.acceleration[0], Vec2{});
}

void TestExactModel::fallWithDragAndBounce_data()
{
    QTest::addColumn<double>("friction");
    QTest::addColumn<double>("gravity");
    QTest::addColumn<double>("restitution");
    QTest::addRow("no drag, elastic") << 0.0 << 0.5 << 1.0;
    QTest::addRow("drag 0.05, elastic") << 0.05 << 0.5 << 1.0;
    QTest::addRow("drag 0.2, e=0.6") << 0.2 << 2.0 << 0.6;
    QTest::addRow("drag 1e-7, e=0.9") << 1e-7 << 0.3 << 0.9;
}

void TestExactModel::fallWithDragAndBounce()
{
    QFETCH(double, friction);
    QFETCH(double, gravity);
    QFETCH(double, restitution);
    const double r = 10.0;
    const double y0 = 20.0;
    const double floorY = 400.0 - r; // centre height at contact with the bottom wall
    World w = bareWorld(friction, true, restitution);
    w.stage = {200, 400, true};
    w.params.gravity = {0.0, gravity};
    w.addMarble({100, y0}, r, {0.0, 0.0});

    // Reference contact time: y(t) = y0 + g phi2(t) = floorY, by bisection in long double.
    long double lo = 0, hi = 1;
    while (freeMotion(y0, 0, gravity, friction, hi).p < floorY)
        hi *= 2;
    for (int it = 0; it < 200; ++it) {
        const long double mid = (lo + hi) / 2;
        (freeMotion(y0, 0, gravity, friction, mid).p < floorY ? lo : hi) = mid;
    }
    const long double tc = (lo + hi) / 2;
    const long double vc = freeMotion(y0, 0, gravity, friction, tc).v;
    const int hitFrame = static_cast<int>(std::ceil(double(tc)));
    QVERIFY(hitFrame >= 3);

    ExactModel model;
    // Before the bounce: closed-form fall.
    for (int f = 1; f < hitFrame; ++f) {
        run(w, model, 1);
        const Free ref = freeMotion(y0, 0, gravity, friction, f);
        QCOMPARE_LE(relativeError(w.position[0].y, double(ref.p)), 1e-12);
        QCOMPARE_LE(relativeError(w.velocity[0].y, double(ref.v)), 1e-12);
        QCOMPARE(w.position[0].x, 100.0);
    }
    // After the bounce at tc: from the floor with velocity -e vc.
    run(w, model, 1);
    QCOMPARE(w.lastHit[0].frame, std::int64_t(hitFrame));
    QCOMPARE_LE(std::abs(w.lastHit[0].normal.y - 1.0), 1e-15);
    for (int f = hitFrame; f < hitFrame + 3; ++f) {
        if (f > hitFrame)
            run(w, model, 1);
        const Free ref = freeMotion(floorY, -restitution * vc, gravity, friction, f - tc);
        QCOMPARE_LE(std::abs(w.position[0].y - double(ref.p)), 1e-9 * floorY);
        QCOMPARE_LE(std::abs(w.velocity[0].y - double(ref.v)), 1e-9 * double(vc));
    }
}

void TestExactModel::headOn_data()
{
    QTest::addColumn<double>("m1");
    QTest::addColumn<double>("m2");
    QTest::addColumn<double>("v1");
    QTest::addColumn<double>("v2");
    QTest::addColumn<double>("restitution");
    QTest::addRow("elastic 1:3") << 1.0 << 3.0 << 2.5 << -0.5 << 1.0;
    QTest::addRow("elastic 7:2") << 7.0 << 2.0 << 2.0 << 0.0 << 1.0;
    QTest::addRow("inelastic e=0.5") << 2.0 << 5.0 << 3.0 << -1.0 << 0.5;
    QTest::addRow("perfectly inelastic") << 4.0 << 1.0 << 3.0 << 1.0 << 0.0;
    QTest::addRow("elastic 1:1e6") << 1.0 << 1e6 << 4.0 << 0.0 << 1.0;
}

void TestExactModel::headOn()
{
    QFETCH(double, m1);
    QFETCH(double, m2);
    QFETCH(double, v1);
    QFETCH(double, v2);
    QFETCH(double, restitution);
    World w = bareWorld(0.0, false, restitution);
    w.addMarble({100, 300}, 10, {v1, 0}, m1);
    w.addMarble({123, 300}, 12, {v2, 0}, m2);
    ExactModel model;
    run(w, model, 1);
    // Gap 1 px closes at the relative speed: t_c = 1 / (v1 - v2) < 1.
    const double tc = 1.0 / (v1 - v2);
    QVERIFY(tc < 1.0);
    // 1-D impulse: momentum kept, relative velocity reversed and scaled by e.
    const double p = m1 * v1 + m2 * v2;
    const double u1 = (p - m2 * restitution * (v1 - v2)) / (m1 + m2);
    const double u2 = (p + m1 * restitution * (v1 - v2)) / (m1 + m2);
    const double scale = std::abs(v1) + std::abs(v2);
    QCOMPARE_LE(std::abs(w.velocity[0].x - u1), 1e-13 * scale);
    QCOMPARE_LE(std::abs(w.velocity[1].x - u2), 1e-13 * scale);
    QCOMPARE(w.velocity[0].y, 0.0);
    QCOMPARE(w.velocity[1].y, 0.0);
    QCOMPARE_LE(std::abs(w.position[0].x - (100 + v1 * tc + u1 * (1 - tc))), 1e-12 * 200);
    QCOMPARE_LE(std::abs(w.position[1].x - (123 + v2 * tc + u2 * (1 - tc))), 1e-12 * 200);
    QCOMPARE(w.lastHit[0].frame, std::int64_t(1));
    QCOMPARE(w.lastHit[0].normal, (Vec2{1.0, 0.0}));
    QCOMPARE(w.lastHit[1].normal, (Vec2{-1.0, 0.0}));
}

void TestExactModel::obliqueElasticEqualMasses_data()
{
    QTest::addColumn<double>("offset");
    QTest::addRow("b=0.1 r") << 1.0;
    QTest::addRow("b=r") << 10.0;
    QTest::addRow("b=1.9 r") << 19.0;
}

void TestExactModel::obliqueElasticEqualMasses()
{
    QFETCH(double, offset);
    World w = bareWorld();
    const double speed = 3.0;
    w.addMarble({100, 300}, 10, {speed, 0});
    w.addMarble({130, 300 + offset}, 10, {0, 0});
    ExactModel model;
    run(w, model, 10);
    const Vec2 a = w.velocity[0];
    const Vec2 b = w.velocity[1];
    QVERIFY(length(a) > 0.0 && length(b) > 0.0);
    // Equal masses, e = 1, target at rest: the outgoing velocities are perpendicular.
    QCOMPARE_LE(std::abs(dot(a, b)) / (length(a) * length(b)), 1e-12);
    // The target leaves along the line of centres at contact, with speed v cos(theta),
    // sin(theta) = b / (2 r).
    const double sinT = offset / 20.0;
    const double cosT = std::sqrt(1 - sinT * sinT);
    QCOMPARE_LE(std::abs(b.x - speed * cosT * cosT), 1e-12 * speed);
    QCOMPARE_LE(std::abs(b.y - speed * cosT * sinT), 1e-12 * speed);
    QCOMPARE_LE(relativeError(w.kineticEnergy(), 0.5 * w.mass[0] * speed * speed), 1e-14);
}

void TestExactModel::pinReflection_data()
{
    QTest::addColumn<double>("impact");
    QTest::addColumn<double>("restitution");
    QTest::addRow("b=0") << 0.0 << 1.0;
    QTest::addRow("b=3") << 3.0 << 1.0;
    QTest::addRow("b=-7.5") << -7.5 << 1.0;
    QTest::addRow("b=9.99") << 9.99 << 1.0;
    QTest::addRow("b=5, e=0.4") << 5.0 << 0.4;
}

void TestExactModel::pinReflection()
{
    QFETCH(double, impact);
    QFETCH(double, restitution);
    const double r = 10.0;
    const double speed = 2.0;
    World w = bareWorld(0.0, false, restitution);
    w.addMarble({100, 300}, r, {speed, 0});
    w.addPin({150, 300 + impact});
    ExactModel model;
    run(w, model, 40);
    // At contact the normal towards the pin is (cos a, sin a), sin a = b / r. The normal
    // component is reversed and scaled by e, the tangential one kept:
    // v' = v (1,0) - (1 + e) v cos a (cos a, sin a).
    const double sinA = impact / r;
    const double cosA = std::sqrt(1 - sinA * sinA);
    const Vec2 expected{speed * (1 - (1 + restitution) * cosA * cosA), -speed * (1 + restitution) * cosA * sinA};
    QCOMPARE_LE(std::abs(w.velocity[0].x - expected.x), 1e-12 * speed);
    QCOMPARE_LE(std::abs(w.velocity[0].y - expected.y), 1e-12 * speed);
    if (restitution == 1.0) {
        // Outgoing angle: atan2(-sin 2a, -cos 2a).
        const double a = std::asin(sinA);
        const double angle = std::atan2(w.velocity[0].y, w.velocity[0].x);
        const double expectedAngle = std::atan2(-std::sin(2 * a), -std::cos(2 * a));
        QCOMPARE_LE(std::abs(std::remainder(angle - expectedAngle, 2 * std::numbers::pi)), 1e-12);
    }
    QCOMPARE_GE(distance(w.position[0], w.pins[0]), r - 1e-9);
}

void TestExactModel::energyKeptInClosedBox()
{
    // A crowd in a closed box, e = 1, k = 0, sped up so that collisions are frequent.
    World w = makeCrowd(400, 7);
    w.params.zeroThreshold = 0.0;
    for (Vec2 &v : w.velocity)
        v = {v.x * 4, v.y * 4};
    const double e0 = w.kineticEnergy();
    ExactModel model;
    std::int64_t collisions = 0;
    int frames = 0;
    while (collisions < 100000 && frames < 20000) {
        model.step(w);
        ++w.frame;
        ++frames;
        collisions += model.lastCollisionCount();
        QCOMPARE(model.lastFrozenCount(), 0);
    }
    QCOMPARE_GE(collisions, std::int64_t(100000));
    QCOMPARE_LE(relativeError(w.kineticEnergy(), e0), 1e-12);
    QCOMPARE_GE(smallestGap(w), -1e-9);
}

void TestExactModel::momentumKeptWithoutWalls_data()
{
    QTest::addColumn<double>("restitution");
    QTest::addColumn<double>("friction");
    QTest::addRow("e=1, k=0") << 1.0 << 0.0;
    QTest::addRow("e=0.7, k=0") << 0.7 << 0.0;
}

void TestExactModel::momentumKeptWithoutWalls()
{
    QFETCH(double, restitution);
    QFETCH(double, friction);
    World w = makeCrowd(300, 11);
    w.stage.walls = false;
    w.params.restitution = restitution;
    w.params.friction = friction;
    // Converging flow, so the crowd keeps colliding instead of flying apart.
    const Vec2 centre{w.stage.width / 2, w.stage.height / 2};
    for (int i = 0; i < w.marbleCount(); ++i)
        w.velocity[i] = {w.velocity[i].x + (centre.x - w.position[i].x) * 0.01,
                         w.velocity[i].y + (centre.y - w.position[i].y) * 0.01};
    const Vec2 p0 = w.momentum();
    const double scale = momentumScale(w);
    ExactModel model;
    std::int64_t collisions = 0;
    for (int f = 0; f < 200; ++f) {
        model.step(w);
        ++w.frame;
        collisions += model.lastCollisionCount();
        QCOMPARE(model.lastFrozenCount(), 0);
    }
    QCOMPARE_GE(collisions, std::int64_t(1000));
    const Vec2 p1 = w.momentum();
    QCOMPARE_LE(std::abs(p1.x - p0.x), 1e-12 * scale);
    QCOMPARE_LE(std::abs(p1.y - p0.y), 1e-12 * scale);
    QCOMPARE_GE(smallestGap(w), -1e-9);
}

void TestExactModel::noPassThrough_data()
{
    QTest::addColumn<QString>("target");
    QTest::addColumn<double>("speed");
    QTest::addColumn<double>("friction");
    QTest::addColumn<double>("gravity");
    for (const char *target : {"pin", "marble", "wall"}) {
        for (double speed : {1.0, 1e2, 1e4, 1e6}) {
            QTest::addRow("%s v=%g", target, speed) << QString(target) << speed << 0.0 << 0.0;
            QTest::addRow("%s v=%g drag+gravity", target, speed) << QString(target) << speed << 0.1 << 0.5;
        }
    }
}

void TestExactModel::noPassThrough()
{
    QFETCH(QString, target);
    QFETCH(double, speed);
    QFETCH(double, friction);
    QFETCH(double, gravity);
    World w = bareWorld(friction, target == "wall");
    // Gravity along the motion, towards the target: the curved-path solvers are used.
    w.params.gravity = {gravity, 0.0};
    const double r = 10.0;
    w.addMarble({100, 300}, r, {speed, 0.0});
    if (target == "pin")
        w.addPin({400, 303});
    else if (target == "marble")
        w.addMarble({400, 297}, 6, {0.0, 0.0}, 0.5);
    ExactModel model;
    // Slow marbles need a few hundred frames to get there; fast ones bounce many times a frame.
    const int frames = speed < 1e3 ? 1000 : 5;
    for (int f = 0; f < frames; ++f) {
        run(w, model, 1);
        if (target == "pin") {
            // Until the first hit the marble stays on its side (afterwards gravity along +x may
            // legitimately roll it around the pin).
            if (w.lastHit[0].frame < 0)
                QCOMPARE_LT(w.position[0].x, 400.0);
        } else if (target == "marble") {
            // Order along x is kept: the light target was hit and flies off ahead.
            QCOMPARE_LT(w.position[0].x, w.position[1].x);
        } else {
            QCOMPARE_GE(w.position[0].x, r - 1e-9 * speed);
            QCOMPARE_LE(w.position[0].x, 800 - r + 1e-9 * speed);
        }
        QCOMPARE_GE(smallestGap(w), -1e-9 * std::max(1.0, speed));
        QVERIFY(isFinite(w.position[0]) && isFinite(w.velocity[0]));
    }
    // Every case reaches its target, except a slow marble chasing a marble: with the same drag
    // and gravity on both, their gap closes by at most speed / lambda < 290 px.
    if (!(target == "marble" && friction > 0.0 && speed < 50))
        QCOMPARE_GE(w.lastHit[0].frame, std::int64_t(1));
}

void TestExactModel::pushesAndZeroThresholdAtFrameBoundary()
{
    World w = bareWorld(0.5);
    w.params.zeroThreshold = 0.5;
    const int i = w.addMarble({100, 100}, 10, {0.0, 0.0});
    w.push(i, {95, 100}); // a = (5, 0) * 10 / m
    const double dv = 5.0 * 10.0 / w.mass[i];
    ExactModel model;
    run(w, model, 1);
    // Instant velocity change at t = 0, then drag: v = dv (1 - k), p = dv * k / lambda.
    QCOMPARE_LE(relativeError(w.velocity[i].x, dv * 0.5), 1e-14);
    QCOMPARE_LE(relativeError(w.position[i].x, 100 + dv * 0.5 / std::log(2.0)), 1e-14);
    QCOMPARE(w.acceleration[i], Vec2{});
    // The threshold only acts at the frame boundary: |v| drops below 0.5 at the end of a frame.
    while (w.velocity[i].x != 0.0) {
        const double before = w.velocity[i].x;
        run(w, model, 1);
        if (w.velocity[i].x != 0.0)
            QCOMPARE_GT(w.velocity[i].x, 0.5);
        else
            QCOMPARE_LE(before * 0.5, 0.5);
    }
}

void TestExactModel::freshAndReusedModelsAgree_data()
{
    QTest::addColumn<bool>("gravity");
    QTest::addColumn<double>("movingFraction");
    QTest::addColumn<double>("speedScale");
    // Everything at once: gravity, drag, e < 1, pins, walls, pushes.
    QTest::addRow("gravity, drag, e=0.8") << true << 1.0 << 1.0;
    // Most marbles at rest (looked at only from the moving side), the others fast enough to
    // leave their anchor cells (grid events, overflow lists).
    QTest::addRow("few moving, fast, e=0.8") << false << 0.1 << 6.0;
}

void TestExactModel::freshAndReusedModelsAgree()
{
    QFETCH(bool, gravity);
    QFETCH(double, movingFraction);
    QFETCH(double, speedScale);
    World w = makeCrowd(300, 3, movingFraction);
    for (Vec2 &v : w.velocity)
        v = {v.x * speedScale, v.y * speedScale};
    w.params.gravity = gravity ? Vec2{0.05, 0.3} : Vec2{};
    w.params.friction = 0.05;
    w.params.restitution = 0.8;
    w.params.zeroThreshold = 0.01;
    for (int k = 0; k < 40; ++k) {
        // Pins only where no marble covers them: the test checks that no overlap appears.
        const Vec2 q{37.0 + 61.0 * (k % 8), 41.0 + 53.0 * (k / 8)};
        bool covered = false;
        for (int i = 0; i < w.marbleCount(); ++i)
            covered = covered || distance(q, w.position[i]) <= w.radius[i];
        if (!covered)
            w.addPin(q);
    }
    QCOMPARE_GE(w.pins.size(), std::size_t(20));
    w.pushes.push_back({5, 3, {w.position[3].x - 2, w.position[3].y}, {}});

    ExactModel reused;
    {
        // The reused model first sees an unrelated world.
        World other = makeCrowd(50, 99);
        run(other, reused, 3);
    }
    for (int f = 0; f < 60; ++f) {
        for (const Push &p : w.pushes) {
            if (p.frame == w.frame)
                w.push(p.marble, p.at);
        }
        World copy = w;
        reused.step(w);
        ++w.frame;
        ExactModel fresh;
        fresh.step(copy);
        ++copy.frame;
        QVERIFY(std::memcmp(w.position.data(), copy.position.data(), sizeof(Vec2) * w.position.size()) == 0);
        QVERIFY(std::memcmp(w.velocity.data(), copy.velocity.data(), sizeof(Vec2) * w.velocity.size()) == 0);
        QVERIFY(w.lastHit == copy.lastHit);
    }
    QCOMPARE_GE(smallestGap(w), -1e-9);
}

void TestExactModel::inelasticClusterNeverStalls_data()
{
    QTest::addColumn<double>("restitution");
    QTest::addColumn<double>("friction");
    QTest::addRow("e=0") << 0.0 << 0.0;
    QTest::addRow("e=0.5") << 0.5 << 0.1;
    QTest::addRow("e=0.9") << 0.9 << 0.0;
    QTest::addRow("e=1") << 1.0 << 0.02;
}

void TestExactModel::inelasticClusterNeverStalls()
{
    QFETCH(double, restitution);
    QFETCH(double, friction);
    // A pile: rows of touching marbles resting on the floor, the rows stacked in the hollows,
    // plus a few falling in from above, under gravity.
    World w = restingPile(240, 300, 10.0, 5, friction, restitution);
    for (int k = 0; k < 6; ++k)
        w.addMarble({30.0 + 35 * k, 40.0}, 8, {0.3 * k - 1, 2.0});

    // Mechanical energy (kinetic + potential -m g.p) never grows: e <= 1, drag, the zero
    // threshold and the guards (resting contact, freezing) only ever remove energy.
    auto energy = [](const World &world) {
        double e = world.kineticEnergy();
        for (int i = 0; i < world.marbleCount(); ++i)
            e -= world.mass[i] * dot(world.params.gravity, world.position[i]);
        return e;
    };
    const double e0 = energy(w);
    ExactModel model;
    const int n = w.marbleCount();
    for (int f = 0; f < 150; ++f) {
        run(w, model, 1);
        // Bounded work per frame: the guards cap every marble's collisions.
        QCOMPARE_LE(model.lastEventCount(),
                    std::int64_t(n) * (4 * ExactModel::freezeAfterCollisions + 64));
        QCOMPARE_GE(smallestGap(w), -1e-9);
        QCOMPARE_LE(energy(w), e0 + 1e-9 * std::abs(e0));
        for (int i = 0; i < n; ++i)
            QVERIFY(isFinite(w.position[i]) && isFinite(w.velocity[i]));
    }
}

void TestExactModel::headOnAtAnySpeed_data()
{
    QTest::addColumn<double>("speed");
    QTest::addColumn<bool>("pin");
    for (const double v : {1e6, 1e150, 1e155, 1e160, 1e200, 1e300}) {
        QTest::addRow("marbles, v=%g", v) << v << false;
        QTest::addRow("pin, v=%g", v) << v << true;
    }
}

void TestExactModel::headOnAtAnySpeed()
{
    // Two equal marbles head on (or one against a pin), no walls: at any speed they bounce back
    // within the frame. From about 1e154 px/frame the contact equation's squares overflowed a
    // double and they went through each other, velocities unchanged (PHYSICS.md: no body passes
    // through another at any speed; a conformance tester's finding).
    QFETCH(double, speed);
    QFETCH(bool, pin);
    World w = bareWorld(0.0, false, 1.0);
    w.addMarble({0.0, 300.0}, 25.0, {speed, 0.0});
    if (pin)
        w.addPin({400.0, 300.0});
    else
        w.addMarble({400.0, 300.0}, 25.0, {-speed, 0.0});
    ExactModel model;
    run(w, model, 1);
    QCOMPARE_LE(std::abs(w.velocity[0].x + speed), 1e-12 * speed);
    QCOMPARE_LT(w.position[0].x, 0.0);
    if (!pin) {
        QCOMPARE_LE(std::abs(w.velocity[1].x - speed), 1e-12 * speed);
        QCOMPARE_GT(w.position[1].x, 400.0);
    }
}

void TestExactModel::elasticAtExtremeSpeeds_data()
{
    QTest::addColumn<double>("speed");
    QTest::addColumn<double>("gravity");
    QTest::addColumn<int>("frames");
    QTest::addRow("v=1e3") << 1e3 << 0.0 << 200;
    QTest::addRow("v=1e5") << 1e5 << 0.0 << 40;
    QTest::addRow("v=1e6") << 1e6 << 0.0 << 20;
    QTest::addRow("v=1e6 gravity") << 1e6 << 0.5 << 20;
    // More bodies than ExactModel::singleCellItems: the grid and its cell crossings.
    QTest::addRow("v=1e5 grid") << 1e5 << 0.0 << 4;
}

void TestExactModel::elasticAtExtremeSpeeds()
{
    QFETCH(double, speed);
    QFETCH(double, gravity);
    QFETCH(int, frames);
    // Marbles of different sizes and masses, thrown in all directions at up to `speed` px/frame
    // among pins in a closed box, e = 1, no drag: every marble hits walls, pins and other marbles
    // hundreds of times a frame. Mechanical energy (kinetic + potential -m g.p) must be kept, and
    // no marble may leave the box or sink into a pin or another marble.
    World w = bareWorld(0.0, true, 1.0);
    w.params.gravity = {0.0, gravity};
    const bool grid = QByteArray(QTest::currentDataTag()).endsWith("grid");
    SplitMix64 rng(5);
    const int marbles = grid ? 60 : 7;
    const int pins = grid ? 30 : 10;
    for (int k = 0; k < pins; ++k)
        w.addPin({60.0 + 70.0 * (k % 10), 150.0 + 150.0 * (k / 10) + 20.0 * std::sin(k)});
    for (int k = 0; k < marbles; ++k) {
        const double r = rng.uniform(4.0, 15.0);
        const double angle = rng.uniform(0.0, 2 * std::numbers::pi);
        const double v = speed * rng.uniform(0.3, 1.0);
        // Rows between the rows of pins (y = 75, 225, 375, 525): no overlap at the start.
        const int perRow = grid ? 17 : 7;
        const double spacing = grid ? 45.0 : 110.0;
        w.addMarble({40.0 + spacing * (k % perRow), 75.0 + 150.0 * (k / perRow)}, r,
                    {v * std::cos(angle), v * std::sin(angle)});
    }
    QCOMPARE_GE(smallestGap(w), 0.0);
    auto energy = [](const World &world) {
        double e = world.kineticEnergy();
        for (int i = 0; i < world.marbleCount(); ++i)
            e -= world.mass[i] * dot(world.params.gravity, world.position[i]);
        return e;
    };
    const double e0 = energy(w);
    ExactModel model;
    std::int64_t collisions = 0;
    for (int f = 0; f < frames; ++f) {
        run(w, model, 1);
        collisions += model.lastCollisionCount();
        QCOMPARE(model.lastFrozenCount(), 0);
        QCOMPARE_LE(relativeError(energy(w), e0), 1e-9);
        // Walls included: a negative gap against a wall would be a marble (partly) outside.
        QCOMPARE_GE(smallestGap(w), -1e-9);
        for (int i = 0; i < w.marbleCount(); ++i)
            QVERIFY(isFinite(w.position[i]) && isFinite(w.velocity[i]));
    }
    // Each marble crosses the box about speed / 800 times a frame.
    QCOMPARE_GE(double(collisions), 0.5 * frames * marbles * speed / 800.0);
}

void TestExactModel::densePileBoundedWork_data()
{
    QTest::addColumn<double>("restitution");
    QTest::addColumn<double>("friction");
    QTest::addRow("e=0.5") << 0.5 << 0.0;
    QTest::addRow("e=0.5 drag") << 0.5 << 0.05;
    QTest::addRow("e=0") << 0.0 << 0.0;
    QTest::addRow("e=0.95") << 0.95 << 0.0;
}

void TestExactModel::densePileBoundedWork()
{
    QFETCH(double, restitution);
    QFETCH(double, friction);
    // A dense hexagonal pile, 12 rows of touching marbles resting on the floor under gravity,
    // shaken by a few fast marbles dropped on it. With e < 1 a resting cluster is where
    // inelastic collapse lives (infinitely many ever smaller bounces in a finite time); the
    // guards must keep every frame finite. The work is counted in events, not in seconds.
    World w = restingPile(400, 400, 8.0, 12, friction, restitution);
    for (int k = 0; k < 8; ++k)
        w.addMarble({30.0 + 45 * k, 30.0}, 6, {0.5 * k - 2, 6.0});
    QCOMPARE_GE(smallestGap(w), -1e-12);
    const int n = w.marbleCount();
    QVERIFY(n > 250);

    ExactModel model;
    std::int64_t events = 0;
    std::int64_t collisions = 0;
    const int frames = 100;
    for (int f = 0; f < frames; ++f) {
        run(w, model, 1);
        events += model.lastEventCount();
        collisions += model.lastCollisionCount();
        QCOMPARE_GE(smallestGap(w), -1e-9);
        for (int i = 0; i < n; ++i)
            QVERIFY(isFinite(w.position[i]) && isFinite(w.velocity[i]));
    }
    qInfo("%d marbles, %d frames: %lld events, %lld collisions", n, frames, static_cast<long long>(events),
          static_cast<long long>(collisions));
    QVERIFY(collisions > 0);
    // The guard's promise: work per marble and frame is bounded (freezeAfterCollisions, the
    // resting-contact and re-check limits), whatever the restitution.
    QCOMPARE_LE(events, std::int64_t(n) * frames * (4 * ExactModel::freezeAfterCollisions + 64));
    // And in practice far below that cap: a resting pile costs about 16 events per marble and
    // frame (its resting contacts); 64 leaves room, and still catches a guard that lets a pile
    // grind through hundreds of collisions per marble.
    QCOMPARE_LE(events, std::int64_t(n) * frames * 64);
}

void TestExactModel::wedgedMarblesNeverStall_data()
{
    QTest::addColumn<double>("restitution");
    QTest::addColumn<double>("gravity");
    for (const double e : {1.0, 0.8}) {
        for (const double g : {0.0, 0.3}) {
            QTest::addRow("e=%g g=%g", e, g) << e << g;
        }
    }
}

void TestExactModel::wedgedMarblesNeverStall()
{
    QFETCH(double, restitution);
    QFETCH(double, gravity);
    // Marbles placed where they cannot fit: each contact sends them straight into the next at
    // the same instant, which with e = 1 once never ended (found by fuzz/fuzz_physics). Every
    // frame must finish with bounded work and finite numbers.
    World w = bareWorld(0.0, true, restitution);
    w.params.gravity = {0.0, gravity};
    // Overlapping two pins at once.
    w.addMarble({100, 100}, 20, {1, 0});
    w.addPin({85, 100});
    w.addPin({115, 100});
    // Overlapping a pin and the left wall.
    w.addMarble({15, 300}, 20, {-1, 0});
    w.addPin({25, 300});
    // Wider than the stage along y, pushed around by a small marble inside it.
    w.addMarble({500, 300}, 320, {0.5, 2});
    w.addMarble({520, 280}, 6, {3, -1});
    const int n = w.marbleCount();
    ExactModel model;
    for (int f = 0; f < 20; ++f) {
        run(w, model, 1);
        // The loops take no time: the guard at one instant ends them (without it, the per-frame
        // limits would, after 16,384 collisions a marble).
        QCOMPARE_LE(model.lastEventCount(), std::int64_t(n) * 2 * ExactModel::freezeAfterInstantCollisions);
        for (int i = 0; i < n; ++i)
            QVERIFY(isFinite(w.position[i]) && isFinite(w.velocity[i]));
    }

    // Two marbles side by side in a stage narrower than both.
    World narrow = bareWorld(0.0, true, restitution);
    narrow.params.gravity = {0.0, gravity};
    narrow.stage = {30, 300, true};
    narrow.addMarble({10, 100}, 10, {-1, 0});
    narrow.addMarble({25, 100}, 10, {-1, 0});
    ExactModel other;
    for (int f = 0; f < 20; ++f) {
        run(narrow, other, 1);
        QCOMPARE_LE(other.lastEventCount(), 2 * 2 * ExactModel::freezeAfterInstantCollisions);
        for (int i = 0; i < 2; ++i)
            QVERIFY(isFinite(narrow.position[i]) && isFinite(narrow.velocity[i]));
    }
}

void TestExactModel::tooWideMarbleHeldBetweenWalls()
{
    // A marble wider than the stage along y (2 r = 700 > 600) but not along x: the walls hold it
    // where it is along y, at once and without freezing it, while it keeps bouncing along x with
    // its speed (e = 1).
    World w = bareWorld(0.0, true, 1.0);
    w.addMarble({400, 280}, 350, {3, 2});
    ExactModel model;
    for (int f = 0; f < 40; ++f) {
        run(w, model, 1);
        QCOMPARE(model.lastFrozenCount(), 0);
        QCOMPARE(w.position[0].y, 280.0);
        QCOMPARE(w.velocity[0].y, 0.0);
        QCOMPARE(std::abs(w.velocity[0].x), 3.0);
        QVERIFY(model.lastEventCount() <= 4);
    }
    // It went right, met the right wall at x = 800 - 350 and came back: still between the walls.
    QCOMPARE_GE(w.position[0].x, 350.0 - 1e-9);
    QCOMPARE_LE(w.position[0].x, 450.0 + 1e-9);
    QCOMPARE_LT(w.position[0].x, 400.0 + 3.0 * 40);
}

void TestExactModel::marblePastAWallIsNotMoved()
{
    // Placed 5 px past the right wall and moving out, beside a marble 3 px clear of it. It
    // bounces where it is and leaves the wall by its own motion: before, the bounce put it at
    // contact with the wall, a jump of 5 px that sank it 2 px into its neighbour (found by
    // fuzz/fuzz_physics).
    World w = bareWorld(0.0, true, 1.0);
    w.addMarble({790, 300}, 15, {2, 0});
    w.addMarble({762, 300}, 10, {0, 0});
    ExactModel model;
    double x = w.position[0].x;
    for (int f = 0; f < 10; ++f) {
        run(w, model, 1);
        QCOMPARE_LE(std::abs(w.position[0].x - x), 2.0 + 1e-9); // no jump: at most its speed
        x = w.position[0].x;
        const double gap = distance(w.position[0], w.position[1]) - 25.0;
        QCOMPARE_GE(gap, -1e-9);
    }
    // It came back and met the neighbour, which now moves left too.
    QCOMPARE_LT(w.velocity[0].x, 0.0);
    QCOMPARE_LT(w.velocity[1].x, 0.0);
}

void TestExactModel::hugeGravityKeepsMarblesInside_data()
{
    QTest::addColumn<Vec2>("gravity");
    QTest::addRow("1e33 down") << Vec2{0, 1e33};
    QTest::addRow("1e34 down") << Vec2{0, 1e34};
    QTest::addRow("1e35 down") << Vec2{0, 1e35};
    QTest::addRow("1e34 up") << Vec2{0, -1e34};
    QTest::addRow("1e34 sideways") << Vec2{1e34, 0};
    QTest::addRow("1e300 down") << Vec2{0, 1e300};
    QTest::addRow("1e308 down") << Vec2{0, 1e308};
    QTest::addRow("1e308 up") << Vec2{0, -1e308};
    QTest::addRow("1e308 left") << Vec2{-1e308, 0};
    QTest::addRow("1e308 right") << Vec2{1e308, 0};
}

void TestExactModel::hugeGravityKeepsMarblesInside()
{
    // From about 1e33 px/frame^2 a falling marble's bounces are closer together than a double
    // tells apart: it ended the frame 0.6 to 10,000 px past the floor, and the pachinko board's
    // marbles likewise. Each ends on the wall it would have gone through.
    QFETCH(Vec2, gravity);
    World w = bareWorld(0.0, true, 1.0);
    w.params.gravity = gravity;
    for (int i = 0; i < 8; ++i)
        w.addMarble({100.0 + 80.0 * i, 150.0 + 40.0 * (i % 3)}, 5.0 + 3.0 * i, {1.5 * i - 5.0, 2.0});
    // Placed past the floor and the right wall: left to leave by its own motion, not moved.
    w.addMarble({790, 595}, 20, {0, 0});
    const Vec2 placed = w.position[8];
    ExactModel model;
    for (int f = 0; f < 3; ++f) {
        run(w, model, 1);
        for (int i = 0; i < 8; ++i) {
            const Vec2 p = w.position[static_cast<std::size_t>(i)];
            const double r = w.radius[static_cast<std::size_t>(i)];
            QVERIFY2(p.x >= r && p.x <= 800 - r && p.y >= r && p.y <= 600 - r,
                     qPrintable(QStringLiteral("frame %1, marble %2 at (%3, %4)").arg(f + 1).arg(i).arg(p.x).arg(p.y)));
            QVERIFY(std::isfinite(w.velocity[static_cast<std::size_t>(i)].x));
        }
        if (gravity.y > 0.0 && f == 0)
            QVERIFY2(w.position[8].y > 580.0 + 1e-9 || w.position[8] == placed, "the placed marble was snapped");
    }

    // Placed across a wall, alone: it may leave through that wall, never through the opposite
    // one (placed across the ceiling under 1e308 px/frame^2 down, it ended 3.7e277 px below the
    // floor; a conformance tester's finding).
    constexpr double tolerance = 1e-6;
    const struct {
        Vec2 at;
        double low;  // its least x or y: within the opposite wall
        double high; // its greatest
        bool vertical;
        bool falls;  // gravity takes it towards the opposite wall
    } placements[] = {
        {{400, 10}, -1e300, 575.0, true, gravity.y > 0.0},   // across the ceiling: never below the floor
        {{400, 590}, 25.0, 1e300, true, gravity.y < 0.0},    // across the floor: never above the ceiling
        {{10, 300}, -1e300, 775.0, false, gravity.x > 0.0},  // across the left wall
        {{790, 300}, 25.0, 1e300, false, gravity.x < 0.0},   // across the right wall
    };
    for (const auto &placed : placements) {
        // (From 1e33 on the old code let it through; a frame that ends resting on a wall under
        // 1e33 to 1e35 takes up to a second, at 1e300 and more a moment.)
        if (!placed.falls || length(gravity) < 1e300)
            continue;
        World across = bareWorld(0.1, true, 1.0); // the default friction and threshold, as where it was found
        across.params.zeroThreshold = 0.01;
        across.params.gravity = gravity;
        across.addMarble(placed.at, 25, {0, 0});
        ExactModel alone;
        for (int f = 0; f < 3; ++f) {
            run(across, alone, 1);
            const Vec2 p = across.position[0];
            const double along = placed.vertical ? p.y : p.x;
            QVERIFY2(along >= placed.low - tolerance && along <= placed.high + tolerance,
                     qPrintable(QStringLiteral("placed at (%1, %2), frame %3: (%4, %5)")
                                    .arg(placed.at.x).arg(placed.at.y).arg(f + 1).arg(p.x).arg(p.y)));
        }
    }
}

void TestExactModel::marginBelowResolutionNeverStalls_data()
{
    QTest::addColumn<double>("radius");
    QTest::addColumn<double>("x0");
    QTest::addRow("tiny marbles") << 1e-20 << 50.0;
    QTest::addRow("far from the origin") << 10.0 << 1e17;
}

void TestExactModel::marginBelowResolutionNeverStalls()
{
    QFETCH(double, radius);
    QFETCH(double, x0);
    // Enough marbles for the grid, whose margin (a quarter of the contact distance) is below the
    // resolution of their coordinates: each grid event re-anchored the marble where it was and
    // fired again at once, for ever (found by fuzz/fuzz_physics). Every frame must end.
    World w = bareWorld(0.0, false, 1.0);
    for (int k = 0; k < 2 * ExactModel::singleCellItems; ++k)
        w.addMarble({x0 + 100.0 * k, 100.0 + k}, radius, {1.0, 0.5});
    ExactModel model;
    for (int f = 0; f < 5; ++f) {
        run(w, model, 1);
        QCOMPARE_LE(model.lastEventCount(), std::int64_t(w.marbleCount()) * 4);
        for (int i = 0; i < w.marbleCount(); ++i)
            QVERIFY(isFinite(w.position[i]) && isFinite(w.velocity[i]));
    }
}

void TestExactModel::fewMovingAmongResting_data()
{
    QTest::addColumn<double>("movingFraction");
    QTest::addColumn<bool>("walls");
    QTest::addRow("2%% moving, walls") << 0.02 << true;
    QTest::addRow("2%% moving, no walls") << 0.02 << false;
    QTest::addRow("30%% moving, walls") << 0.3 << true;
}

void TestExactModel::fewMovingAmongResting()
{
    QFETCH(double, movingFraction);
    QFETCH(bool, walls);
    // A crowd in which most marbles start at rest: the first look of each frame tests pairs only
    // from their moving side, so a resting marble must still be found by every marble that runs
    // into it, in every frame. Sped up so that each moving marble crosses several cells a frame.
    World w = makeCrowd(1500, 17, movingFraction);
    w.stage.walls = walls;
    for (Vec2 &v : w.velocity)
        v = {v.x * 5, v.y * 5};
    const double e0 = w.kineticEnergy();
    const Vec2 p0 = w.momentum();
    const double scale = momentumScale(w);
    ExactModel model;
    std::int64_t collisions = 0;
    for (int f = 0; f < 60; ++f) {
        run(w, model, 1);
        collisions += model.lastCollisionCount();
        QCOMPARE(model.lastFrozenCount(), 0);
        QCOMPARE_GE(smallestGap(w), -1e-9);
    }
    QCOMPARE_GE(collisions, std::int64_t(200));
    QCOMPARE_LE(relativeError(w.kineticEnergy(), e0), 1e-12);
    if (!walls) {
        const Vec2 p1 = w.momentum();
        QCOMPARE_LE(std::abs(p1.x - p0.x), 1e-12 * scale);
        QCOMPARE_LE(std::abs(p1.y - p0.y), 1e-12 * scale);
    }
}

void TestExactModel::nonFiniteWorldCarriedAlong_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addColumn<QString>("bad");
    QTest::addRow("few (all pairs), NaN position") << 20 << "nan position";
    QTest::addRow("few (all pairs), infinite speed") << 20 << "infinite speed";
    QTest::addRow("crowd (grid), NaN position") << 2000 << "nan position";
    QTest::addRow("crowd (grid), infinite speed") << 2000 << "infinite speed";
    QTest::addRow("crowd (grid), NaN radius") << 2000 << "nan radius";
    // A NaN y, which std::max passes over, recursed between straightContact() and its scaled form
    // until the stack ran out.
    QTest::addRow("few (all pairs), NaN y") << 20 << "nan y";
    QTest::addRow("crowd (grid), NaN y") << 2000 << "nan y";
    QTest::addRow("crowd (grid), NaN speed y") << 2000 << "nan speed y";
}

void TestExactModel::nonFiniteWorldCarriedAlong()
{
    QFETCH(int, marbles);
    QFETCH(QString, bad);
    // A world that has left finite numbers (World::step reports it) is only carried along: every
    // marble moves straight on, no collision is resolved, and the step returns.
    World w = makeCrowd(marbles, 5, 1.0);
    w.params.model = ModelKind::Exact;
    const int broken = marbles / 2;
    if (bad == "nan position")
        w.position[broken].x = std::numeric_limits<double>::quiet_NaN();
    else if (bad == "nan y")
        w.position[broken].y = std::numeric_limits<double>::quiet_NaN();
    else if (bad == "nan speed y")
        w.velocity[broken].y = std::numeric_limits<double>::quiet_NaN();
    else if (bad == "infinite speed")
        w.velocity[broken].y = std::numeric_limits<double>::infinity();
    else
        w.radius[broken] = std::numeric_limits<double>::quiet_NaN();
    const World before = w;
    ExactModel model;
    run(w, model, 1);
    QCOMPARE(model.lastEventCount(), std::int64_t(0));
    for (int i = 0; i < marbles; ++i) {
        if (i == broken)
            continue;
        // Without friction or gravity a frame of straight motion is p + v (to rounding).
        const Vec2 p = w.position[i];
        const Vec2 v = w.velocity[i];
        QCOMPARE_LE(std::abs(p.x - (before.position[i].x + before.velocity[i].x)), 1e-9);
        QCOMPARE_LE(std::abs(p.y - (before.position[i].y + before.velocity[i].y)), 1e-9);
        QCOMPARE_LE(std::abs(v.x - before.velocity[i].x), 1e-12);
        QCOMPARE_LE(std::abs(v.y - before.velocity[i].y), 1e-12);
    }

    // That frame stopped after the first look, with events left in the calendar: the model's
    // next frames, on a finite world of the same size, must not see them (same bits as a fresh
    // model, and events handled again).
    World next = makeCrowd(marbles, 6, 1.0);
    World copy = next;
    run(next, model, 3);
    QCOMPARE_GT(model.lastEventCount(), std::int64_t(0));
    ExactModel fresh;
    run(copy, fresh, 3);
    QVERIFY(std::memcmp(next.position.data(), copy.position.data(), sizeof(Vec2) * next.position.size()) == 0);
    QVERIFY(std::memcmp(next.velocity.data(), copy.velocity.data(), sizeof(Vec2) * next.velocity.size()) == 0);
}

QTEST_APPLESS_MAIN(TestExactModel)
namespace {

// Everything a frame changes, compared bit for bit: positions, velocities, pending pushes and
// last hits.
bool sameState(const World &a, const World &b)
{
    auto same = [](const std::vector<Vec2> &x, const std::vector<Vec2> &y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), sizeof(Vec2) * x.size()) == 0;
    };
    return same(a.position, b.position) && same(a.velocity, b.velocity) && same(a.acceleration, b.acceleration)
        && a.lastHit == b.lastHit;
}

// Steps `w` with the sleepers kept in their layer (`layered`) and a copy of it with every
// marble read every frame, and checks that each frame comes out the same bits, with the same
// events. Returns the marbles that woke (at rest before a frame, moving after it) in frames the
// layer was in use: the ones the layer had to hand over to the moving marbles.
// `edit(world, frame, which)`, when given, changes each world (0: layered, 1: plain) before each frame.
int compareWithoutLayer(World &w, ExactModel &layered, int frames,
                        const std::function<void(World &, int, int)> &edit = {})
{
    World plain = w;
    ExactModel reference;
    reference.setSleeping(ExactModel::Sleeping::Never);
    int woken = 0;
    for (int f = 0; f < frames; ++f) {
        if (edit) {
            edit(w, f, 0);
            edit(plain, f, 1);
        }
        std::vector<char> resting(static_cast<std::size_t>(w.marbleCount()));
        for (int i = 0; i < w.marbleCount(); ++i)
            resting[i] = w.velocity[i] == Vec2{};
        run(w, layered, 1);
        run(plain, reference, 1);
        if (!sameState(w, plain) || layered.lastEventCount() != reference.lastEventCount()
            || layered.lastCollisionCount() != reference.lastCollisionCount()) {
            qWarning("frame %d differs", f + 1);
            return -1;
        }
        if (layered.lastSleepingCount() > 0) {
            for (int i = 0; i < w.marbleCount(); ++i)
                woken += resting[i] && !(w.velocity[i] == Vec2{});
        }
    }
    return woken;
}

} // namespace

void TestExactModel::sleepersLayerSameBits_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addColumn<double>("movingFraction");
    QTest::addColumn<double>("speedScale");
    QTest::addColumn<double>("friction");
    QTest::addColumn<double>("restitution");
    QTest::addColumn<bool>("walls");
    QTest::addColumn<int>("pins");
    QTest::addColumn<int>("giants");
    QTest::addColumn<double>("giantSpeed");
    QTest::addRow("2%% moving") << 2000 << 0.02 << 1.0 << 0.0 << 1.0 << true << 0 << 0 << 0.0;
    // Fast marbles leave their anchors: woken sleepers move bucket and come back.
    QTest::addRow("10%% moving, 5x speed, no walls") << 2000 << 0.1 << 5.0 << 0.0 << 1.0 << false << 0 << 0 << 0.0;
    // Marbles come to rest (friction and threshold), so the layer is built again as they do.
    QTest::addRow("friction, pins") << 2000 << 0.3 << 3.0 << 0.05 << 1.0 << true << 30 << 0 << 0.0;
    QTest::addRow("e = 0.5") << 1500 << 0.1 << 3.0 << 0.0 << 0.5 << true << 0 << 0 << 0.0;
    // Giants (left out of the grid, never in the layer) ploughing through sleepers, or at rest
    // among them while a few marbles move: their searches take the sleepers in.
    QTest::addRow("giants through sleepers") << 2000 << 0.0 << 1.0 << 0.0 << 1.0 << true << 0 << 3 << 12.0;
    QTest::addRow("fast giants, no walls, pins") << 2000 << 0.02 << 2.0 << 0.0 << 1.0 << false << 20 << 2 << 60.0;
    QTest::addRow("giants at rest, 5%% moving") << 2000 << 0.05 << 3.0 << 0.0 << 1.0 << true << 0 << 4 << 0.0;
    QTest::addRow("giants, friction") << 2000 << 0.05 << 3.0 << 0.05 << 1.0 << true << 10 << 2 << 20.0;
}

void TestExactModel::sleepersLayerSameBits()
{
    // The layer is a way of storing the marbles at rest: with it or without it, every frame must
    // come out the same bits (PHYSICS.md, determinism; issue 5: each skip gives the same results).
    QFETCH(int, marbles);
    QFETCH(double, movingFraction);
    QFETCH(double, speedScale);
    QFETCH(double, friction);
    QFETCH(double, restitution);
    QFETCH(bool, walls);
    QFETCH(int, pins);
    QFETCH(int, giants);
    QFETCH(double, giantSpeed);
    World w = makeCrowdWithGiants(marbles, 11, giants, 70.0, movingFraction);
    for (Vec2 &v : w.velocity)
        v = {v.x * speedScale, v.y * speedScale};
    for (int i = 0, k = 0; i < w.marbleCount(); ++i) {
        if (w.radius[i] == 70.0) {
            const double angle = 1.0 + 2.1 * k++;
            w.velocity[i] = {giantSpeed * std::cos(angle), giantSpeed * std::sin(angle)};
        }
    }
    QCOMPARE(splitRadii(w.radius).oversize, giants);
    w.params.friction = friction;
    w.params.zeroThreshold = friction > 0.0 ? 0.05 : 0.0;
    w.params.restitution = restitution;
    w.stage.walls = walls;
    for (int k = 0; k < pins; ++k)
        w.addPin({w.stage.width * ((k * 37) % 101) / 101.0, w.stage.height * ((k * 53) % 97) / 97.0});
    ExactModel layered;
    layered.setSleeping(ExactModel::Sleeping::Always);
    const int woken = compareWithoutLayer(w, layered, 80);
    QCOMPARE_GE(woken, 20); // the layer was used, and marbles in it were hit
}

void TestExactModel::layerKeepsTiesInWedges()
{
    // A fuzzer's finding: a marble resting in the top left corner (in the sleepers' layer, or in
    // the frame's arrays without it) is hit by marbles wedged against a giant; at one instant two
    // partners' contacts fell on the same time, one of them 1.26 units in the last place of the
    // time left beyond the other, and only the one offered first was kept. The layer offers the
    // marbles it promotes last: positions a few units in the last place apart. (65 marbles: none
    // can be taken out without losing the difference, which follows the grid's lattice.)
    QFile file(QStringLiteral(MARBLES_SOURCE_DIR "/tests/core/data/exact-layer-corner.marbles.json"));
    QVERIFY(file.open(QIODevice::ReadOnly));
    const QByteArray text = file.readAll();
    const SceneLoad load = parseScene(std::string_view(text.constData(), static_cast<std::size_t>(text.size())), "corner");
    QVERIFY2(load.ok, load.error.c_str());
    World layered = load.world;
    World plain = load.world;
    ExactModel withLayer;
    withLayer.setSleeping(ExactModel::Sleeping::Always);
    ExactModel withoutLayer;
    withoutLayer.setSleeping(ExactModel::Sleeping::Never);
    withLayer.step(layered);
    withoutLayer.step(plain);
    QVERIFY(withLayer.lastSleepingCount() > 0); // the corner's marble was in the layer
    for (int i = 0; i < plain.marbleCount(); ++i) {
        QVERIFY2(sameBits(layered.position[i], plain.position[i]), qPrintable(QString::number(i)));
        QVERIFY2(sameBits(layered.velocity[i], plain.velocity[i]), qPrintable(QString::number(i)));
    }
}

void TestExactModel::finiteCheckIsTheModels_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addColumn<double>("movingFraction");
    QTest::addColumn<QString>("bad");
    QTest::addRow("few (all pairs)") << 20 << 1.0 << "";
    QTest::addRow("crowd (grid)") << 2000 << 1.0 << "";
    QTest::addRow("crowd at rest (layer)") << 2000 << 0.02 << "";
    QTest::addRow("few, NaN position") << 20 << 1.0 << "nan position";
    QTest::addRow("crowd, infinite speed") << 2000 << 1.0 << "infinite speed";
    QTest::addRow("sleeper given a NaN position") << 2000 << 0.02 << "nan sleeper";
    QTest::addRow("sleeper given an infinite position") << 2000 << 0.02 << "infinite sleeper";
    QTest::addRow("flown past the doubles") << 1 << 1.0 << "1.7e308";
}

void TestExactModel::finiteCheckIsTheModels()
{
    // The model says whether its frame left every position and velocity finite, so that
    // World::step() need not read them all again (a skip: the same report as without it). It must
    // say so exactly when it is so, the marbles kept at rest in the layer included.
    QFETCH(int, marbles);
    QFETCH(double, movingFraction);
    QFETCH(QString, bad);
    World w = makeCrowd(marbles, 9, movingFraction);
    if (bad == "1.7e308") { // no walls: its x is 1.7e308 after one frame, infinite after two
        w = World();
        w.params.friction = 0.0;
        w.stage.walls = false;
        w.addMarble({200.0, 300.0}, 20.0, {1.7e308, 0.0});
    }
    ExactModel model;
    int sawLayer = 0;
    for (int f = 0; f < 12; ++f) {
        if (f == 6 && !bad.isEmpty() && bad != QLatin1String("1.7e308")) {
            int k = marbles / 2;
            if (bad.endsWith(QLatin1String("sleeper"))) {
                while (!(w.velocity[k] == Vec2{}))
                    ++k; // one at rest, kept in the layer
            }
            const double nan = std::numeric_limits<double>::quiet_NaN();
            const double inf = std::numeric_limits<double>::infinity();
            if (bad == QLatin1String("infinite speed"))
                w.velocity[k].y = inf;
            else
                w.position[k].x = bad.startsWith(QLatin1String("infinite")) ? inf : nan;
        }
        model.step(w);
        ++w.frame;
        sawLayer += model.lastSleepingCount() > 0;
        QCOMPARE(model.leftAllFinite(), w.firstNonFiniteMarble() < 0);
    }
    if (movingFraction < 1.0)
        QCOMPARE_GT(sawLayer, 5);
    QCOMPARE(w.firstNonFiniteMarble() < 0, bad.isEmpty());
}

void TestExactModel::sleepersLayerFollowsEdits()
{
    // Between frames the World may change under the layer: a sleeper moved, resized or pushed, a
    // marble removed, an earlier frame restored (Step Back). Each must be seen.
    World w = makeCrowd(1500, 5, 0.05);
    const World start = w;
    ExactModel layered;
    layered.setSleeping(ExactModel::Sleeping::Always);
    World saved[2];
    auto edit = [&](World &x, int f, int which) {
        // Every frame some marbles at rest move a few px or change size (enough of them that
        // moving marbles run into some), and one gets a push.
        for (int e = 0; e < 30; ++e) {
            const int k = ((f * 30 + e) * 7919) % x.marbleCount();
            if (!(x.velocity[k] == Vec2{}))
                continue;
            if (e % 2 == 0)
                x.position[k].x += 3.0;
            else
                x.setRadius(k, x.radius[k] * (e % 4 == 1 ? 1.15 : 0.8));
        }
        const int k = (f * 104729) % x.marbleCount();
        if (f % 3 == 0)
            x.push(k, {x.position[k].x - 3.0, x.position[k].y + 1.0});
        if (f == 20)
            x.removeMarble(7);
        if (f == 30)
            saved[which] = x;
        if (f == 45)
            x = saved[which]; // back to frame 30, as Step Back does
    };
    QCOMPARE_GE(compareWithoutLayer(w, layered, 70, edit), 20);
    QVERIFY(!sameState(w, start));
}

void TestExactModel::sleepersLayerBreaksTiesAlike()
{
    // Ties between events at the same instant are broken by each marble's place among all
    // marbles in bucket order, sleepers included, as if every marble were in the arrays. Here a
    // moving marble reaches two resting ones at exactly the same time (mirror images): one a
    // sleeper, the other awake (its velocity is -0, at rest but not asleep). Which it hits first
    // decides where all three go. Many sleepers lie in earlier buckets, so an awake marble's
    // index among the awake ones alone is far below its place among all.
    World w = bareWorld(0.0, true);
    for (int k = 0; k < 150; ++k)
        w.addMarble({15.0 + 25.0 * (k % 30), 15.0 + 25.0 * (k / 30)}, 10.0);
    for (int t = 0; t < 6; ++t) {
        const double x = 60.0 + 120.0 * t;
        w.addMarble({x, 300.0}, 10.0, {2.0, 0.0});
        w.addMarble({x + 30.0, 288.0}, 10.0);
        w.addMarble({x + 30.0, 312.0}, 10.0, {-0.0, 0.0});
    }
    ExactModel layered;
    layered.setSleeping(ExactModel::Sleeping::Always);
    QCOMPARE_GE(compareWithoutLayer(w, layered, 30), 12);
}

void TestExactModel::sleepersLayerUsedWhenMostRest()
{
    // By default the layer is used from sleepingLayerFrom marbles on, where nearly every marble
    // rests.
    World few = makeCrowd(ExactModel::sleepingLayerFrom, 2, 0.01);
    ExactModel model;
    QCOMPARE_GE(compareWithoutLayer(few, model, 3), 0);
    QCOMPARE_GT(model.lastSleepingCount(), ExactModel::sleepingLayerFrom / 2);
    // Once many are awake again, every marble is read every frame.
    for (int i = 0; i < few.marbleCount(); i += 4)
        few.velocity[i] = {0.5, -0.25};
    QCOMPARE_GE(compareWithoutLayer(few, model, 2), 0);
    QCOMPARE(model.lastSleepingCount(), 0);
    World many = makeCrowd(ExactModel::sleepingLayerFrom, 2, 0.5);
    ExactModel busy;
    QCOMPARE_GE(compareWithoutLayer(many, busy, 3), 0);
    QCOMPARE(busy.lastSleepingCount(), 0);
    World small = makeCrowd(ExactModel::sleepingLayerFrom / 2, 2, 0.01);
    ExactModel smallModel;
    QCOMPARE_GE(compareWithoutLayer(small, smallModel, 3), 0);
    QCOMPARE(smallModel.lastSleepingCount(), 0);
}

void TestExactModel::oversizeMarblesLeftOutOfGrid_data()
{
    QTest::addColumn<int>("giants");
    QTest::addColumn<double>("giantSpeed");
    QTest::addColumn<double>("movingFraction");
    QTest::addColumn<bool>("walls");
    QTest::addColumn<bool>("withPins");
    QTest::addColumn<double>("gravity");
    QTest::addColumn<double>("restitution");
    QTest::addColumn<double>("crowdSpeedup");
    QTest::addColumn<int>("marbles");
    QTest::addColumn<int>("comparedFrames");
    QTest::addRow("one giant") << 1 << 3.0 << 1.0 << true << false << 0.0 << 1.0 << 1.0 << 1500 << 4;
    QTest::addRow("fast giants, pins") << 3 << 25.0 << 1.0 << true << true << 0.0 << 1.0 << 1.0 << 1500 << 4;
    QTest::addRow("giants, no walls") << 4 << 6.0 << 1.0 << false << false << 0.0 << 1.0 << 1.0 << 1500 << 4;
    QTest::addRow("giants among resting marbles") << 2 << 8.0 << 0.05 << true << true << 0.0 << 1.0 << 1.0 << 1500 << 4;
    QTest::addRow("resting giants") << 3 << 0.0 << 1.0 << true << false << 0.0 << 1.0 << 1.0 << 1500 << 4;
    QTest::addRow("giants, gravity, e = 0.9") << 2 << 4.0 << 1.0 << true << true << 0.2 << 0.9 << 1.0 << 1500 << 4;
    // Small marbles crossing cells within a frame (re-anchored in other buckets' lists).
    QTest::addRow("fast crowd, fast giants") << 3 << 30.0 << 1.0 << true << true << 0.0 << 1.0 << 6.0 << 1500 << 4;
    // Sixteen giants in a crowd at 20 times its speeds: the small marbles stray up to the margin
    // from their anchors within a frame while the giants change course again and again, and a
    // giant's search after each change must take in the marbles anchored up to a margin beyond
    // its reach (without it a giant sinks 0.4 px into a marble in frame 6). Compared with the grid
    // sized from the largest radius only for no overlap: rounding differences grow to the size
    // of a marble within four frames at these speeds.
    QTest::addRow("very fast crowd, many giants") << 16 << 10.0 << 1.0 << true << false << 0.0 << 1.0 << 20.0 << 3000 << 0;
}

void TestExactModel::oversizeMarblesLeftOutOfGrid()
{
    QFETCH(int, giants);
    QFETCH(double, giantSpeed);
    QFETCH(double, movingFraction);
    QFETCH(bool, walls);
    QFETCH(bool, withPins);
    QFETCH(double, gravity);
    QFETCH(double, restitution);
    QFETCH(double, crowdSpeedup);
    QFETCH(int, marbles);
    QFETCH(int, comparedFrames);
    // A few marbles far larger than the rest (RadiusSplit) are left out of the grid, whose cells
    // are sized from the others: they must still meet every marble and pin, from either side,
    // and the run must be the one a grid sized from the largest radius gives. (Not the same bits:
    // the giants' places in the order change, and with them the order of a pair's arithmetic.)
    World w = makeCrowdWithGiants(marbles, 23, giants, 70.0, movingFraction);
    w.stage.walls = walls;
    w.params.gravity = {0.0, gravity};
    w.params.restitution = restitution;
    SplitMix64 rng(5);
    std::vector<int> giantIndex;
    for (int i = 0; i < w.marbleCount(); ++i) {
        if (w.radius[i] == 70.0) {
            giantIndex.push_back(i);
            const double angle = rng.uniform(0.0, 6.283185307179586);
            w.velocity[i] = {giantSpeed * std::cos(angle), giantSpeed * std::sin(angle)};
        } else {
            w.velocity[i] = {w.velocity[i].x * crowdSpeedup, w.velocity[i].y * crowdSpeedup};
        }
    }
    // No overlap at the start (an overlap collides at once, at the same instant as others, and
    // the order of such ties is the order of the arrays): pins clear of every marble.
    for (int j = 0; withPins && j < 40; ++j) {
        const Vec2 q{rng.uniform(0.0, w.stage.width), rng.uniform(0.0, w.stage.height)};
        bool clear = true;
        for (int i = 0; i < w.marbleCount(); ++i)
            clear = clear && distance(w.position[i], q) > w.radius[i] + 1.0;
        if (clear)
            w.addPin(q);
    }
    QCOMPARE(static_cast<int>(giantIndex.size()), giants);
    QVERIFY(!withPins || w.pins.size() >= 10);
    QCOMPARE_GE(smallestGap(w), 0.0);
    QCOMPARE(splitRadii(w.radius).oversize, giants);
    World reference = w;
    const double e0 = w.kineticEnergy();
    const Vec2 p0 = w.momentum();
    const double scale = momentumScale(w);
    ExactModel model;
    ExactModel gridFromLargest;
    gridFromLargest.setSplitRadii(false);
    const std::vector<Vec2> giantStart = [&] {
        std::vector<Vec2> v;
        for (int g : giantIndex)
            v.push_back(w.velocity[g]);
        return v;
    }();
    double largestDifference = 0.0;
    for (int f = 0; f < 12; ++f) {
        run(w, model, 1);
        run(reference, gridFromLargest, 1);
        QCOMPARE(model.lastOversizeCount(), giants);
        QCOMPARE(gridFromLargest.lastOversizeCount(), 0);
        QCOMPARE(model.lastFrozenCount(), 0);
        QCOMPARE_GE(smallestGap(w), -1e-9);
        // (After a few frames the rounding differences below grow too fast to compare: tenfold a
        // frame in the fast crowd.)
        for (int i = 0; f < comparedFrames && i < w.marbleCount(); ++i) {
            largestDifference = std::max(largestDifference, distance(w.position[i], reference.position[i]));
            largestDifference = std::max(largestDifference, distance(w.velocity[i], reference.velocity[i]));
        }
    }
    // Rounding, amplified by the chaos of a crowd: 9e-9 px in the fast crowd, 3e-13 in the calm
    // one. A missed contact would make a difference of the order of a pixel.
    QCOMPARE_LE(largestDifference, 1e-6);
    // The giants met something (a marble, a pin or a wall) and changed course.
    for (std::size_t k = 0; k < giantIndex.size(); ++k)
        QVERIFY(!(w.velocity[giantIndex[k]] == giantStart[k]) || giantSpeed == 0.0);
    if (restitution == 1.0 && gravity == 0.0)
        QCOMPARE_LE(relativeError(w.kineticEnergy(), e0), 1e-12);
    if (!walls && !withPins && gravity == 0.0) {
        const Vec2 p1 = w.momentum();
        QCOMPARE_LE(std::abs(p1.x - p0.x), 1e-12 * scale);
        QCOMPARE_LE(std::abs(p1.y - p0.y), 1e-12 * scale);
    }
}

void TestExactModel::sparseFastGasWidensTheMargin()
{
    // A gas: 2,000 marbles of 1 to 3 px at up to 60 px/frame, one per 60 x 56 px of stage. With
    // the anchor margin a quarter of the contact distance (1.5 px) each marble crossed about 18
    // margins a frame, 36,000 grid events; the margin grows to twice the mean travel (capped by
    // the room each marble has), and a frame's events (grid events, wall bounces, collisions)
    // are fewer than the marbles: about 1,250. Nothing else changes: no overlap, energy kept.
    World w = makeSparseGas();
    w.params.model = ModelKind::Exact;
    QCOMPARE(splitRadii(w.radius).oversize, 0);
    const double e0 = w.kineticEnergy();
    ExactModel model;
    std::int64_t collisions = 0;
    for (int f = 0; f < 10; ++f) {
        run(w, model, 1);
        QCOMPARE_LE(model.lastEventCount(), std::int64_t(w.marbleCount()));
        collisions += model.lastCollisionCount();
    }
    QCOMPARE_GE(collisions, 500); // a gas, not marbles flying past each other
    QCOMPARE_GE(smallestGap(w), -1e-9);
    QCOMPARE_LE(relativeError(w.kineticEnergy(), e0), 1e-12);
    // The margin: far beyond a quarter of the contact distance (6 px) in the gas...
    QCOMPARE_GE(model.lastAnchorMargin(), 10.0);
    // ...but not for the same marbles packed 12 px apart in a corner of the stage, whose cells
    // would otherwise hold dozens of them (the stage's area per marble, 58 px, is no guide there):
    // about half the room a marble has there, (12 - 6) / 2 (3.16 as estimated; 26 from the stage).
    World clump = makeSparseGas();
    clump.params.model = ModelKind::Exact;
    for (int i = 0; i < clump.marbleCount(); ++i)
        clump.position[i] = {12.0 * (i % 50) + 6.0, 12.0 * (i / 50) + 6.0};
    ExactModel clumped;
    run(clump, clumped, 1);
    QCOMPARE_LE(clumped.lastAnchorMargin(), 4.0);
    QCOMPARE_GE(smallestGap(clump), -1e-9);
    // A dense crowd (issue 5's) keeps a quarter of the contact distance, twice its largest radius
    // (the same arithmetic: the same bits).
    World crowd = makeCrowd(2000, 3);
    ExactModel dense;
    run(crowd, dense, 1);
    QVERIFY(dense.lastAnchorMargin() == ExactModel::anchorMargin * (2.0 * largestOf(crowd.radius)));
}

void TestExactModel::oversizeMarbleReachesFarInOneFrame()
{
    // An oversize marble looks for partners only in the buckets its path can reach this frame:
    // at 800 px/frame that is most of the way across the stage, to a marble at rest far beyond
    // its neighbourhood, which it must hit 0.79 of the way through the first frame. (A band of
    // 2,720 marbles at rest along the top keeps the lattice from folding, which would make every
    // bucket reachable.)
    World w = bareWorld(0.0, true);
    w.stage = {2000, 600, true};
    for (int k = 0; k < 2720; ++k)
        w.addMarble({20.0 + 11.6 * (k % 170), 15.0 + 11.5 * (k / 170)}, 5.0);
    const int lone = w.addMarble({1000, 450}, 5.0);
    const int giant = w.addMarble({1700, 450}, 60.0, {-800.0, 0.0});
    QCOMPARE(splitRadii(w.radius).oversize, 1);
    QCOMPARE_GE(smallestGap(w), 0.0);
    ExactModel model;
    run(w, model, 1);
    QCOMPARE(model.lastOversizeCount(), 1);
    QCOMPARE(model.lastCollisionCount(), 1);
    QCOMPARE_LT(w.velocity[lone].x, -800.0); // the lighter marble leaves faster than the giant came
    QCOMPARE_GT(w.velocity[giant].x, -800.0);
    QCOMPARE_GE(smallestGap(w), -1e-9);
}

void TestExactModel::oversizeMarbleFallsFarInOneFrame()
{
    // The same under gravity, where the path is a parabola, boxed with what gravity adds. A giant
    // thrown up at 250 px/frame (g = 400 px/frame^2, e = 0) stops dead on a pin 10 px above it
    // and falls 160 px onto a marble lying on the floor, all in the first frame. That marble
    // looked for partners at the start of the frame, when the giant's path stayed above it; only
    // the giant's search after the pin, at rest, can find it: its box must reach down as far as
    // gravity takes it. A band of 2,700 pins along the top keeps the lattice from folding.
    World w = bareWorld(0.0, true, 0.0);
    w.stage = {2000, 600, true};
    w.params.gravity = {0.0, 400.0};
    for (int k = 0; k < 2700; ++k)
        w.addPin({10.0 + 11.0 * (k % 180), 5.0 + 11.0 * (k / 180)});
    w.addPin({1000, 310});
    const int lone = w.addMarble({1000, 595}, 5.0);
    for (int k = 0; k < 20; ++k)
        w.addMarble({100.0 + 20.0 * k, 595}, 5.0); // more marbles on the floor, far away
    const int giant = w.addMarble({1000, 380}, 60.0, {0.0, -250.0});
    QCOMPARE(splitRadii(w.radius).oversize, 1);
    QCOMPARE_GE(smallestGap(w), 0.0);
    ExactModel model;
    run(w, model, 1);
    QCOMPARE(model.lastOversizeCount(), 1);
    QCOMPARE_GE(smallestGap(w), -1e-9);
    QCOMPARE_GE(model.lastCollisionCount(), 2); // the pin, then the marble on the floor
    QCOMPARE_GT(w.position[giant].y, 500.0);
    QVERIFY(w.lastHit[lone].frame == 1);
}

void TestExactModel::brownianPresetWanders()
{
    // The "Brownian motion" preset: nothing pushes the heavy marble, yet the small ones' kicks
    // move it about, with the energy kept (e = 1, no friction). It is the one marble the grid
    // leaves out.
    World w;
    QVERIFY(makePreset("brownian", w));
    QCOMPARE(w.info[0].name, std::string("heavy"));
    QCOMPARE(w.velocity[0], Vec2{});
    QCOMPARE_GE(smallestGap(w), 0.0);
    const Vec2 start = w.position[0];
    const double e0 = w.kineticEnergy();
    ExactModel model;
    double farthest = 0.0;
    for (int f = 0; f < 300; ++f) {
        run(w, model, 1);
        QCOMPARE(model.lastOversizeCount(), 1);
        farthest = std::max(farthest, distance(w.position[0], start));
    }
    QCOMPARE_GE(farthest, 10.0);
    QCOMPARE_GE(smallestGap(w), -1e-9);
    QCOMPARE_LE(relativeError(w.kineticEnergy(), e0), 1e-12);
}

#include "tst_exactmodel.moc"
