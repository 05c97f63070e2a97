// Determinism (PHYSICS.md): the same scene, model and pushes give bit-identical results on every
// run and machine. A golden hash of the state after a fixed run of each preset guards it, as
// Box2D's determinism test does: any change to the arithmetic, the order of operations or the
// compiler flags of the core shows up here.

#include "core/presets.h"
#include "core/world.h"

#include <QtTest>

#include <bit>
#include <cstdint>
#include <limits>
#include <memory>

using namespace marbles;

namespace {

// FNV-1a over the bit patterns of every position and velocity, and the frame number.
std::uint64_t stateHash(const World &w)
{
    std::uint64_t h = 0xcbf29ce484222325ULL;
    auto mix = [&h](std::uint64_t word) {
        for (int b = 0; b < 8; ++b) {
            h ^= (word >> (8 * b)) & 0xffU;
            h *= 0x100000001b3ULL;
        }
    };
    mix(static_cast<std::uint64_t>(w.frame));
    for (int i = 0; i < w.marbleCount(); ++i) {
        mix(std::bit_cast<std::uint64_t>(w.position[i].x));
        mix(std::bit_cast<std::uint64_t>(w.position[i].y));
        mix(std::bit_cast<std::uint64_t>(w.velocity[i].x));
        mix(std::bit_cast<std::uint64_t>(w.velocity[i].y));
    }
    return h;
}

// A preset by name, or "crowd" for the reference crowd of issue #5 (2,000 marbles, seed 7).
World presetWithModel(const QString &preset, const QString &model)
{
    World w;
    if (preset == "crowd")
        w = makeCrowd(2000, 7);
    else
        makePreset(preset.toStdString(), w);
    parseModelName(model.toStdString(), w.params.model);
    if (w.params.model != ModelKind::Book && w.params.friction >= 1)
        w.params.friction = 0.1;
    return w;
}

} // namespace

class TestDeterminism : public QObject {
    Q_OBJECT

private slots:
    void goldenHash_data();
    void goldenHash();
    void snapshotContinuesIdentically_data();
    void snapshotContinuesIdentically();
    void modelsSayWhenTheirFrameIsFinite_data();
    void modelsSayWhenTheirFrameIsFinite();
};

void TestDeterminism::modelsSayWhenTheirFrameIsFinite_data()
{
    QTest::addColumn<ModelKind>("model");
    QTest::addColumn<QString>("scene");
    QTest::addColumn<QString>("bad");
    for (const ModelKind model : {ModelKind::Book, ModelKind::Impulse, ModelKind::Exact}) {
        const char *name = model == ModelKind::Book ? "book" : model == ModelKind::Impulse ? "impulse" : "exact";
        QTest::addRow("%s, crowd", name) << model << "crowd" << "";
        QTest::addRow("%s, crowd at rest", name) << model << "rest" << "";
        QTest::addRow("%s, pachinko", name) << model << "pachinko" << "";
        QTest::addRow("%s, a resting marble given a NaN place", name) << model << "rest" << "nan place";
        QTest::addRow("%s, a resting marble given an infinite place", name) << model << "rest" << "infinite place";
        QTest::addRow("%s, a moving marble given an infinite speed", name) << model << "crowd" << "infinite speed";
    }
    QTest::addRow("book, friction 3 blows up") << ModelKind::Book << "friction 3" << "";
}

void TestDeterminism::modelsSayWhenTheirFrameIsFinite()
{
    // Each model says whether its frame left every position and velocity finite, and World::step()
    // then skips its own pass over them (issue 5: a skip gives the results of not skipping). The
    // model may say no when it cannot tell; it must never say yes of a frame that is not finite,
    // and must say yes of a frame that is, while nothing is wrong.
    QFETCH(ModelKind, model);
    QFETCH(QString, scene);
    QFETCH(QString, bad);
    World w;
    if (scene == QLatin1String("pachinko"))
        QVERIFY(makePreset("pachinko", w));
    else
        w = makeCrowd(scene == QLatin1String("friction 3") ? 300 : 1500, 4, scene == QLatin1String("rest") ? 0.02 : 1.0);
    // Speeds doubled every frame: past the doubles in about 1,150 frames (marbles-cli run).
    const bool blowUp = scene == QLatin1String("friction 3");
    if (blowUp)
        w.params.friction = 3.0;
    if (bad == QLatin1String("infinite place"))
        w.stage.walls = false; // (the impulse model's walls would put it back on the stage)
    w.params.model = model;
    World reported = w; // stepped through World::step()
    const std::unique_ptr<Stepper> stepper = makeStepper(model);
    bool everFinite = false;
    bool wentBad = false;
    for (int f = 0; f < (blowUp ? 1300 : 40); ++f) {
        if (f == 5 && !bad.isEmpty()) {
            int k = w.marbleCount() / 3;
            while (bad != QLatin1String("infinite speed") && !(w.velocity[k] == Vec2{}))
                ++k; // one at rest: a sleeper, in the models that keep them
            for (World *x : {&w, &reported}) {
                if (bad == QLatin1String("infinite speed"))
                    x->velocity[k].x = std::numeric_limits<double>::infinity();
                else
                    x->position[k].y = bad.startsWith(QLatin1String("nan")) ? std::numeric_limits<double>::quiet_NaN()
                                                                            : std::numeric_limits<double>::infinity();
            }
        }
        stepper->step(w);
        ++w.frame;
        const int first = w.firstNonFiniteMarble();
        const QString where = QStringLiteral("frame %1").arg(w.frame);
        QVERIFY2(!stepper->leftAllFinite() || first < 0, qPrintable(where));
        if (first < 0 && !wentBad)
            QVERIFY2(stepper->leftAllFinite(), qPrintable(where));
        everFinite = everFinite || stepper->leftAllFinite();
        wentBad = wentBad || first >= 0;
        const StepResult result = reported.step();
        QCOMPARE(result.badMarble, first);
        QCOMPARE(result.finite, first < 0);
    }
    QVERIFY(everFinite);
    QCOMPARE(wentBad, !bad.isEmpty() || blowUp);
}

