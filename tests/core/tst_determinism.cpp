// Determinism (PHYSICS.md): the same scene, model and pushes give bit-identical results on every
// run and machine. A golden hash of the state after a fixed run of each preset guards it, as
// Box2D's determinism test does: any change to the arithmetic, the order of operations or the
// compiler flags of the core shows up here.

#include "core/presets.h"
#include "core/world.h"

#include <QtTest>

#include <bit>
#include <cstdint>

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
};

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
