// The book model against a second, independent reading of PHYSICS.md.
//
// The oracle below is written straight from the contract's numbered steps: all pairs, no grid,
// no sleeping, no prefilters, plain structs, every formula spelled out in the contract's order.
// It shares nothing with core/bookmodel.cpp: it only reads the starting scene out of a World.
// Random scenes are built to reach every branch: integer positions and radii so that touching
// (dist == r_i + r_j, dist == r) happens exactly, velocities on a 0.01 grid so that v == +-Z
// happens exactly, marbles at rest inside pins and on top of each other (the division-by-zero
// deviation), friction above 1 and 2, gravity, pushes, walls on and off, short circuit on and
// off. The core must agree bit for bit, every frame.
#include "core/world.h"

#include <QTest>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using namespace marbles;

namespace {

struct OracleMarble {
    double px, py, vx, vy, ax, ay, r, m;
};

struct OraclePush {
    std::int64_t frame;
    int marble;
    double cx, cy;
};

// How often the oracle took each branch, over every row: the last test checks that the random
// scenes really reach them all.
struct Coverage {
    long wallX = 0, wallY = 0, pinHit = 0, pinTouchExactly = 0, marbleHit = 0, divisionByZero = 0;
    long thresholdEdge = 0, shortCircuitStop = 0, pushes = 0;
};
Coverage coverage;

struct Oracle {
    double width, height;
    bool walls;
    double k, z, pushScale, gx, gy;
    bool shortCircuit;
    std::vector<OracleMarble> marbles;
    std::vector<std::pair<double, double>> pins;
    std::vector<OraclePush> pushes;
    std::int64_t frame = 0;

    static double length(double x, double y) { return std::sqrt(x * x + y * y); }

    // PHYSICS.md step 7 for the pair (i, j), or the pin reflection of step 6 when `pin` is set
    // (then j is unused and c points at the pin). Returns false, changing nothing, where the
    // book would divide by zero.
    bool reflect(OracleMarble &a, OracleMarble *b, double cx, double cy)
    {
        const double oldMag = length(a.vx, a.vy);
        const double cLen = length(cx, cy);
        if (oldMag == 0 || cLen == 0) {
            ++coverage.divisionByZero;
            return false;
        }
        double nvx = a.vx, nvy = a.vy;
        nvx /= oldMag;
        nvy /= oldMag;
        double ncx = cx, ncy = cy;
        ncx /= cLen;
        ncy /= cLen;
        const double d = nvx * ncx + nvy * ncy;
        nvx -= 2 * d * ncx;
        nvy -= 2 * d * ncy;
        const double cur = length(nvx, nvy);
        if (cur == 0) {
            ++coverage.divisionByZero;
            return false;
        }
        if (!b) {
            const double f = oldMag / cur;
            a.vx = nvx * f;
            a.vy = nvy * f;
            return true;
        }
        const double newI = (b->m / a.m) * (oldMag / 2);
        const double newJ = (a.m / b->m) * (oldMag / 2);
        double bvx = b->vx + 2 * d * ncx;
        double bvy = b->vy + 2 * d * ncy;
        const double curJ = length(bvx, bvy);
        if (curJ == 0) {
            ++coverage.divisionByZero;
            return false;
        }
        const double fi = newI / cur;
        a.vx = nvx * fi;
        a.vy = nvy * fi;
        const double fj = newJ / curJ;
        b->vx = bvx * fj;
        b->vy = bvy * fj;
        return true;
    }

