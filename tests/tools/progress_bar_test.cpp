// The progress bar: silent when disabled, the line format, rate limiting and concurrent updates.
#include "report/progress_bar.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

namespace beamtrace::report {
namespace {

// Everything written to file descriptor 2 while fn runs.
std::string capture_stderr(const std::function<void()>& fn) {
    std::fflush(stderr);
    std::FILE* tmp = std::tmpfile();
    EXPECT_NE(tmp, nullptr);
    const int saved = dup(2);
    dup2(fileno(tmp), 2);
    fn();
    std::fflush(stderr);
    dup2(saved, 2);
    close(saved);
    std::rewind(tmp);
    std::string out;
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, tmp)) > 0) out.append(buf, n);
    std::fclose(tmp);
    return out;
}

TEST(ProgressBar, DisabledWritesNothing) {
    const std::string out = capture_stderr([] {
        ProgressBar bar("silent", false);
        EXPECT_FALSE(bar.enabled());
        for (int i = 0; i <= 100; ++i) bar.update(i / 100.0);
        bar.finish();
    });
    EXPECT_EQ(out, "");
}

TEST(ProgressBar, DefaultFollowsWhetherStderrIsATerminal) {
    // Under ctest stderr is a pipe or file; when captured it is a file for sure.
    std::string out = capture_stderr([] {
        ProgressBar bar("default");
        EXPECT_EQ(bar.enabled(), stderr_is_terminal());
        EXPECT_FALSE(bar.enabled());
        bar.update(0.5);
        bar.finish();
    });
    EXPECT_EQ(out, "");
}

TEST(ProgressBar, DrawsTheLine) {
    const std::string out = capture_stderr([] {
        ProgressBar bar("tracing", true);
        bar.update(0.42);
        bar.finish();
        bar.finish();  // only once
    });
    EXPECT_EQ(out.rfind("\rtracing [############..................]  42%  ", 0), 0u) << out;
    EXPECT_NE(out.find(" s  \r"), std::string::npos) << out;  // elapsed seconds after the percentage
    EXPECT_NE(out.find("\rtracing [##############################] 100%  "), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1);
    EXPECT_EQ(out.back(), '\n');
}

TEST(ProgressBar, RateLimitedAndMonotonic) {
    const std::string out = capture_stderr([] {
        ProgressBar bar("fast", true);
        for (int i = 0; i < 100000; ++i) bar.update(0.5 * i / 100000.0);
        bar.update(0.9);
        std::this_thread::sleep_for(ProgressBar::kRedrawInterval * 2);
        bar.update(0.1);  // late update from a slow thread: the bar stays at 90 %
        bar.finish();
    });
    const auto redraws = std::count(out.begin(), out.end(), '\r');
    EXPECT_GE(redraws, 3);
    EXPECT_LE(redraws, 12) << out;  // 100000 updates in well under a second
    EXPECT_NE(out.find(" 90%"), std::string::npos) << out;
    EXPECT_EQ(out.find(" 10%"), std::string::npos) << out;
}

TEST(ProgressBar, ConcurrentUpdates) {
    const std::string out = capture_stderr([] {
        ProgressBar bar("parallel", true);
        tbb::parallel_for(0, 200000, [&](int i) { bar.update(i / 200000.0); });
        bar.finish();
    });
    EXPECT_NE(out.find("100%"), std::string::npos);
    EXPECT_EQ(out.back(), '\n');
    // Every drawn line is complete: a '\r' starts each one and none is interleaved with another.
    std::size_t pos = 0;
    while ((pos = out.find('\r', pos)) != std::string::npos) {
        EXPECT_EQ(out.compare(pos, 11, "\rparallel ["), 0) << out.substr(pos, 40);
        ++pos;
    }
}

TEST(ProgressBar, DestroyedUnfinishedEndsTheLine) {
    const std::string out = capture_stderr([] {
        ProgressBar bar("aborted", true);
        bar.update(0.3);
    });
    EXPECT_NE(out.find(" 30%"), std::string::npos);
    EXPECT_EQ(out.back(), '\n');
    EXPECT_EQ(out.find("100%"), std::string::npos);
}

}  // namespace
}  // namespace beamtrace::report
