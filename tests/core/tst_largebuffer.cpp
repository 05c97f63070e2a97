// The models' large buffers (core/largebuffer.h): a buffer of a megabyte or more is mapped on its
// own, 2 MiB aligned, and asked for huge pages; a smaller one comes from operator new. Either way
// it must behave as any std::vector's storage.

#include "core/largebuffer.h"

#include <QtTest>

#include <cstdint>
#include <fstream>
#include <string>

using namespace marbles;

namespace {

constexpr std::uintptr_t hugePage = std::uintptr_t(2) << 20;

struct alignas(64) Line {
    double values[8];
};

bool isAligned(const void *p, std::uintptr_t alignment)
{
    return reinterpret_cast<std::uintptr_t>(p) % alignment == 0;
}

// The kernel's transparent huge pages setting: the bracketed word of
// /sys/kernel/mm/transparent_hugepage/enabled ("always", "madvise" or "never"), "" if unknown.
std::string hugePageMode()
{
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    std::getline(in, line);
    const auto open = line.find('[');
    const auto close = line.find(']');
    if (open == std::string::npos || close == std::string::npos || close < open)
        return {};
    return line.substr(open + 1, close - open - 1);
}

// The kB of huge pages backing the mapping that holds `address` (its AnonHugePages line in
// /proc/self/smaps), or -1 when no mapping holds it.
long hugePageKbAt(const void *address)
{
    const auto at = reinterpret_cast<std::uintptr_t>(address);
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        // A mapping's first line: "start-end perms ...", in hexadecimal.
        const auto dash = line.find('-');
        const auto space = line.find(' ');
        if (dash != std::string::npos && space != std::string::npos && dash < space
            && line.find_first_not_of("0123456789abcdef") == dash) {
            const auto start = std::stoull(line.substr(0, dash), nullptr, 16);
            const auto end = std::stoull(line.substr(dash + 1, space - dash - 1), nullptr, 16);
            inside = start <= at && at < end;
        } else if (inside && line.rfind("AnonHugePages:", 0) == 0) {
            return std::stol(line.substr(14));
        }
    }
    return -1;
}

} // namespace

class TestLargeBuffer : public QObject {
    Q_OBJECT

private slots:
    void smallBuffersComeFromOperatorNew();
    void largeBuffersAreMappedAligned();
    void growingKeepsTheContents();
    void largeBuffersGetHugePages();
};

void TestLargeBuffer::smallBuffersComeFromOperatorNew()
{
    const std::uint64_t before = largeBuffersMapped();
    LargeVector<int> ints(1000, 7);
    LargeVector<Line> lines(100);
    QCOMPARE(largeBuffersMapped(), before);
    QVERIFY(isAligned(lines.data(), alignof(Line)));
    QCOMPARE(ints[999], 7);
}

void TestLargeBuffer::largeBuffersAreMappedAligned()
{
    const std::uint64_t before = largeBuffersMapped();
    // Just over a megabyte, and 3 MiB: each its own mapping, on a 2 MiB boundary.
    LargeVector<Line> lines(largeBufferBytes / sizeof(Line) + 1);
    LargeVector<double> doubles(3 * (std::size_t(1) << 20) / sizeof(double));
    if (mapsLargeBuffers()) {
        QCOMPARE(largeBuffersMapped(), before + 2);
        QVERIFY(isAligned(lines.data(), hugePage));
        QVERIFY(isAligned(doubles.data(), hugePage));
    } else {
        QCOMPARE(largeBuffersMapped(), before);
        QVERIFY(isAligned(lines.data(), alignof(Line)));
    }
    // Value-initialised, and every byte writable.
    QCOMPARE(lines.back().values[7], 0.0);
    QCOMPARE(doubles.back(), 0.0);
    for (std::size_t i = 0; i < doubles.size(); ++i)
        doubles[i] = static_cast<double>(i);
    QCOMPARE(doubles[doubles.size() - 1], static_cast<double>(doubles.size() - 1));
}

void TestLargeBuffer::growingKeepsTheContents()
{
    // From operator new to a mapping and on to a larger one, then copied and shrunk back.
    LargeVector<std::int64_t> values;
    for (std::int64_t i = 0; i < 600'000; ++i)
        values.push_back(i * 3);
    LargeVector<std::int64_t> copy = values;
    values.resize(10);
    values.shrink_to_fit();
    QCOMPARE(values.size(), std::size_t(10));
    QCOMPARE(values[9], std::int64_t(27));
    for (std::int64_t i = 0; i < 600'000; i += 997)
        QCOMPARE(copy[static_cast<std::size_t>(i)], i * 3);
    QCOMPARE(copy.back(), std::int64_t(599'999 * 3));
}

void TestLargeBuffer::largeBuffersGetHugePages()
{
    if (!mapsLargeBuffers())
        QSKIP("this build takes large buffers from operator new (not Linux, or AddressSanitizer)");
    const std::string mode = hugePageMode();
    if (mode != "always" && mode != "madvise")
        QSKIP(qPrintable(QString("this kernel gives no transparent huge pages (enabled: \"%1\")")
                             .arg(QString::fromStdString(mode))));
    // 8 MiB, written once: four huge pages where the kernel had them to give. One is asked of it,
    // so that a machine short of contiguous memory does not fail the test.
    LargeVector<double> doubles((std::size_t(8) << 20) / sizeof(double), 1.0);
    const long kb = hugePageKbAt(doubles.data());
    QVERIFY2(kb >= 0, "no mapping holds the buffer");
    QVERIFY2(kb >= 2048, qPrintable(QString("AnonHugePages %1 kB").arg(kb)));
}

QTEST_APPLESS_MAIN(TestLargeBuffer)
#include "tst_largebuffer.moc"