    void step()
    {
        for (const OraclePush &push : pushes) {
            if (push.frame != frame)
                continue;
            OracleMarble &m = marbles[static_cast<std::size_t>(push.marble)];
            m.ax += (m.px - push.cx) * pushScale / m.m;
            m.ay += (m.py - push.cy) * pushScale / m.m;
            ++coverage.pushes;
        }
        for (std::size_t i = 0; i < marbles.size(); ++i) {
            OracleMarble &a = marbles[i];
            a.ax += (-a.vx) * k;
            a.ay += (-a.vy) * k;
            a.ax += gx;
            a.ay += gy;
            a.vx += a.ax;
            a.vy += a.ay;
            if (z > 0 && (a.vx == z || a.vx == -z || a.vy == z || a.vy == -z))
                ++coverage.thresholdEdge;
            if (-z <= a.vx && a.vx <= z)
                a.vx = 0;
            if (-z <= a.vy && a.vy <= z)
                a.vy = 0;
            const double oldX = a.px, oldY = a.py;
            a.px += a.vx;
            a.py += a.vy;
            bool done = false;
            if (walls) {
                if ((a.px - a.r < 0 && a.vx < 0) || (a.px + a.r > width && a.vx > 0)) {
                    a.px = oldX;
                    a.py = oldY;
                    a.vx = -a.vx;
                    done = shortCircuit;
                    ++coverage.wallX;
                }
                if (!done && ((a.py - a.r < 0 && a.vy < 0) || (a.py + a.r > height && a.vy > 0))) {
                    a.px = oldX;
                    a.py = oldY;
                    a.vy = -a.vy;
                    done = shortCircuit;
                    ++coverage.wallY;
                }
            }
            for (std::size_t j = 0; j < pins.size() && !done; ++j) {
                const auto [qx, qy] = pins[j];
                const double dist = std::sqrt((qx - a.px) * (qx - a.px) + (qy - a.py) * (qy - a.py));
                if (dist <= a.r) {
                    ++coverage.pinHit;
                    coverage.pinTouchExactly += dist == a.r ? 1 : 0;
                    a.px = oldX;
                    a.py = oldY;
                    reflect(a, nullptr, qx - a.px, qy - a.py);
                    done = shortCircuit;
                }
            }
            for (std::size_t j = 0; j < marbles.size() && !done; ++j) {
                if (j == i)
                    continue;
                OracleMarble &b = marbles[j];
                const double dist = std::sqrt((a.px - b.px) * (a.px - b.px) + (a.py - b.py) * (a.py - b.py));
                if (dist < a.r + b.r) {
                    ++coverage.marbleHit;
                    a.px = oldX;
                    a.py = oldY;
                    reflect(a, &b, b.px - a.px, b.py - a.py);
                    done = shortCircuit;
                }
            }
            coverage.shortCircuitStop += done ? 1 : 0;
            a.ax = 0;
            a.ay = 0;
        }
        ++frame;
    }

