// The chart writer behind `marbles-cli bench --plot`: a valid PNG (checksums, stored deflate
// blocks that decode back to the raster), and points drawn where the axes say.
#include "app/pngplot.h"

#include <QTest>

#include <cmath>
#include <cstring>

using namespace marbles;

namespace {

std::uint32_t readU32(const std::vector<std::uint8_t> &b, std::size_t at)
{
    return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) | b[at + 3];
}

struct Chunk {
    std::string type;
    std::vector<std::uint8_t> data;
    bool crcOk = false;
};

// Splits a PNG into its chunks, checking each CRC.
std::vector<Chunk> chunks(const std::vector<std::uint8_t> &png)
{
    std::vector<Chunk> out;
    std::size_t at = 8;
    while (at + 12 <= png.size()) {
        const std::uint32_t length = readU32(png, at);
        Chunk c;
        c.type.assign(reinterpret_cast<const char *>(&png[at + 4]), 4);
        c.data.assign(png.begin() + static_cast<std::ptrdiff_t>(at + 8),
                      png.begin() + static_cast<std::ptrdiff_t>(at + 8 + length));
        c.crcOk = plot::crc32(&png[at + 4], length + 4) == readU32(png, at + 8 + length);
        out.push_back(std::move(c));
        at += 12 + length;
    }
    return out;
}

// Inflates a zlib stream made only of stored blocks; empty on anything else.
std::vector<std::uint8_t> inflateStored(const std::vector<std::uint8_t> &z)
{
    std::vector<std::uint8_t> out;
    if (z.size() < 6 || ((z[0] << 8) | z[1]) % 31 != 0 || (z[0] & 0x0f) != 8)
        return {};
    std::size_t at = 2;
    for (;;) {
        if (at + 5 > z.size() || (z[at] & 0x06) != 0)
            return {};
        const bool last = z[at] & 1;
        const unsigned n = z[at + 1] | (z[at + 2] << 8);
        const unsigned check = z[at + 3] | (z[at + 4] << 8);
        if ((n ^ 0xffffu) != check || at + 5 + n > z.size())
            return {};
        out.insert(out.end(), z.begin() + static_cast<std::ptrdiff_t>(at + 5),
                   z.begin() + static_cast<std::ptrdiff_t>(at + 5 + n));
        at += 5 + n;
        if (last)
            break;
    }
    std::uint32_t a = 1, b = 0;
    for (std::uint8_t byte : out) {
        a = (a + byte) % 65521;
        b = (b + a) % 65521;
    }
    if (at + 4 != z.size() || readU32(z, at) != ((b << 16) | a))
        return {};
    return out;
}

bool near(std::uint32_t rgb, std::uint32_t want, int tolerance)
{
    for (int shift : {16, 8, 0}) {
        if (std::abs(int((rgb >> shift) & 0xff) - int((want >> shift) & 0xff)) > tolerance)
            return false;
    }
    return true;
}

// Is there a pixel of colour `want` within `radius` px of (x, y)?
bool colourNear(const plot::Image &image, int x, int y, std::uint32_t want, int radius)
{
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx)
            if (near(image.pixel(x + dx, y + dy), want, 8))
                return true;
    return false;
}

} // namespace

class TestPngPlot : public QObject {
    Q_OBJECT

private Q_SLOTS:
    void crcMatchesTheStandardCheckValue()
    {
        const char *check = "123456789";
        QCOMPARE(plot::crc32(reinterpret_cast<const std::uint8_t *>(check), 9), 0xcbf43926u);
        QCOMPARE(plot::crc32(nullptr, 0), 0u);
    }

