#pragma once
// The picture of a trade: Mrays/s against error rate, one point per setting, the Pareto front.
#include <cstddef>
#include <string>
#include <vector>

namespace beamtrace::workload {

struct TradeResult;

// Indices of the points no other point beats: none has at most the same error and at least the same
// speed with one of them strictly better. Equal points keep the first. Sorted by error, ascending
// (so speeds ascend too). Throws beamtrace::Error if the two lists differ in length.
std::vector<std::size_t> pareto_front(const std::vector<double>& error, const std::vector<double>& speed);

// The gnuplot script body and data files of the plot (report::plot_with_gnuplot takes both).
// x: mismatches per ray in percent on a log scale, settings without mismatches drawn at a "0" tick
// left of the smallest decade; y: Mrays/s (log scale when the speeds span more than 10x), the right
// axis as multiples of the anchor, whose speed is a dashed line across the plot. The front takes in
// the references (Embree): an exact Embree point faster than one of ours dominates it.
struct TradePlot {
    std::string script;
    std::vector<std::pair<std::string, std::string>> data_files;
};
TradePlot trade_plot(const TradeResult& result);

// Writes the plot with gnuplot (throws beamtrace::Error if gnuplot is missing or fails).
void plot_trade(const TradeResult& result, const std::string& png_path);

}  // namespace beamtrace::workload
