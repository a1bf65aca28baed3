// PNG output read back with stb_image.
#include "report/png_image.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <filesystem>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::report {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("beamtrace_report_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    return dir;
}

TEST(PngImage, WrittenAndReadBack) {
    Image img(5, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) img.set(x, y, std::uint8_t(40 * x), std::uint8_t(100 * y), std::uint8_t(x + y));
    img.set(4, 2, 255, 0, 7);
    const fs::path dir = fresh_dir("png");
    const std::string path = (dir / "nested" / "deeper" / "image.png").string();  // parents created
    write_png(img, path);

    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
    ASSERT_NE(data, nullptr) << stbi_failure_reason();
    EXPECT_EQ(w, 5);
    EXPECT_EQ(h, 3);
    EXPECT_EQ(channels, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) {
            const unsigned char* p = data + (y * 5 + x) * 3;
            const std::uint8_t* q = img.at(x, y);
            EXPECT_EQ(p[0], q[0]);
            EXPECT_EQ(p[1], q[1]);
            EXPECT_EQ(p[2], q[2]);
        }
    const unsigned char* corner = data + (2 * 5 + 4) * 3;
    EXPECT_EQ(corner[0], 255);
    EXPECT_EQ(corner[1], 0);
    EXPECT_EQ(corner[2], 7);
    EXPECT_EQ(data[1 * 3 + 0], 40);         // pixel (1, 0)
    EXPECT_EQ(data[(1 * 5) * 3 + 1], 100);  // pixel (0, 1)
    stbi_image_free(data);
    fs::remove_all(dir);
}

TEST(PngImage, Errors) {
    Image img(2, 2);
    EXPECT_THROW(img.set(2, 0, 1, 2, 3), Error);
    EXPECT_THROW(img.set(0, -1, 1, 2, 3), Error);
    EXPECT_THROW(Image(-1, 4), Error);
    EXPECT_THROW(write_png(Image(), "/tmp/never.png"), Error);

    const fs::path dir = fresh_dir("err");
    fs::create_directories(dir);
    // A regular file where a parent directory should be: the message names the path.
    const fs::path blocker = dir / "blocker";
    {
        std::FILE* f = std::fopen(blocker.c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fclose(f);
    }
    const std::string path = (blocker / "sub" / "x.png").string();
    try {
        write_png(img, path);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    // A directory in place of the file.
    const std::string as_dir = (dir).string();
    try {
        write_png(img, as_dir);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(as_dir), std::string::npos) << e.what();
    }
    img.rgb.pop_back();
    EXPECT_THROW(write_png(img, (dir / "bad.png").string()), Error);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace beamtrace::report
