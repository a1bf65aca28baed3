// PNG output through stb_image_write (its implementation comes compiled in libstb).
#include "report/png_image.hpp"

#include <stb_image_write.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "beamtrace/error.hpp"

namespace beamtrace::report {

namespace {

void check_inside(const Image& image, int x, int y) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height)
        throw Error("image: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                    std::to_string(image.width) + "x" + std::to_string(image.height) + " image");
}

}  // namespace

Image::Image(int w, int h) : width(w), height(h) {
    if (w < 0 || h < 0) throw Error("image: negative size " + std::to_string(w) + "x" + std::to_string(h));
    rgb.assign(std::size_t(w) * std::size_t(h) * 3, 0);
}

void Image::set(int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    check_inside(*this, x, y);
    std::uint8_t* p = &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

const std::uint8_t* Image::at(int x, int y) const {
    check_inside(*this, x, y);
    return &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
}

void write_png(const Image& image, const std::string& path) {
    if (image.width <= 0 || image.height <= 0)
        throw Error("cannot write PNG '" + path + "': the image is empty (" + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + ")");
    if (image.rgb.size() != std::size_t(image.width) * std::size_t(image.height) * 3)
        throw Error("cannot write PNG '" + path + "': pixel buffer holds " + std::to_string(image.rgb.size()) +
                    " bytes, expected " + std::to_string(std::size_t(image.width) * image.height * 3));
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(parent, ec);
        if (ec)
            throw Error("cannot write PNG '" + path + "': cannot create directory '" + parent.string() +
                        "': " + ec.message());
    }
    errno = 0;
    if (stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(), image.width * 3) == 0)
        throw Error("cannot write PNG '" + path + "'" + (errno != 0 ? std::string(": ") + std::strerror(errno) : ""));
}

}  // namespace beamtrace::report
