// How the grids are sized from the radii (issue "Scale"): splitRadii() leaves a few marbles far
// larger than the rest out of the grid, and nothing else.

#include "core/broadphase.h"
#include "core/presets.h"

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace marbles;

namespace {

// n radii uniform in [4, 12] (the crowd's), from a fixed seed.
std::vector<double> crowdRadii(int n)
{
    SplitMix64 rng(7);
    std::vector<double> radii(static_cast<std::size_t>(n));
    for (double &r : radii)
        r = rng.uniform(4.0, 12.0);
    return radii;
}

double largestBelow(const std::vector<double> &radii, double bound)
{
    double largest = 0.0;
    for (const double r : radii) {
        if (r <= bound)
            largest = std::max(largest, r);
    }
    return largest;
}

} // namespace

class TestBroadPhase : public QObject {
    Q_OBJECT

private slots:
    void crowdIsNotSplit();
    void fewGiantsAreLeftOut_data();
    void fewGiantsAreLeftOut();
    void tooManyGiantsAreNotLeftOut();
    void giantsJustAboveTheRestAreNotLeftOut();
    void fewRadiiAreNotSplit();
    void nonFiniteRadii();
    void callerSumsAgree();
    void runsInBoxAreTheBoxsBuckets();
};

void TestBroadPhase::crowdIsNotSplit()
{
    // Radii within a factor 3 of each other: the grid is sized from the largest, as always.
    const std::vector<double> radii = crowdRadii(5000);
    const RadiusSplit split = splitRadii(radii);
    QCOMPARE(split.largest, largestOf(radii));
    QCOMPARE(split.cut, split.largest);
    QCOMPARE(split.oversize, 0);
    QVERIFY(!split.isOversize(split.largest));
}

void TestBroadPhase::fewGiantsAreLeftOut_data()
{
    QTest::addColumn<int>("marbles");
    QTest::addColumn<int>("giants");
    QTest::addColumn<double>("giantRadius");
    QTest::addRow("one of 100 px among 2,000") << 2000 << 1 << 100.0;
    QTest::addRow("16 of 60 px among 20,000") << 20000 << RadiusSplit::maxOversize << 60.0;
    QTest::addRow("one of 1e6 px among 100") << 100 << 1 << 1e6;
    QTest::addRow("3 of 60 px among 50") << 50 << 3 << 60.0;
}

void TestBroadPhase::fewGiantsAreLeftOut()
{
    QFETCH(int, marbles);
    QFETCH(int, giants);
    QFETCH(double, giantRadius);
    std::vector<double> radii = crowdRadii(marbles);
    const double rest = largestOf(radii);
    for (int k = 0; k < giants; ++k)
        radii[static_cast<std::size_t>(k * (marbles / giants))] = giantRadius - k * 1e-3;
    const double restAfter = largestBelow(radii, giantRadius / 2);
    QVERIFY(restAfter <= rest);
    const RadiusSplit split = splitRadii(radii);
    QCOMPARE(split.largest, giantRadius);
    QCOMPARE(split.oversize, giants);
    QCOMPARE(split.cut, restAfter);
    int leftOut = 0;
    for (const double r : radii)
        leftOut += split.isOversize(r);
    QCOMPARE(leftOut, giants);
}

void TestBroadPhase::tooManyGiantsAreNotLeftOut()
{
    // One more than maxOversize: every marble would pay that many more tests than the grid saves.
    std::vector<double> radii = crowdRadii(20000);
    for (int k = 0; k <= RadiusSplit::maxOversize; ++k)
        radii[static_cast<std::size_t>(100 * k)] = 100.0;
    const RadiusSplit split = splitRadii(radii);
    QCOMPARE(split.oversize, 0);
    QCOMPARE(split.cut, 100.0);
}

void TestBroadPhase::giantsJustAboveTheRestAreNotLeftOut()
{
    // Below oversizeFactor times the mean (about 8 px here) nothing is left out.
    std::vector<double> radii = crowdRadii(2000);
    radii[5] = 30.0;
    QCOMPARE(splitRadii(radii).oversize, 0);
    QCOMPARE(splitRadii(radii).cut, 30.0);
    // Above it, but where the rest would not make the cells even half as wide, neither: a
    // tenth of the marbles is 20 px, so the mean is about 9 and the bound 36; the largest of
    // the rest is 20 and one marble of 38 px is not twice that.
    for (std::size_t i = 0; i < radii.size(); i += 10)
        radii[i] = 20.0;
    radii[5] = 38.0;
    const RadiusSplit split = splitRadii(radii);
    QCOMPARE(split.oversize, 0);
    QCOMPARE(split.cut, 38.0);
}

