#include "app/pngplot.h"

#include "app/plotfont.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

namespace marbles::plot {

namespace {

constexpr std::uint32_t kBackground = 0xffffff;
constexpr std::uint32_t kInk = 0x202020;
constexpr std::uint32_t kGrid = 0xe4e4e4;
constexpr std::uint32_t kFrame = 0x808080;

// The plot area inside the image: room on the left for tick labels and the rotated y label,
// below for tick labels and the x label, above for the title.
constexpr int kLeft = 96;
constexpr int kRight = 24;
constexpr int kTop = 44;
constexpr int kBottom = 64;

class Canvas {
public:
    explicit Canvas(Image &image) : m_image(image) {}

    // Mixes `rgb` into pixel (x, y) with weight `alpha` in [0, 1]; pixels outside are ignored.
    void blend(int x, int y, std::uint32_t rgb, double alpha)
    {
        if (x < 0 || y < 0 || x >= m_image.width || y >= m_image.height || alpha <= 0)
            return;
        alpha = std::min(alpha, 1.0);
        std::uint8_t *p = &m_image.rgb[(static_cast<std::size_t>(y) * m_image.width + x) * 3];
        for (int c = 0; c < 3; ++c) {
            const double source = (rgb >> (16 - 8 * c)) & 0xff;
            p[c] = static_cast<std::uint8_t>(std::lround(p[c] + (source - p[c]) * alpha));
        }
    }

    void fill(int x0, int y0, int x1, int y1, std::uint32_t rgb)
    {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                blend(x, y, rgb, 1.0);
    }

    // An antialiased segment of the given width (px): each pixel near the segment is covered
    // by how far its centre lies inside the stroke, clamped to [0, 1].
    void line(double ax, double ay, double bx, double by, double width, std::uint32_t rgb)
    {
        const double half = width / 2;
        const int x0 = static_cast<int>(std::floor(std::min(ax, bx) - half - 1));
        const int x1 = static_cast<int>(std::ceil(std::max(ax, bx) + half + 1));
        const int y0 = static_cast<int>(std::floor(std::min(ay, by) - half - 1));
        const int y1 = static_cast<int>(std::ceil(std::max(ay, by) + half + 1));
        const double dx = bx - ax;
        const double dy = by - ay;
        const double length2 = dx * dx + dy * dy;
        for (int y = std::max(y0, 0); y <= std::min(y1, m_image.height - 1); ++y) {
            for (int x = std::max(x0, 0); x <= std::min(x1, m_image.width - 1); ++x) {
                const double px = x + 0.5 - ax;
                const double py = y + 0.5 - ay;
                const double t = length2 > 0 ? std::clamp((px * dx + py * dy) / length2, 0.0, 1.0) : 0.0;
                const double d = std::hypot(px - t * dx, py - t * dy);
                blend(x, y, rgb, half + 0.5 - d);
            }
        }
    }

    void disc(double cx, double cy, double radius, std::uint32_t rgb) { line(cx, cy, cx, cy, 2 * radius, rgb); }

    // Text in the 7x13 font with its top-left corner at (x, y); `vertical` turns it a quarter
    // turn anticlockwise, reading bottom to top, with (x, y) then its bottom-left corner.
    void text(int x, int y, const std::string &s, std::uint32_t rgb, bool vertical = false)
    {
        int advance = 0;
        for (unsigned char ch : s) {
            const int code = (ch < font::kFirst || ch > font::kLast) ? '?' : ch;
            const auto &glyph = font::kGlyphs[static_cast<std::size_t>(code - font::kFirst)];
            for (int row = 0; row < font::kHeight; ++row) {
                for (int col = 0; col < font::kWidth; ++col) {
                    if (!(glyph[static_cast<std::size_t>(row)] & (0x80 >> col)))
                        continue;
                    if (vertical)
                        blend(x + row, y - advance - col, rgb, 1.0);
                    else
                        blend(x + advance + col, y + row, rgb, 1.0);
                }
            }
            advance += font::kWidth;
        }
    }

private:
    Image &m_image;
};

int textWidth(const std::string &s) { return static_cast<int>(s.size()) * font::kWidth; }

// One axis: maps data values to pixels and lists its ticks.
struct Axis {
    bool log = false;
    double lo = 0; // in axis units: log10(value) on a log axis
    double hi = 1;

