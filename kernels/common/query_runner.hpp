#pragma once
// What every accelerator's span queries share (query.hpp): the size checks, and the run of a query
// over [0, n) on QueryOptions::threads TBB threads of the library's own, each part counting into its
// own QueryCounters (added to QueryOptions::counters at the end).
#include <algorithm>
#include <cstddef>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "beamtrace/error.hpp"
#include "beamtrace/query.hpp"

namespace beamtrace {

// Throws beamtrace::Error when the spans differ in size or the options are out of range.
inline void check_query(const char* what, std::size_t inputs, std::size_t outputs, const QueryOptions& options) {
    if (inputs != outputs)
        throw Error(std::string(what) + ": " + std::to_string(inputs) + " inputs but room for " +
                    std::to_string(outputs) + " answers (the spans must have the same size)");
    if (options.threads < 1)
        throw Error(std::string(what) + ": threads must be at least 1, not " + std::to_string(options.threads));
}

// f(begin, end, counters) over parts of [0, n) of at least `grain` items; counters is null when the
// call counts nothing. One thread: a single part on the calling thread.
template <class F>
void run_query(std::size_t n, const QueryOptions& options, std::size_t grain, F&& f) {
    if (options.threads <= 1 || n <= grain) {
        f(std::size_t{0}, n, options.counters);
        return;
    }
    tbb::combinable<QueryCounters> per_thread;
    tbb::task_arena arena(options.threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
            f(r.begin(), r.end(), options.counters ? &per_thread.local() : nullptr);
        });
    });
    if (options.counters) per_thread.combine_each([&](const QueryCounters& c) { *options.counters += c; });
}

// f(begin, end) on exactly min(threads, n) contiguous parts of [0, n) at once (for streams, which
// are faster the longer they are); one part on the calling thread when threads is 1.
template <class F>
void run_query_parts(std::size_t n, const QueryOptions& options, F&& f) {
    const std::size_t parts = std::max<std::size_t>(1, std::min<std::size_t>(std::size_t(options.threads), n));
    if (parts == 1) {
        f(std::size_t{0}, n);
        return;
    }
    tbb::task_arena arena{int(parts)};
    arena.execute([&] {
        tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t k) { f(n * k / parts, n * (k + 1) / parts); });
    });
}

}  // namespace beamtrace
