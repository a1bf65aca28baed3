#pragma once
// A one-line progress bar on stderr: "label [#########.........]  42%  3.1 s".
//
// Redrawn in place with '\r' at most about ten times a second; update() may be called from any
// number of threads at once (TBB workers) and costs an atomic load or two when no redraw is due.
// Silent when disabled, which by default it is unless stderr is a terminal.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace beamtrace::report {

// Whether stderr is a terminal (isatty).
bool stderr_is_terminal();

class ProgressBar {
public:
    explicit ProgressBar(std::string label, bool enabled = stderr_is_terminal());
    // Ends the line if a bar was drawn and finish() was not called (an interrupted task).
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    // Reports progress in [0, 1] (clamped; NaN ignored). The bar never moves backwards, so
    // out-of-order updates from several threads are harmless.
    void update(double fraction);
    // Draws the bar at 100 % with the total time and ends the line. Later calls do nothing.
    void finish();

    bool enabled() const { return enabled_; }

    static constexpr int kWidth = 30;  // characters between the brackets
    static constexpr std::chrono::milliseconds kRedrawInterval{100};

private:
    void draw(double fraction, bool final);  // with mutex_ held
    std::int64_t elapsed_ns() const;

    std::string label_;
    bool enabled_;
    std::chrono::steady_clock::time_point start_;
    std::atomic<double> fraction_{0.0};
    std::atomic<std::int64_t> next_draw_ns_{0};
    std::mutex mutex_;
    bool drawn_ = false;
    bool finished_ = false;
};

}  // namespace beamtrace::report
