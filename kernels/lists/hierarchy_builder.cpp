// The paper's automatic hierarchy, top down: a regular grid laid over a volume's box, each object in
// the cell holding its box centre, each non-empty cell a child whose volume is the union of its
// objects' boxes (so volumes may overlap; no object is split or duplicated), recursively until a
// volume holds at most leaf_objects objects. When every centre falls in one cell, the objects that
// cover a large part of the volume go to its *special cell* (they stay direct children of the volume)
// and the rest is split again; when nothing is large, the grid is laid over the centres' box instead
// (our addition: it always separates distinct centres), and objects with one common centre make a
// leaf whatever their number. Then every volume gets its event lists over its direct children.
#include <algorithm>
#include <cmath>
#include <vector>

#include "lists/lists_impl.hpp"

namespace beamtrace::lists {
namespace {

struct Task {
    std::vector<std::uint32_t> triangles;  // the volume's objects
    std::uint32_t volume;
};

struct Builder {
    SortedLists::Impl& impl;
    std::vector<Box> boxes;       // by triangle id
    std::vector<Float3> centres;  // by triangle id

    Box union_of(const std::vector<std::uint32_t>& tris) const {
        Box b;
        for (std::uint32_t t : tris) b.extend(boxes[t]);
        return b;
    }

    // Groups of tris by the cell of the res[0] x res[1] x res[2] grid over `over` holding their
    // centres (empty cells dropped, groups in cell order).
    std::vector<std::vector<std::uint32_t>> grid_groups(const std::vector<std::uint32_t>& tris, const Box& over) const {
        const int* res = impl.rules.grid;
        std::vector<std::vector<std::uint32_t>> cells(std::size_t(res[0] * res[1] * res[2]));
        for (std::uint32_t t : tris) {
            int cell = 0;
            for (int a = 2; a >= 0; --a) {
                const float extent = over.upper[a] - over.lower[a];
                int c = 0;
                if (extent > 0.0f) {
                    c = int(float(res[a]) * ((centres[t][a] - over.lower[a]) / extent));
                    c = std::clamp(c, 0, res[a] - 1);
                }
                cell = cell * res[a] + c;
            }
            cells[std::size_t(cell)].push_back(t);
        }
        std::vector<std::vector<std::uint32_t>> groups;
        for (auto& c : cells)
            if (!c.empty()) groups.push_back(std::move(c));
        return groups;
    }

    // The children of a volume holding tris (bound `box`): direct triangles, and groups for new volumes.
    void split(const std::vector<std::uint32_t>& tris, const Box& box, std::vector<std::uint32_t>& direct,
               std::vector<std::vector<std::uint32_t>>& groups, bool& special) const {
        special = false;
        if (impl.rules.flat || tris.size() <= std::size_t(impl.rules.leaf_objects)) {
            direct = tris;
            return;
        }
        groups = grid_groups(tris, box);
        if (groups.size() > 1) return;
        // Every centre in one cell: the special cell takes the objects covering a large part of the volume.
        std::vector<std::uint32_t> rest;
        for (std::uint32_t t : tris) {
            bool large = false;
            for (int a = 0; a < 3; ++a) {
                const float extent = box.upper[a] - box.lower[a];
                large = large || (extent > 0.0f &&
                                  boxes[t].upper[a] - boxes[t].lower[a] >= impl.rules.special_cell_fraction * extent);
            }
            (large ? direct : rest).push_back(t);
        }
        groups.clear();
        if (!direct.empty()) {
            special = true;
            if (rest.size() == 1) direct.push_back(rest[0]);
            if (rest.size() > 1) groups.push_back(std::move(rest));
            return;
        }
        Box centre_box;
        for (std::uint32_t t : tris) centre_box.extend(centres[t]);
        groups = grid_groups(tris, centre_box);
        if (groups.size() > 1) return;
        groups.clear();
        direct = tris;  // one common centre: a leaf
    }

    void run() {
        const Scene& scene = impl.scene;
        impl.triangle_count = std::uint32_t(scene.triangle_count());
        boxes.resize(impl.triangle_count);
        centres.resize(impl.triangle_count);
        std::vector<std::uint32_t> all;
        for (std::uint32_t t = 0; t < impl.triangle_count; ++t) {
            const Triangle& tri = scene.triangle(t);
            Box b;
            b.extend(tri.v0);
            b.extend(tri.v1);
            b.extend(tri.v2);
            boxes[t] = b;
            // Half the sum (not the sum halved) stays finite for coordinates near float's limit.
            for (int a = 0; a < 3; ++a) centres[t][a] = b.lower[a] * 0.5f + b.upper[a] * 0.5f;
            if (!scene.is_degenerate(t)) all.push_back(t);
        }
        SortedListStats& st = impl.stats;
        st.triangles = impl.triangle_count;
        st.degenerate_triangles = scene.degenerate_count();

        impl.volumes.push_back(Volume{});
        std::vector<Task> stack;
        stack.push_back(Task{std::move(all), 0});
        std::size_t children_total = 0;
        while (!stack.empty()) {
            Task task = std::move(stack.back());
            stack.pop_back();
            const Box box = union_of(task.triangles);
            std::vector<std::uint32_t> direct;
            std::vector<std::vector<std::uint32_t>> groups;
            bool special = false;
            split(task.triangles, box, direct, groups, special);
            if (special) ++st.special_cells;

            // Children: the direct triangles, single-object groups as triangles, the others as volumes.
            std::vector<std::uint32_t> items = direct;
            std::vector<Box> item_boxes;
            for (std::uint32_t t : direct) item_boxes.push_back(boxes[t]);
            const std::uint32_t depth = impl.volumes[task.volume].depth;
            for (auto& g : groups) {
                if (g.size() == 1) {
                    items.push_back(g[0]);
                    item_boxes.push_back(boxes[g[0]]);
                    continue;
                }
                const std::uint32_t v = std::uint32_t(impl.volumes.size());
                Volume child;
                child.box = union_of(g);
                child.depth = depth + 1;
                impl.volumes.push_back(child);
                items.push_back(impl.triangle_count + v);
                item_boxes.push_back(child.box);
                stack.push_back(Task{std::move(g), v});
            }

            Volume& vol = impl.volumes[task.volume];
            vol.box = box;
            vol.children = std::uint32_t(items.size());
            vol.first = std::uint32_t(impl.events.size());
            children_total += items.size();
            st.depth = std::max(st.depth, int(depth) + 1);
            for (int a = 0; a < 3; ++a)
                for (int upper = 0; upper < 2; ++upper) {
                    const std::size_t start = impl.events.size();
                    for (std::size_t i = 0; i < items.size(); ++i)
                        impl.events.push_back(Event{upper ? item_boxes[i].upper[a] : item_boxes[i].lower[a], items[i]});
                    std::sort(impl.events.begin() + std::ptrdiff_t(start), impl.events.end(),
                              [](const Event& x, const Event& y) {
                                  return x.value < y.value || (x.value == y.value && x.item < y.item);
                              });
                }
        }
        st.volumes = impl.volumes.size();
        st.events = impl.events.size();
        st.mean_children = st.volumes ? double(children_total) / double(st.volumes) : 0.0;
        st.memory_bytes = impl.events.size() * sizeof(Event) + impl.volumes.size() * sizeof(Volume);
    }
};

}  // namespace

void build_hierarchy(SortedLists::Impl& impl) {
    Builder b{impl, {}, {}};
    b.run();
}

}  // namespace beamtrace::lists
