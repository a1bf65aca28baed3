#pragma once
// The library's own access to the implementation behind its public classes (tests and benchmarks
// use it too, through the beamtrace_internal target). Never installed: the public headers show the
// API only and name this struct as a friend.
#include <memory>

#include "beamtrace/crsh.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "beamtrace/sorted_lists.hpp"
#include "beamtrace/vlf.hpp"

namespace beamtrace::detail {

struct Access {
    static const KdTree::Impl& impl(const KdTree& tree) { return *tree.impl_; }
    // A tree assembled by other means (tests build trees node by node to reach exact cases).
    static KdTree make_tree(std::shared_ptr<const KdTree::Impl> impl) { return KdTree(std::move(impl)); }
    static const Mlrta::Impl& impl(const Mlrta& mlrta) { return *mlrta.impl_; }
    static std::shared_ptr<const Mlrta::Impl> share(const Mlrta& mlrta) { return mlrta.impl_; }
    static const DirectionSet::Impl& impl(const DirectionSet& set) { return *set.impl_; }
    static const VisibilityField::Impl& impl(const VisibilityField& field) { return *field.impl_; }
    static const Crsh::Impl& impl(const Crsh& crsh) { return *crsh.impl_; }
    static const SortedLists::Impl& impl(const SortedLists& lists) { return *lists.impl_; }
};

}  // namespace beamtrace::detail
