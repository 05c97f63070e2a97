// Issue 5: "no allocation per frame". Every model keeps its buffers between frames, so once they
// have grown to a scene's size, stepping it allocates nothing: this counts the calls of the global
// operator new (plain and aligned) made while frames are stepped, and the large buffers mapped
// apart from it (core/largebuffer.h).

#include "core/largebuffer.h"
#include "core/presets.h"
#include "core/world.h"

#include <QtTest>

#include <algorithm>
#include <cstdlib>
#include <new>

namespace {

// Only the allocations made while `counting` is set are counted (QtTest allocates too).
long allocations = 0;
bool counting = false;

} // namespace

void *operator new(std::size_t size)
{
    if (counting)
        ++allocations;
    if (void *p = std::malloc(size ? size : 1))
        return p;
    throw std::bad_alloc();
}

void *operator new(std::size_t size, std::align_val_t alignment)
{
    if (counting)
        ++allocations;
    const auto align = static_cast<std::size_t>(alignment);
    if (void *p = std::aligned_alloc(align, (std::max<std::size_t>(size, 1) + align - 1) / align * align))
        return p;
    throw std::bad_alloc();
}

void operator delete(void *p) noexcept
{
    std::free(p);
}

void operator delete(void *p, std::align_val_t) noexcept
{
    std::free(p);
}

void operator delete(void *p, std::size_t, std::align_val_t) noexcept
{
    std::free(p);
}

void operator delete(void *p, std::size_t) noexcept
{
    std::free(p);
}

using namespace marbles;

class TestAllocations : public QObject {
    Q_OBJECT

private slots:
    void steadyFramesAllocateNothing_data();
    void steadyFramesAllocateNothing();
};

void TestAllocations::steadyFramesAllocateNothing_data()
{
    QTest::addColumn<QString>("model");
    QTest::addColumn<int>("marbles");
    QTest::addColumn<double>("moving");
    QTest::addColumn<int>("pins");
    QTest::addColumn<double>("friction");
    for (const char *model : {"book", "impulse", "exact"}) {
        QTest::addRow("%s, all moving", model) << model << 3000 << 1.0 << 0 << 0.0;
        QTest::addRow("%s, all moving, pins, friction", model) << model << 3000 << 1.0 << 60 << 0.05;
        QTest::addRow("%s, 1%% moving", model) << model << 3000 << 0.01 << 0 << 0.0;
        // Large enough that the event counts and crowded cells keep changing for a while, and
        // for buffers of a megabyte and more, which are mapped apart.
        QTest::addRow("%s, 40k, all moving", model) << model << 40000 << 1.0 << 0 << 0.0;
    }
}

void TestAllocations::steadyFramesAllocateNothing()
{
    QFETCH(QString, model);
    QFETCH(int, marbles);
    QFETCH(double, moving);
    QFETCH(int, pins);
    QFETCH(double, friction);
    World w = makeCrowd(marbles, 9, moving);
    QVERIFY(parseModelName(model.toStdString(), w.params.model));
    w.params.friction = friction;
    w.params.zeroThreshold = friction > 0.0 ? 0.02 : 0.0;
    for (int k = 0; k < pins; ++k)
        w.addPin({w.stage.width * (k + 0.5) / pins, w.stage.height * ((k * 7) % pins + 0.5) / pins});
    for (int f = 0; f < 10; ++f)
        w.step();
    // Over the next frames a buffer may still grow now and then (as more marbles start moving,
    // say), each time to double its size: a handful of allocations at most, where one per frame
    // would be 40.
    allocations = 0;
    const std::uint64_t mappedBefore = largeBuffersMapped();
    counting = true;
    for (int f = 0; f < 40; ++f)
        w.step();
    counting = false;
    QCOMPARE_LE(allocations + static_cast<long>(largeBuffersMapped() - mappedBefore), 8L);
}

QTEST_APPLESS_MAIN(TestAllocations)
#include "tst_allocations.moc"
