#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

/// A small chart writer for marbles-cli: line charts on linear or logarithmic axes, rendered into
/// an RGB raster and stored as PNG, with no Qt and no zlib (the CLI stays headless and light).
namespace marbles::plot {

/// One line of the chart: points joined in the given order, each marked with a dot.
struct Series {
    std::string label;
    std::uint32_t rgb = 0x000000; ///< 0xRRGGBB
    std::vector<double> x;
    std::vector<double> y;
    bool markers = true;
};

/// What to draw. On a logarithmic axis, points with a value <= 0 or not finite cannot be placed;
/// they are left out and the legend says how many.
struct Chart {
    std::string title;
    std::string xLabel;
    std::string yLabel;
    bool logX = true;
    bool logY = true;
    std::vector<Series> series;
    int width = 960;  ///< px
    int height = 640; ///< px
};

/// An 8-bit RGB raster, rows top to bottom.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb; ///< width * height * 3 bytes

    /// The colour at (x, y) as 0xRRGGBB; (x, y) must be inside.
    std::uint32_t pixel(int x, int y) const;
};

/// Draws `chart` into a new raster of chart.width x chart.height.
Image render(const Chart &chart);

/// The PNG file for `image` (colour type 2, 8 bits, stored deflate blocks).
std::vector<std::uint8_t> encodePng(const Image &image);

/// CRC-32 (ISO 3309, as PNG uses) of `size` bytes.
std::uint32_t crc32(const std::uint8_t *data, std::size_t size);

} // namespace marbles::plot