    double unit(double v) const { return log ? std::log10(v) : v; }
    bool placeable(double v) const { return std::isfinite(v) && (!log || v > 0); }
};

std::string tickLabel(double value, bool log)
{
    std::ostringstream out;
    if (log) {
        const int decade = static_cast<int>(std::lround(value));
        if (decade == 0)
            out << "1";
        else if (decade == 1)
            out << "10";
        else
            out << "1e" << decade;
    } else {
        out << value;
    }
    return out.str();
}

// Axis range and ticks for values already in axis units. A log axis spans whole decades with a
// tick at each (thinned to at most about 10); a linear axis uses steps of 1, 2 or 5 times a
// power of ten.
Axis makeAxis(bool log, double lo, double hi, std::vector<double> &ticks)
{
    Axis axis;
    axis.log = log;
    if (!(lo <= hi)) {
        lo = log ? -1 : 0;
        hi = log ? 1 : 1;
    }
    if (log) {
        axis.lo = std::floor(lo);
        axis.hi = std::ceil(hi);
        if (axis.hi - axis.lo < 1)
            axis.hi = axis.lo + 1;
        const int span = static_cast<int>(axis.hi - axis.lo);
        const int step = std::max(1, (span + 9) / 10);
        for (int d = static_cast<int>(axis.lo); d <= static_cast<int>(axis.hi); d += step)
            ticks.push_back(d);
        return axis;
    }
    if (hi - lo <= 0) {
        const double pad = lo == 0 ? 1 : std::abs(lo) * 0.1;
        lo -= pad;
        hi += pad;
    }
    const double raw = (hi - lo) / 6;
    const double magnitude = std::pow(10, std::floor(std::log10(raw)));
    double step = magnitude;
    for (double m : {2.0, 5.0, 10.0}) {
        if (step >= raw)
            break;
        step = m * magnitude;
    }
    axis.lo = std::floor(lo / step) * step;
    axis.hi = std::ceil(hi / step) * step;
    for (double t = axis.lo; t <= axis.hi + step / 2; t += step)
        ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
    return axis;
}

void appendU32(std::vector<std::uint8_t> &out, std::uint32_t v)
{
    for (int shift = 24; shift >= 0; shift -= 8)
        out.push_back(static_cast<std::uint8_t>(v >> shift));
}

void appendChunk(std::vector<std::uint8_t> &out, const char type[4], const std::vector<std::uint8_t> &data)
{
    appendU32(out, static_cast<std::uint32_t>(data.size()));
    const std::size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    appendU32(out, crc32(&out[start], out.size() - start));
}

} // namespace

std::uint32_t Image::pixel(int x, int y) const
{
    const std::uint8_t *p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    return (std::uint32_t{p[0]} << 16) | (std::uint32_t{p[1]} << 8) | p[2];
}

std::uint32_t crc32(const std::uint8_t *data, std::size_t size)
{
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t n = 0; n < 256; ++n) {
            std::uint32_t c = n;
            for (int k = 0; k < 8; ++k)
                c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[n] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < size; ++i)
        c = table[(c ^ data[i]) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

std::vector<std::uint8_t> encodePng(const Image &image)
{
    // Raw scanlines, each led by filter type 0 (none).
    const std::size_t rowBytes = static_cast<std::size_t>(image.width) * 3;
    std::vector<std::uint8_t> raw;
    raw.reserve((rowBytes + 1) * static_cast<std::size_t>(image.height));
    for (int y = 0; y < image.height; ++y) {
        raw.push_back(0);
        const auto row = image.rgb.begin() + static_cast<std::ptrdiff_t>(rowBytes * static_cast<std::size_t>(y));
        raw.insert(raw.end(), row, row + static_cast<std::ptrdiff_t>(rowBytes));
    }

    // A zlib stream of stored (uncompressed) deflate blocks of at most 65535 bytes each,
    // followed by the Adler-32 of the raw data.
    std::vector<std::uint8_t> z{0x78, 0x01};
    std::size_t offset = 0;
    do {
        const std::size_t n = std::min<std::size_t>(65535, raw.size() - offset);
        const bool last = offset + n == raw.size();
        z.push_back(last ? 1 : 0);
        z.push_back(static_cast<std::uint8_t>(n & 0xff));
        z.push_back(static_cast<std::uint8_t>(n >> 8));
        z.push_back(static_cast<std::uint8_t>(~n & 0xff));
        z.push_back(static_cast<std::uint8_t>((~n >> 8) & 0xff));
        z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(offset),
                 raw.begin() + static_cast<std::ptrdiff_t>(offset + n));
        offset += n;
    } while (offset < raw.size());
    std::uint32_t a = 1, b = 0;
    for (std::uint8_t byte : raw) {
        a = (a + byte) % 65521;
        b = (b + a) % 65521;
    }
    appendU32(z, (b << 16) | a);

    std::vector<std::uint8_t> png{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<std::uint8_t> header;
    appendU32(header, static_cast<std::uint32_t>(image.width));
    appendU32(header, static_cast<std::uint32_t>(image.height));
    header.insert(header.end(), {8, 2, 0, 0, 0}); // 8 bits, RGB, deflate, adaptive filters, no interlace
    appendChunk(png, "IHDR", header);
    appendChunk(png, "IDAT", z);
    appendChunk(png, "IEND", {});
    return png;
}

Image render(const Chart &chart)
{
    Image image;
    image.width = std::max(chart.width, kLeft + kRight + 64);
    image.height = std::max(chart.height, kTop + kBottom + 64);
    image.rgb.assign(static_cast<std::size_t>(image.width) * image.height * 3, 0xff);
    Canvas canvas(image);
    canvas.fill(0, 0, image.width, image.height, kBackground);

    // Data range in axis units, over the placeable points only.
    double xLo = std::numeric_limits<double>::infinity(), xHi = -xLo, yLo = xLo, yHi = -xLo;
    Axis probeX{chart.logX}, probeY{chart.logY};
    for (const Series &s : chart.series) {
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            if (!probeX.placeable(s.x[i]) || !probeY.placeable(s.y[i]))
                continue;
            xLo = std::min(xLo, probeX.unit(s.x[i]));
            xHi = std::max(xHi, probeX.unit(s.x[i]));
            yLo = std::min(yLo, probeY.unit(s.y[i]));
            yHi = std::max(yHi, probeY.unit(s.y[i]));
        }
    }
    std::vector<double> xTicks, yTicks;
    const Axis ax = makeAxis(chart.logX, xLo, xHi, xTicks);
    const Axis ay = makeAxis(chart.logY, yLo, yHi, yTicks);

    const int left = kLeft, top = kTop;
    const int right = image.width - kRight, bottom = image.height - kBottom;
    const auto toX = [&](double u) { return left + (u - ax.lo) / (ax.hi - ax.lo) * (right - left); };
    const auto toY = [&](double u) { return bottom - (u - ay.lo) / (ay.hi - ay.lo) * (bottom - top); };

    // Grid, frame, ticks and their labels.
    for (double t : xTicks) {
        const double x = std::round(toX(t)) + 0.5;
        canvas.line(x, top, x, bottom, 1, kGrid);
        const std::string label = tickLabel(t, ax.log);
        canvas.text(static_cast<int>(x) - textWidth(label) / 2, bottom + 6, label, kInk);
    }
    for (double t : yTicks) {
        const double y = std::round(toY(t)) + 0.5;
        canvas.line(left, y, right, y, 1, kGrid);
        const std::string label = tickLabel(t, ay.log);
        canvas.text(left - 6 - textWidth(label), static_cast<int>(y) - font::kHeight / 2, label, kInk);
    }
    canvas.line(left + 0.5, top + 0.5, right - 0.5, top + 0.5, 1, kFrame);
    canvas.line(left + 0.5, bottom - 0.5, right - 0.5, bottom - 0.5, 1, kFrame);
    canvas.line(left + 0.5, top + 0.5, left + 0.5, bottom - 0.5, 1, kFrame);
    canvas.line(right - 0.5, top + 0.5, right - 0.5, bottom - 0.5, 1, kFrame);

    // Title (bold by a one-pixel double strike) and axis labels.
    const int titleX = (image.width - textWidth(chart.title)) / 2;
    canvas.text(titleX, 14, chart.title, kInk);
    canvas.text(titleX + 1, 14, chart.title, kInk);
    canvas.text((left + right - textWidth(chart.xLabel)) / 2, bottom + 30, chart.xLabel, kInk);
    canvas.text(18, (top + bottom + textWidth(chart.yLabel)) / 2, chart.yLabel, kInk, true);

    // The series: joined lines, then dots on top.
    std::vector<std::string> legend;
    for (const Series &s : chart.series) {
        std::vector<std::pair<double, double>> points;
        int hidden = 0;
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            if (ax.placeable(s.x[i]) && ay.placeable(s.y[i]))
                points.emplace_back(toX(ax.unit(s.x[i])), toY(ay.unit(s.y[i])));
            else
                ++hidden;
        }
        for (std::size_t i = 1; i < points.size(); ++i)
            canvas.line(points[i - 1].first, points[i - 1].second, points[i].first, points[i].second, 2, s.rgb);
        if (s.markers || points.size() == 1)
            for (const auto &[x, y] : points)
                canvas.disc(x, y, 3.5, s.rgb);
        std::string entry = s.label;
        if (hidden > 0)
            entry += " (" + std::to_string(hidden) + (hidden == 1 ? " point" : " points") + " at 0, not shown)";
        legend.push_back(entry);
    }

