#pragma once
// Where to put the text of point labels in a plot so that they cover neither each other nor the
// points: each label goes above or below its point, to the right or to the left, greedily in the
// order given (so the important labels go first and get their favourite side).
#include <cstddef>
#include <vector>

namespace beamtrace::report {

enum class LabelSide { above_right, below_right, above_left, below_left };

struct LabelGeometry {
    double width = 1.0, height = 1.0;  // the plotting area, same units as the points (pixels, say)
    double char_width = 5.5;           // of the label font
    double line_height = 11.0;
    double gap_x = 8.0, gap_y = 7.0;  // from the point to the text's near edge / to the text's centre line
    double marker_radius = 5.0;       // points are kept free of text within this distance
};

struct LabelledPoint {
    double x = 0.0, y = 0.0;  // in the area, y upwards
    std::size_t characters = 0;
};

// One side per label: the side whose text box overlaps earlier labels, markers (every label's point
// and the extra ones) and the area's outside the least, the first side listed in LabelSide on ties.
std::vector<LabelSide> place_labels(const std::vector<LabelledPoint>& labels, const std::vector<LabelledPoint>& markers,
                                    const LabelGeometry& geometry);

}  // namespace beamtrace::report