    bool finite() const
    {
        for (const OracleMarble &m : marbles)
            if (!std::isfinite(m.px) || !std::isfinite(m.py) || !std::isfinite(m.vx) || !std::isfinite(m.vy))
                return false;
        return true;
    }
};

struct Config {
    int marbles;
    int pins;
    double friction;
    double threshold;
    double gravityY;
    bool walls;
    bool shortCircuit;
    int pushes;
};

// A random scene for `config`, reproducible from `seed`.
World randomScene(const Config &config, std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    const auto uniformInt = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    World w;
    w.stage.width = 400;
    w.stage.height = 300;
    w.stage.walls = config.walls;
    w.params.friction = config.friction;
    w.params.zeroThreshold = config.threshold;
    w.params.gravity = {0, config.gravityY};
    w.params.shortCircuit = config.shortCircuit;
    for (int i = 0; i < config.marbles; ++i) {
        const double r = uniformInt(2, 30);
        // Velocities on a 0.01 grid (some exactly +-Z, some zero), positions on whole pixels.
        const Vec2 v{uniformInt(-600, 600) / 100.0, uniformInt(-600, 600) / 100.0};
        const Vec2 p{double(uniformInt(0, 400)), double(uniformInt(0, 300))};
        const int kind = uniformInt(0, 9);
        const double mass = kind == 0 ? uniformInt(1, 200) / 4.0 : 0.0;
        w.addMarble(p, r, kind == 1 ? Vec2{} : v, mass);
    }
    for (int j = 0; j < config.pins; ++j) {
        // Some pins sit exactly on a marble's centre (|c| = 0 once it is restored there).
        if (config.marbles > 0 && uniformInt(0, 4) == 0)
            w.addPin(w.position[static_cast<std::size_t>(uniformInt(0, config.marbles - 1))]);
        else
            w.addPin({double(uniformInt(0, 400)), double(uniformInt(0, 300))});
    }
    if (config.marbles >= 2) {
        // Two marbles on the same spot, one at rest: the book's |c| = 0 and |v| = 0 cases.
        w.position[1] = w.position[0];
        w.velocity[1] = {};
    }
    if (config.marbles >= 3 && config.pins > 0) {
        // Marble 2 moves 2 px/frame towards a pin that it touches exactly (dist == r) after
        // five frames when nothing else is in the way and there is no friction.
        const auto s = std::size_t{2};
        w.velocity[s] = {2, 0};
        w.pins.back() = {w.position[s].x + 10 + w.radius[s], w.position[s].y};
    }
    if (config.marbles >= 5) {
        // Exactly at the threshold, and just outside it (kept when friction is 0).
        w.velocity[3] = {config.threshold, -config.threshold};
        w.velocity[4] = {std::nextafter(config.threshold, 1.0), -std::nextafter(config.threshold, 1.0)};
    }
    for (int n = 0; n < config.pushes && config.marbles > 0; ++n) {
        Push push;
        push.frame = uniformInt(0, 60);
        push.marble = uniformInt(0, config.marbles - 1);
        const Vec2 p = w.position[static_cast<std::size_t>(push.marble)];
        push.at = {p.x + uniformInt(-20, 20), p.y + uniformInt(-20, 20)};
        w.pushes.push_back(push);
    }
    return w;
}

Oracle oracleOf(const World &w)
{
    Oracle o;
    o.width = w.stage.width;
    o.height = w.stage.height;
    o.walls = w.stage.walls;
    o.k = w.params.friction;
    o.z = w.params.zeroThreshold;
    o.pushScale = w.params.pushScale;
    o.gx = w.params.gravity.x;
    o.gy = w.params.gravity.y;
    o.shortCircuit = w.params.shortCircuit;
    for (int i = 0; i < w.marbleCount(); ++i) {
        const auto s = static_cast<std::size_t>(i);
        o.marbles.push_back({w.position[s].x, w.position[s].y, w.velocity[s].x, w.velocity[s].y, 0, 0, w.radius[s],
                             w.mass[s]});
    }
    for (const Vec2 &q : w.pins)
        o.pins.emplace_back(q.x, q.y);
    for (const Push &p : w.pushes)
        o.pushes.push_back({p.frame, p.marble, p.at.x, p.at.y});
    return o;
}

} // namespace