void TestBroadPhase::fewRadiiAreNotSplit()
{
    // Up to maxOversize marbles: leaving them all out would leave no grid.
    std::vector<double> radii(RadiusSplit::maxOversize, 5.0);
    radii[0] = 500.0;
    const RadiusSplit split = splitRadii(radii);
    QCOMPARE(split.oversize, 0);
    QCOMPARE(split.cut, 500.0);
    QCOMPARE(splitRadii({}).largest, 0.0);
    QCOMPARE(splitRadii({}).oversize, 0);
}

void TestBroadPhase::nonFiniteRadii()
{
    // A NaN radius is passed over by the largest (as in largestOf) but makes the mean NaN, and an
    // infinite one makes it infinite: nothing is left out, and the grid is sized from the largest.
    std::vector<double> radii = crowdRadii(1000);
    radii[3] = 300.0;
    radii[10] = std::numeric_limits<double>::quiet_NaN();
    const RadiusSplit withNaN = splitRadii(radii);
    QCOMPARE(withNaN.largest, 300.0);
    QCOMPARE(withNaN.oversize, 0);
    QCOMPARE(withNaN.cut, 300.0);
    radii[10] = std::numeric_limits<double>::infinity();
    const RadiusSplit withInfinity = splitRadii(radii);
    QCOMPARE(withInfinity.oversize, 0);
    QCOMPARE(withInfinity.cut, std::numeric_limits<double>::infinity());
}

void TestBroadPhase::callerSumsAgree()
{
    // The impulse model passes its own running maximum and sum: the same split.
    std::vector<double> radii = crowdRadii(3000);
    radii[42] = 150.0;
    radii[1000] = 90.0;
    double largest = 0.0;
    double sum = 0.0;
    for (const double r : radii) {
        largest = std::max(largest, r);
        sum += r;
    }
    const RadiusSplit a = splitRadii(radii);
    const RadiusSplit b = splitRadii(radii, largest, sum);
    QCOMPARE(b.largest, a.largest);
    QCOMPARE(b.cut, a.cut);
    QCOMPARE(b.oversize, 2);
    QCOMPARE(a.oversize, 2);
}

void TestBroadPhase::runsInBoxAreTheBoxsBuckets()
{
    // forEachRunInBox() visits the buckets of the cells meeting a box, each once, as runs of
    // consecutive buckets, on an unfolded and on a folded lattice, for boxes inside the stage,
    // across its edges, far outside it (folded onto it) and wider than the lattice.
    SplitMix64 rng(11);
    for (const int items : {5000, 50}) {
        const GridGeometry g = GridGeometry::fit(10.0, 800.0, 600.0, items);
        int boxed = 0;
        for (int trial = 0; trial < 2000; ++trial) {
            const double x0 = rng.uniform(-2000.0, 2000.0);
            const double y0 = rng.uniform(-2000.0, 2000.0);
            const double w = trial % 10 == 0 ? rng.uniform(0.0, 1500.0) : rng.uniform(0.0, 150.0);
            const double h = trial % 10 == 0 ? rng.uniform(0.0, 1500.0) : rng.uniform(0.0, 150.0);
            std::vector<int> expected(static_cast<std::size_t>(g.bucketCount()), 0);
            for (std::int64_t kx = g.coord(x0); kx <= g.coord(x0 + w); ++kx) {
                for (std::int64_t ky = g.coord(y0); ky <= g.coord(y0 + h); ++ky)
                    expected[static_cast<std::size_t>(g.bucket(kx, ky))] = 1;
            }
            std::vector<int> visited(expected.size(), 0);
            bool runsOk = true;
            const bool some = g.forEachRunInBox(x0, x0 + w, y0, y0 + h, [&](int b0, int b1) {
                runsOk = runsOk && 0 <= b0 && b0 < b1 && b1 <= g.bucketCount() && b0 / g.bucketsX() == (b1 - 1) / g.bucketsX();
                for (int b = b0; b < b1; ++b)
                    ++visited[static_cast<std::size_t>(b)];
            });
            QVERIFY(runsOk);
            if (!some) {
                // Only when the box covers every bucket, and then nothing was visited.
                QCOMPARE(std::count(expected.begin(), expected.end(), 1), std::ptrdiff_t(g.bucketCount()));
                QCOMPARE(std::count(visited.begin(), visited.end(), 0), std::ptrdiff_t(g.bucketCount()));
                continue;
            }
            ++boxed;
            QCOMPARE(visited, expected);
        }
        QCOMPARE_GE(boxed, 1000);
    }
    const GridGeometry g = GridGeometry::fit(10.0, 800.0, 600.0, 5000);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    QVERIFY(!g.forEachRunInBox(nan, 10.0, 0.0, 10.0, [](int, int) { QFAIL("visited"); }));
    QVERIFY(!g.forEachRunInBox(0.0, std::numeric_limits<double>::infinity(), 0.0, 10.0, [](int, int) { QFAIL("visited"); }));
}

QTEST_GUILESS_MAIN(TestBroadPhase)
#include "tst_broadphase.moc"
