#pragma once
// One ray through the sorted lists (list_traversal.cpp). Counting is a template parameter, so the
// measured path and the counted path are the same code.
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "lists/lists_impl.hpp"

namespace beamtrace::lists {

// Closest hit (or, with kOcclusion, any hit: Hit::hit() tells) of the ray; with kCount, counters->rays,
// triangle_tests and lists.* grow.
template <bool kOcclusion, bool kCount>
Hit trace_ray(const SortedLists::Impl& impl, const Ray& ray, QueryCounters* counters);

}  // namespace beamtrace::lists