class TestBookOracle : public QObject {
    Q_OBJECT

private Q_SLOTS:
    void everyFrameMatchesTheContract_data()
    {
        QTest::addColumn<int>("marbles");
        QTest::addColumn<int>("pins");
        QTest::addColumn<double>("friction");
        QTest::addColumn<double>("threshold");
        QTest::addColumn<double>("gravityY");
        QTest::addColumn<bool>("walls");
        QTest::addColumn<bool>("shortCircuit");
        QTest::addColumn<int>("pushes");
        QTest::addColumn<int>("frames");
        QTest::addRow("defaults") << 12 << 6 << 0.1 << 0.01 << 0.0 << true << false << 4 << 400;
        QTest::addRow("short circuit") << 12 << 6 << 0.1 << 0.01 << 0.0 << true << true << 4 << 400;
        QTest::addRow("no friction, threshold 0") << 10 << 4 << 0.0 << 0.0 << 0.0 << true << false << 3 << 400;
        QTest::addRow("threshold on the velocity grid") << 10 << 4 << 0.0 << 0.5 << 0.0 << true << false << 6 << 300;
        QTest::addRow("gravity") << 10 << 8 << 0.02 << 0.01 << 0.25 << true << false << 3 << 400;
        QTest::addRow("gravity, short circuit") << 10 << 8 << 0.02 << 0.01 << 0.25 << true << true << 3 << 400;
        QTest::addRow("no walls") << 10 << 5 << 0.1 << 0.01 << 0.0 << false << false << 3 << 300;
        QTest::addRow("crowded") << 40 << 10 << 0.1 << 0.01 << 0.0 << true << false << 10 << 300;
        QTest::addRow("pins only") << 1 << 20 << 0.0 << 0.0 << 0.0 << true << false << 2 << 400;
        QTest::addRow("friction 1.5 flips sign") << 8 << 4 << 1.5 << 0.01 << 0.0 << true << false << 3 << 200;
        QTest::addRow("friction 2.5 blows up") << 8 << 4 << 2.5 << 0.0 << 0.0 << true << false << 3 << 2000;
        QTest::addRow("heavy pushes") << 6 << 3 << 0.1 << 0.01 << 0.0 << true << true << 30 << 200;
    }
    void everyFrameMatchesTheContract()
    {
        QFETCH(int, marbles);
        QFETCH(int, pins);
        QFETCH(double, friction);
        QFETCH(double, threshold);
        QFETCH(double, gravityY);
        QFETCH(bool, walls);
        QFETCH(bool, shortCircuit);
        QFETCH(int, pushes);
        QFETCH(int, frames);
        const Config config{marbles, pins, friction, threshold, gravityY, walls, shortCircuit, pushes};
        for (std::uint64_t seed = 1; seed <= 8; ++seed) {
            World world = randomScene(config, seed * 7919 + std::uint64_t(marbles));
            Oracle oracle = oracleOf(world);
            for (int f = 1; f <= frames; ++f) {
                const StepResult result = world.step();
                oracle.step();
                QCOMPARE(result.finite, oracle.finite());
                for (int i = 0; i < world.marbleCount(); ++i) {
                    const auto s = static_cast<std::size_t>(i);
                    const OracleMarble &o = oracle.marbles[s];
                    const bool same = sameBits(world.position[s].x, o.px) && sameBits(world.position[s].y, o.py)
                        && sameBits(world.velocity[s].x, o.vx) && sameBits(world.velocity[s].y, o.vy);
                    if (!same) {
                        const QString where = QStringLiteral("seed %1, frame %2, marble %3: core (%4, %5, %6, %7), "
                                                             "contract (%8, %9, %10, %11)")
                                                  .arg(seed).arg(f).arg(i)
                                                  .arg(world.position[s].x, 0, 'g', 17).arg(world.position[s].y, 0, 'g', 17)
                                                  .arg(world.velocity[s].x, 0, 'g', 17).arg(world.velocity[s].y, 0, 'g', 17)
                                                  .arg(o.px, 0, 'g', 17).arg(o.py, 0, 'g', 17)
                                                  .arg(o.vx, 0, 'g', 17).arg(o.vy, 0, 'g', 17);
                        QFAIL(qPrintable(where));
                    }
                }
                if (!result.finite)
                    break;
            }
        }
    }

    // Runs after the rows above (Qt Test keeps declaration order).
    void everyBranchWasReached()
    {
        QVERIFY(coverage.wallX > 0);
        QVERIFY(coverage.wallY > 0);
        QVERIFY(coverage.pinHit > 0);
        QVERIFY(coverage.pinTouchExactly > 0);
        QVERIFY(coverage.marbleHit > 0);
        QVERIFY(coverage.divisionByZero > 0);
        QVERIFY(coverage.thresholdEdge > 0);
        QVERIFY(coverage.shortCircuitStop > 0);
        QVERIFY(coverage.pushes > 0);
        qInfo("walls x %ld, y %ld; pins %ld (exactly touching %ld); marbles %ld; division by zero %ld; "
              "v = +-Z %ld; short circuit %ld; pushes %ld",
              coverage.wallX, coverage.wallY, coverage.pinHit, coverage.pinTouchExactly, coverage.marbleHit,
              coverage.divisionByZero, coverage.thresholdEdge, coverage.shortCircuitStop, coverage.pushes);
    }
};

QTEST_APPLESS_MAIN(TestBookOracle)
#include "tst_bookoracle.moc"
