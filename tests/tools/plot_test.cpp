// gnuplot renders a PNG; failures come back as clear errors.
#include "report/plot.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::report {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("beamtrace_plot_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    return dir;
}

TEST(Plot, GnuplotProducesAPng) {
    if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed; skipping the plot test";
    const fs::path dir = fresh_dir("ok");
    const std::string png = (dir / "out" / "squares.png").string();
    plot_with_gnuplot(png,
                      "set xlabel 'n'\nset ylabel \"n squared\"\n"
                      "plot 'squares.dat' using 1:2 with linespoints title 'squares', "
                      "'cubes.dat' using 1:2 with lines title 'cubes'",
                      {{"squares.dat", "1 1\n2 4\n3 9\n4 16\n"}, {"cubes.dat", "1 1\n2 8\n3 27\n"}});
    int w = 0, h = 0, c = 0;
    unsigned char* data = stbi_load(png.c_str(), &w, &h, &c, 3);
    ASSERT_NE(data, nullptr) << stbi_failure_reason();
    EXPECT_EQ(w, 1024);
    EXPECT_EQ(h, 640);
    // Not a blank image: some pixels differ from the first one.
    int different = 0;
    for (int i = 0; i < w * h; ++i)
        if (data[3 * i] != data[0] || data[3 * i + 1] != data[1] || data[3 * i + 2] != data[2]) ++different;
    EXPECT_GT(different, 1000);
    stbi_image_free(data);
    // The data and the script stay beside the PNG.
    EXPECT_TRUE(fs::exists(dir / "out" / "squares.plot" / "squares.dat"));
    EXPECT_TRUE(fs::exists(dir / "out" / "squares.plot" / "plot.gp"));
    fs::remove_all(dir);
}

TEST(Plot, PathsWithQuotesAndSpaces) {
    if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed; skipping the plot test";
    const fs::path dir = fresh_dir("quote") / "it's a dir";
    const std::string png = (dir / "p.png").string();
    plot_with_gnuplot(png, "plot 'd.dat' with lines notitle", {{"d.dat", "0 0\n1 1\n"}});
    EXPECT_GT(fs::file_size(png), 0u);
    fs::remove_all(dir.parent_path());
}

TEST(Plot, GnuplotErrorsAreReported) {
    if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed; skipping the plot test";
    const fs::path dir = fresh_dir("bad");
    const std::string png = (dir / "bad.png").string();
    try {
        plot_with_gnuplot(png, "plot 'missing.dat' using 1:2 with lines", {});
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("gnuplot failed"), std::string::npos) << what;
        EXPECT_NE(what.find("missing.dat"), std::string::npos) << what;  // gnuplot's own message
        EXPECT_NE(what.find(png), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(png));
    try {
        plot_with_gnuplot(png, "this is not gnuplot", {});
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("gnuplot failed"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

TEST(Plot, BadDataFileNamesAreRejected) {
    const fs::path dir = fresh_dir("names");
    const std::string png = (dir / "x.png").string();
    EXPECT_THROW(plot_with_gnuplot(png, "plot x", {{"../escape.dat", "1 1\n"}}), Error);
    EXPECT_THROW(plot_with_gnuplot(png, "plot x", {{"", "1 1\n"}}), Error);
    EXPECT_THROW(plot_with_gnuplot(png, "plot x", {{"plot.gp", "1 1\n"}}), Error);
    EXPECT_THROW(plot_with_gnuplot("", "plot x", {}), Error);
    fs::remove_all(dir);
}

TEST(Plot, MissingGnuplotIsAClearError) {
    // With an empty PATH gnuplot cannot be found.
    const char* old = std::getenv("PATH");
    const std::string saved = old != nullptr ? old : "";
    setenv("PATH", "/nonexistent-beamtrace-dir", 1);
    EXPECT_FALSE(gnuplot_available());
    const fs::path dir = fresh_dir("nognuplot");
    try {
        plot_with_gnuplot((dir / "x.png").string(), "plot x", {});
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("gnuplot is not installed"), std::string::npos) << e.what();
    }
    setenv("PATH", saved.c_str(), 1);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace beamtrace::report
