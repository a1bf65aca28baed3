#pragma once
// Plots through the gnuplot program.
#include <string>
#include <utility>
#include <vector>

namespace beamtrace::report {

// Whether an executable `gnuplot` is on PATH.
bool gnuplot_available();

// Renders a 1024x640 PNG at png_path with gnuplot.
//
// The data files (name, contents) and the script are written to the folder "<png stem>.plot"
// beside the PNG, where they stay so the plot can be redone by hand (`gnuplot plot.gp`); gnuplot's
// output goes to gnuplot.log there. The script sets the terminal (pngcairo when gnuplot has it,
// else png) and the output, changes to that folder so the body can name data files plainly
// (plot 'speed.dat' using 1:2 ...), then runs gnuplot_script_body.
//
// Throws beamtrace::Error if a data file name is not a plain file name, a file cannot be written,
// gnuplot is missing or exits with an error (the message quotes its log), or no PNG was produced.
// A failed run leaves no PNG behind (neither an old one nor gnuplot's partial one).
void plot_with_gnuplot(const std::string& png_path, const std::string& gnuplot_script_body,
                       const std::vector<std::pair<std::string, std::string>>& data_files);

}  // namespace beamtrace::report