    // Legend, top right inside the plot area, on a white box.
    int legendWidth = 0;
    for (const std::string &entry : legend)
        legendWidth = std::max(legendWidth, textWidth(entry));
    if (!legend.empty()) {
        const int boxW = legendWidth + 40, boxH = static_cast<int>(legend.size()) * 18 + 8;
        const int bx = right - boxW - 8, by = top + 8;
        canvas.fill(bx, by, bx + boxW, by + boxH, kBackground);
        canvas.line(bx + 0.5, by + 0.5, bx + boxW - 0.5, by + 0.5, 1, kFrame);
        canvas.line(bx + 0.5, by + boxH - 0.5, bx + boxW - 0.5, by + boxH - 0.5, 1, kFrame);
        canvas.line(bx + 0.5, by + 0.5, bx + 0.5, by + boxH - 0.5, 1, kFrame);
        canvas.line(bx + boxW - 0.5, by + 0.5, bx + boxW - 0.5, by + boxH - 0.5, 1, kFrame);
        for (std::size_t i = 0; i < legend.size(); ++i) {
            const int y = by + 6 + static_cast<int>(i) * 18;
            canvas.line(bx + 8, y + 7, bx + 28, y + 7, 2, chart.series[i].rgb);
            canvas.disc(bx + 18, y + 7, 3.5, chart.series[i].rgb);
            canvas.text(bx + 34, y, legend[i], kInk);
        }
    }
    return image;
}

} // namespace marbles::plot
