#pragma once
// Runs work over the packets of a RaySet on a given number of threads (TBB), or inline for one.
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace beamtrace::workload {

// f(begin, end) over packet index ranges; ranges are small enough to balance, large enough to be cheap.
template <class F>
void for_packet_ranges(std::size_t packets, int threads, F&& f) {
    if (threads <= 1) {
        f(std::size_t{0}, packets);
        return;
    }
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, packets, 16),
                          [&](const tbb::blocked_range<std::size_t>& r) { f(r.begin(), r.end()); });
    });
}

}  // namespace beamtrace::workload
