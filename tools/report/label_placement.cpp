#include "report/label_placement.hpp"

#include <algorithm>

namespace beamtrace::report {

namespace {

struct Box {
    double x0, y0, x1, y1;
};

double overlap(const Box& a, const Box& b) {
    const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0);
    const double h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
    return w > 0.0 && h > 0.0 ? w * h : 0.0;
}

double area(const Box& b) { return (b.x1 - b.x0) * (b.y1 - b.y0); }

Box text_box(const LabelledPoint& p, LabelSide side, const LabelGeometry& g) {
    const double w = double(p.characters) * g.char_width;
    const bool right = side == LabelSide::above_right || side == LabelSide::below_right;
    const bool above = side == LabelSide::above_right || side == LabelSide::above_left;
    const double x0 = right ? p.x + g.gap_x : p.x - g.gap_x - w;
    const double yc = above ? p.y + g.gap_y : p.y - g.gap_y;
    return {x0, yc - g.line_height / 2, x0 + w, yc + g.line_height / 2};
}

Box marker_box(const LabelledPoint& p, const LabelGeometry& g) {
    return {p.x - g.marker_radius, p.y - g.marker_radius, p.x + g.marker_radius, p.y + g.marker_radius};
}

}  // namespace

std::vector<LabelSide> place_labels(const std::vector<LabelledPoint>& labels, const std::vector<LabelledPoint>& markers,
                                    const LabelGeometry& g) {
    std::vector<Box> obstacles;
    for (const LabelledPoint& m : markers) obstacles.push_back(marker_box(m, g));
    for (const LabelledPoint& l : labels) obstacles.push_back(marker_box(l, g));
    const Box inside{0.0, 0.0, g.width, g.height};
    std::vector<LabelSide> sides;
    for (const LabelledPoint& label : labels) {
        LabelSide best = LabelSide::above_right;
        double best_cost = -1.0;
        for (LabelSide side :
             {LabelSide::above_right, LabelSide::below_right, LabelSide::above_left, LabelSide::below_left}) {
            const Box b = text_box(label, side, g);
            double cost = 4.0 * (area(b) - overlap(b, inside));  // text cut off by the frame is worst
            for (const Box& o : obstacles) cost += overlap(b, o);
            if (best_cost < 0.0 || cost < best_cost) best = side, best_cost = cost;
        }
        sides.push_back(best);
        obstacles.push_back(text_box(label, best, g));
    }
    return sides;
}

}  // namespace beamtrace::report