void TestDeterminism::goldenHash_data()
{
    QTest::addColumn<QString>("preset");
    QTest::addColumn<QString>("model");
    QTest::addColumn<int>("frames");
    QTest::addColumn<quint64>("golden");
    QTest::addRow("book four-marbles") << "four-marbles" << "book" << 600 << Q_UINT64_C(0xc9266bd2b19cde37);
    QTest::addRow("book pins") << "pins" << "book" << 600 << Q_UINT64_C(0x2cab09053196053f);
    QTest::addRow("book masses") << "masses" << "book" << 600 << Q_UINT64_C(0x09dff3f22afc66d5);
    QTest::addRow("book newtons-cradle") << "newtons-cradle" << "book" << 600 << Q_UINT64_C(0xa11ae8f47c414c00);
    QTest::addRow("book pachinko") << "pachinko" << "book" << 600 << Q_UINT64_C(0x9560e8bfb3b3e80f);
    QTest::addRow("book brownian") << "brownian" << "book" << 600 << Q_UINT64_C(0x8d10fe3a5774b150);
    QTest::addRow("book crowd") << "crowd" << "book" << 200 << Q_UINT64_C(0x465ebe00817bd342);
    QTest::addRow("exact four-marbles") << "four-marbles" << "exact" << 600 << Q_UINT64_C(0x9d5145e261cc7a18);
    QTest::addRow("exact pins") << "pins" << "exact" << 600 << Q_UINT64_C(0x6a6a960620967692);
    QTest::addRow("exact masses") << "masses" << "exact" << 600 << Q_UINT64_C(0x96c0baedd3b58f33);
    QTest::addRow("exact newtons-cradle") << "newtons-cradle" << "exact" << 600 << Q_UINT64_C(0x14dcf6894c9e1e87);
    QTest::addRow("exact pachinko") << "pachinko" << "exact" << 600 << Q_UINT64_C(0xa3e1d671beea4bbf);
    QTest::addRow("exact brownian") << "brownian" << "exact" << 600 << Q_UINT64_C(0x023e22c0f6252976);
    QTest::addRow("exact crowd") << "crowd" << "exact" << 200 << Q_UINT64_C(0x7a57b0784348d287);
    QTest::addRow("impulse four-marbles") << "four-marbles" << "impulse" << 600 << Q_UINT64_C(0x3b51679133f1439d);
    QTest::addRow("impulse pins") << "pins" << "impulse" << 600 << Q_UINT64_C(0x402b79bc3a364758);
    QTest::addRow("impulse masses") << "masses" << "impulse" << 600 << Q_UINT64_C(0xb7fb44f7cd815783);
    QTest::addRow("impulse newtons-cradle") << "newtons-cradle" << "impulse" << 600 << Q_UINT64_C(0x012267d32e44fe4e);
    QTest::addRow("impulse pachinko") << "pachinko" << "impulse" << 600 << Q_UINT64_C(0xb95146af5ffa9c99);
    QTest::addRow("impulse brownian") << "brownian" << "impulse" << 600 << Q_UINT64_C(0x7d286c11d0ec61cd);
    QTest::addRow("impulse crowd") << "crowd" << "impulse" << 200 << Q_UINT64_C(0x3a4e7a79baa7d4ee);
}

void TestDeterminism::goldenHash()
{
    QFETCH(QString, preset);
    QFETCH(QString, model);
    QFETCH(int, frames);
    QFETCH(quint64, golden);
    World w = presetWithModel(preset, model);
    for (int f = 0; f < frames; ++f)
        QVERIFY(w.step().finite);
    const std::uint64_t h = stateHash(w);
    QVERIFY2(h == golden, qPrintable(QString("state hash 0x%1").arg(h, 16, 16, QChar('0'))));
}

void TestDeterminism::snapshotContinuesIdentically_data()
{
    QTest::addColumn<QString>("preset");
    QTest::addColumn<QString>("model");
    for (const char *preset : {"four-marbles", "pins", "masses", "newtons-cradle", "pachinko", "brownian"}) {
        for (const char *model : {"book", "exact", "impulse"})
            QTest::addRow("%s %s", model, preset) << preset << model;
    }
}

void TestDeterminism::snapshotContinuesIdentically()
{
    QFETCH(QString, preset);
    QFETCH(QString, model);
    World w = presetWithModel(preset, model);
    for (int f = 0; f < 137; ++f)
        w.step();
    // A copy is a snapshot: its stepper starts with empty caches, which must not matter.
    World copy = w;
    for (int f = 0; f < 300; ++f) {
        w.step();
        copy.step();
    }
    QCOMPARE(stateHash(copy), stateHash(w));
    QCOMPARE(copy.position, w.position);
    QCOMPARE(copy.velocity, w.velocity);
}

QTEST_GUILESS_MAIN(TestDeterminism)
#include "tst_determinism.moc"
