// The stderr progress bar.
#include "report/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace beamtrace::report {

bool stderr_is_terminal() { return isatty(fileno(stderr)) != 0; }

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (drawn_ && !finished_) {
        std::fputc('\n', stderr);
        std::fflush(stderr);
    }
}

std::int64_t ProgressBar::elapsed_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressBar::update(double fraction) {
    if (!enabled_ || std::isnan(fraction)) return;
    fraction = std::clamp(fraction, 0.0, 1.0);
    double seen = fraction_.load(std::memory_order_relaxed);
    while (fraction > seen && !fraction_.compare_exchange_weak(seen, fraction, std::memory_order_relaxed)) {}
    const std::int64_t now = elapsed_ns();
    if (now < next_draw_ns_.load(std::memory_order_relaxed)) return;
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;  // another thread is drawing right now
    if (finished_ || now < next_draw_ns_.load(std::memory_order_relaxed)) return;
    next_draw_ns_.store(now + std::chrono::nanoseconds(kRedrawInterval).count(), std::memory_order_relaxed);
    draw(fraction_.load(std::memory_order_relaxed), false);
}

void ProgressBar::finish() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    finished_ = true;
    draw(1.0, true);
}

void ProgressBar::draw(double fraction, bool final) {
    const int filled = std::min(kWidth, static_cast<int>(fraction * kWidth));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.append(static_cast<std::size_t>(kWidth - filled), '.');
    const int percent = static_cast<int>(fraction * 100.0);
    const double seconds = static_cast<double>(elapsed_ns()) * 1e-9;
    std::fprintf(stderr, "\r%s [%s] %3d%%  %.1f s  ", label_.c_str(), bar.c_str(), percent, seconds);
    if (final) std::fputc('\n', stderr);
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace beamtrace::report
