#pragma once
// An 8-bit RGB image and PNG output (stb_image_write).
#include <cstdint>
#include <string>
#include <vector>

namespace beamtrace::report {

struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // row-major from the top row, 3 bytes per pixel

    Image() = default;
    // A black image; throws beamtrace::Error for negative sizes.
    Image(int width, int height);

    // Pixel (x, y), y = 0 the top row. Throws beamtrace::Error outside the image.
    void set(int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b);
    const std::uint8_t* at(int x, int y) const;
};

// Writes the image as PNG, creating missing parent directories. Throws beamtrace::Error naming the
// path if the image is empty or inconsistent, or the file cannot be written.
void write_png(const Image& image, const std::string& path);

}  // namespace beamtrace::report