    void pngDecodesBackToTheRaster_data()
    {
        QTest::addColumn<int>("width");
        QTest::addColumn<int>("height");
        QTest::addRow("1x1") << 1 << 1;
        QTest::addRow("odd") << 37 << 11;
        QTest::addRow("more than one stored block") << 300 << 200; // 180,200 bytes of scanlines
    }
    void pngDecodesBackToTheRaster()
    {
        QFETCH(int, width);
        QFETCH(int, height);
        plot::Image image;
        image.width = width;
        image.height = height;
        image.rgb.resize(static_cast<std::size_t>(width) * height * 3);
        for (std::size_t i = 0; i < image.rgb.size(); ++i)
            image.rgb[i] = static_cast<std::uint8_t>((i * 7919) >> 3);

        const std::vector<std::uint8_t> png = plot::encodePng(image);
        const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        QVERIFY(png.size() > 8 && std::memcmp(png.data(), signature, 8) == 0);
        const std::vector<Chunk> parts = chunks(png);
        QCOMPARE(parts.size(), std::size_t{3});
        QCOMPARE(QString::fromStdString(parts[0].type), QStringLiteral("IHDR"));
        QCOMPARE(QString::fromStdString(parts[1].type), QStringLiteral("IDAT"));
        QCOMPARE(QString::fromStdString(parts[2].type), QStringLiteral("IEND"));
        for (const Chunk &c : parts)
            QVERIFY2(c.crcOk, c.type.c_str());
        QCOMPARE(readU32(parts[0].data, 0), std::uint32_t(width));
        QCOMPARE(readU32(parts[0].data, 4), std::uint32_t(height));
        QCOMPARE(int(parts[0].data[8]), 8); // bit depth
        QCOMPARE(int(parts[0].data[9]), 2); // RGB

        const std::vector<std::uint8_t> raw = inflateStored(parts[1].data);
        const std::size_t row = static_cast<std::size_t>(width) * 3;
        QCOMPARE(raw.size(), (row + 1) * height);
        for (int y = 0; y < height; ++y) {
            QCOMPARE(int(raw[y * (row + 1)]), 0); // filter: none
            QVERIFY(std::memcmp(&raw[y * (row + 1) + 1], &image.rgb[y * row], row) == 0);
        }
    }

    void pointsLandWhereTheAxesSay_data()
    {
        QTest::addColumn<bool>("log");
        QTest::addRow("log axes") << true;
        QTest::addRow("linear axes") << false;
    }
    void pointsLandWhereTheAxesSay()
    {
        QFETCH(bool, log);
        plot::Chart chart;
        chart.logX = chart.logY = log;
        plot::Series s;
        s.label = "a";
        s.rgb = 0xd9822b;
        // On log axes 1e-3..1e1 and 1e-6..1e2 span whole decades; on linear ones 0..10 and 0..100
        // are multiples of the tick step, so the corners are the data's corners in both cases.
        s.x = log ? std::vector<double>{1e-3, 1e1} : std::vector<double>{0, 10};
        s.y = log ? std::vector<double>{1e2, 1e-6} : std::vector<double>{100, 0};
        chart.series.push_back(s);
        const plot::Image image = plot::render(chart);
        QCOMPARE(image.width, chart.width);
        QCOMPARE(image.height, chart.height);

        // The plot area is the frame; find it from the first point (top-left) and the second
        // (bottom-right), which both sit on its corners.
        const int left = 96, top = 44, right = chart.width - 24, bottom = chart.height - 64;
        QVERIFY(colourNear(image, left, top, s.rgb, 2));
        QVERIFY(colourNear(image, right, bottom, s.rgb, 2));
        // The line joins them: its midpoint is the series colour too.
        QVERIFY(colourNear(image, (left + right) / 2, (top + bottom) / 2, s.rgb, 2));
        // Far from the line, the opposite corners stay clear of it.
        QVERIFY(!colourNear(image, right - 4, top + 4, s.rgb, 2));
        QVERIFY(!colourNear(image, left + 4, bottom - 4, s.rgb, 2));
    }

    void zeroOnALogAxisIsLeftOutNotACrash()
    {
        plot::Chart chart;
        plot::Series s;
        s.label = "exact";
        s.rgb = 0x2a9d4b;
        s.x = {1e-3, 2e-3, 4e-3};
        s.y = {0.0, 1e-12, std::nan("")};
        chart.series.push_back(s);
        const plot::Image image = plot::render(chart);
        // The one placeable point is drawn inside the plot area.
        int found = 0;
        for (int y = 44; y < chart.height - 64; ++y)
            for (int x = 96; x < chart.width - 24; ++x)
                found += near(image.pixel(x, y), s.rgb, 8) ? 1 : 0;
        QVERIFY(found > 10);
    }
};

QTEST_APPLESS_MAIN(TestPngPlot)
#include "tst_pngplot.moc"
