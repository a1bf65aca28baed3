#include "experiments/trade_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "beamtrace/error.hpp"
#include "report/label_placement.hpp"
#include "report/plot.hpp"
#include "experiments/trade_sweep.hpp"

namespace beamtrace::workload {

namespace {

// A gnuplot single-quoted string.
std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) {
        out += c;
        if (c == '\'') out += '\'';
    }
    return out + "'";
}

// A gnuplot data-file string (double quotes; no quotes or backslashes inside).
std::string data_string(std::string s) {
    for (char& c : s)
        if (c == '"' || c == '\\') c = '\'';
    return "\"" + s + "\"";
}

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

// A tick label for a percentage on a log axis: 0.001%, 0.1%, 10% (written %% for gnuplot).
std::string percent(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g%%%%", v);  // gnuplot reads tic labels as formats: %% is one %
    return buf;
}

// The plotting area of the 1024x640 picture in pixels, roughly (margins, axis labels and the key
// below take the rest): what label placement measures against.
constexpr double kAreaWidth = 840.0, kAreaHeight = 450.0;

// Colour and point type of each engine, the same in every plot.
struct Style {
    const char* colour;
    int point;
};
Style engine_style(const std::string& engine) {
    static const std::map<std::string, Style> styles = {
        {"embree1", {"#7f7f7f", 4}}, {"embree16", {"#404040", 5}}, {"embree-stream", {"#a0a0a0", 8}},
        {"brute", {"#bcbd22", 3}},   {"kd1", {"#1f77b4", 7}},      {"kd16", {"#17becf", 9}},
        {"mlrta", {"#2ca02c", 11}},  {"vlf", {"#d62728", 13}},     {"vlf-fast", {"#ff7f0e", 15}}};
    const auto it = styles.find(engine);
    return it != styles.end() ? it->second : Style{"#9467bd", 1};
}

// "set TICS (...)" with ticks at 1, 2 and 5 times the powers of ten between low and high.
std::string log_tics(const std::string& tics, double low, double high) {
    std::string out;
    for (double decade = std::pow(10.0, std::floor(std::log10(low))); decade <= high; decade *= 10.0)
        for (double m : {1.0, 2.0, 5.0}) {
            const double t = m * decade;
            if (t < low || t > high) continue;
            char label[64];
            std::snprintf(label, sizeof label, "%g", t);
            out += (out.empty() ? "" : ", ") + quoted(label) + " " + number(t);
        }
    return "set " + tics + " (" + out + ")\n";
}

}  // namespace

std::vector<std::size_t> pareto_front(const std::vector<double>& error, const std::vector<double>& speed) {
    if (error.size() != speed.size())
        throw Error("pareto_front: " + std::to_string(error.size()) + " errors but " + std::to_string(speed.size()) +
                    " speeds");
    std::vector<std::size_t> order(error.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    // By error ascending, then speed descending, then index (the first of equal points wins).
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (error[a] != error[b]) return error[a] < error[b];
        return speed[a] > speed[b];
    });
    std::vector<std::size_t> front;
    for (std::size_t i : order)
        if (front.empty() || speed[i] > speed[front.back()]) front.push_back(i);
    return front;
}

TradePlot trade_plot(const TradeResult& r) {
    std::vector<const TradeRow*> rows;
    for (const TradeRow& row : r.rows)
        if (row.measured()) rows.push_back(&row);
    if (rows.empty()) throw Error("trade: no setting was measured, nothing to plot");

    // x in percent; settings without mismatches sit around `zero`, a decade below the smallest error,
    // each engine a little apart (a strip of the "0" tick) so that their points do not hide each other.
    double smallest = 0.0, largest = 0.0;
    for (const TradeRow* row : rows) {
        const double x = 100.0 * row->error_rate();
        if (x > 0.0) smallest = smallest > 0.0 ? std::min(smallest, x) : x, largest = std::max(largest, x);
    }
    if (smallest == 0.0) smallest = 100.0 / double(std::max<std::size_t>(r.rays, 1));
    const double zero = std::pow(10.0, std::floor(std::log10(smallest)) - 1.0);
    const double top = std::pow(10.0, std::ceil(std::log10(std::max(largest, zero * 10.0))));
    std::map<std::string, double> strip;  // engine -> x of its error-free settings
    for (const TradeRow* row : rows) strip.emplace(row->setting.engine, 0.0);
    {
        const double n = double(strip.size());
        double k = 0.0;
        for (auto& [engine, x] : strip) x = zero * std::pow(10.0, 0.5 * ((k++ + 0.5) / n - 0.5));
    }
    const auto x_of = [&](const TradeRow& row) {
        return row.error_rate() > 0.0 ? 100.0 * row.error_rate() : strip.at(row.setting.engine);
    };
    // Labels: the front, the references and each engine's fastest setting (the CSV names them all).
    std::map<std::string, const TradeRow*> fastest_of;
    for (const TradeRow* row : rows) {
        const TradeRow*& f = fastest_of[row->setting.engine];
        if (!f || row->x_reference > f->x_reference) f = row;
    }

    double slowest = 1e300, fastest = 0.0;
    for (const TradeRow* row : rows)
        slowest = std::min(slowest, r.steady_mrays_per_s(*row)),
        fastest = std::max(fastest, r.steady_mrays_per_s(*row));
    const bool log_y = slowest > 0.0 && fastest / slowest > 10.0;

    const double y_low = log_y ? slowest / 1.6 : 0.0, y_high = log_y ? fastest * 1.6 : fastest * 1.15;
    const double x_low = zero / 2.5, x_high = top * 1.5;

    TradePlot plot;
    std::map<std::string, std::string> points;  // engine -> data
    std::vector<std::string> engines;           // in the order of the rows
    std::string front;
    std::vector<const TradeRow*> front_rows, labelled;
    for (const TradeRow* row : rows) {
        const std::string& engine = row->setting.engine;
        if (!points.count(engine)) engines.push_back(engine);
        points[engine] += number(x_of(*row)) + " " + number(r.steady_mrays_per_s(*row)) + "\n";
        if (row->pareto || is_reference_engine(engine) || fastest_of.at(engine) == row) labelled.push_back(row);
        if (row->pareto) front_rows.push_back(row);
    }
    std::sort(front_rows.begin(), front_rows.end(),
              [](const TradeRow* a, const TradeRow* b) { return a->error_rate() < b->error_rate(); });
    for (const TradeRow* row : front_rows)
        front += number(x_of(*row)) + " " + number(r.steady_mrays_per_s(*row)) + "\n";

    std::string s;
    char head[512];
    std::snprintf(head, sizeof head,
                  "%s (%zu triangles), %s, %dx%d, %zu rays, %d thread%s, best pass of >= %d and >= %g s",
                  r.scene.c_str(), r.triangles, describe_rays(r.mode, r.order, r.lights, r.area_light).c_str(), r.width,
                  r.height, r.rays, r.threads, r.threads == 1 ? "" : "s", r.repeats, r.min_seconds);
    s += "set termoption noenhanced\n";
    s += "set title " + quoted(head) + "\n";
    s += "set xlabel 'mismatches per ray (log scale; 0 = no mismatch, engines side by side)' offset 0,0.3\n";
    s += "set ylabel " + quoted(std::string("Mrays/s at embree16's best pass") + (log_y ? " (log scale)" : "")) + "\n";
    const TradeRow* anchor = r.anchor();
    s += "set y2label " +
         quoted(anchor ? "speed / anchor (" + anchor->setting.engine + ", alternating passes)"
                       : std::string("speed / embree16 (alternating passes)")) +
         "\n";
    s += "set ytics nomirror\n";

    s += "set logscale x\n";
    // The right axis shows the same heights as multiples of the anchor's speed (gnuplot 5.4 cannot
    // link a log axis, so both ranges are set).
    const double reference = anchor && r.steady_mrays_per_s(*anchor) > 0.0 ? r.steady_mrays_per_s(*anchor)
                             : r.reference_mrays_per_s > 0.0               ? r.reference_mrays_per_s
                                                                           : 1.0;
    if (log_y) s += "set logscale y\nset logscale y2\n";
    s += "set yrange [" + number(y_low) + ":" + number(y_high) + "]\n";
    s += "set y2range [" + number(y_low / reference) + ":" + number(y_high / reference) + "]\n";
    if (log_y) {
        s += log_tics("ytics", y_low, y_high);
        s += log_tics("y2tics", y_low / reference, y_high / reference);
    } else {
        s += "set y2tics\n";
    }
    s += "set xrange [" + number(x_low) + ":" + number(x_high) + "]\n";
    std::string tics = "set xtics (\"0\" " + number(zero);
    for (double t = zero * 10.0; t <= top * 1.0001; t *= 10.0) tics += ", " + quoted(percent(t)) + " " + number(t);
    s += tics + ")\n";
    const double gap = zero * std::sqrt(10.0);
    s += "set arrow from " + number(gap) + ", graph 0 to " + number(gap) +
         ", graph 1 nohead dashtype 3 linecolor rgb '#b0b0b0'\n";
    s += "set grid ytics lc rgb '#e0e0e0'\n";
    if (anchor) {
        // The anchor's speed across the whole plot: every setting below it is slower than Embree at its best.
        const double y = r.steady_mrays_per_s(*anchor);
        s += "set arrow from graph 0, first " + number(y) + " to graph 1, first " + number(y) +
             " nohead dashtype 2 linewidth 2 linecolor rgb '#404040'\n";
        char text[160];
        std::snprintf(text, sizeof text, "anchor: %s, the fastest Embree engine (%zu of %zu references on the front)",
                      anchor->setting.engine.c_str(), r.references_on_front(),
                      std::size_t(std::count_if(rows.begin(), rows.end(), [](const TradeRow* row) {
                          return is_reference_engine(row->setting.engine);
                      })));
        s += "set label " + quoted(text) + " at graph 0.99, first " + number(y) +
             " right offset 0,0.6 font ',9' textcolor rgb '#404040'\n";
    }
    s += "set key outside bottom center horizontal box\nset bmargin 7\n";
    s += "plot ";
    std::vector<std::string> parts;
    if (!front.empty()) {
        parts.push_back(
            "'front.dat' using 1:2 with linespoints linewidth 3 pointtype 6 pointsize 3 linecolor rgb '#9edae5' title "
            "'Pareto front'");
        plot.data_files.emplace_back("front.dat", front);
    }
    for (const std::string& e : engines) {
        const Style st = engine_style(e);
        const std::string file = "points-" + e + ".dat";
        plot.data_files.emplace_back(file, points[e]);
        parts.push_back(quoted(file) + " using 1:2 with points pointtype " + std::to_string(st.point) +
                        " pointsize 1.6 linecolor rgb '" + st.colour + "' title " +
                        quoted(e + (is_reference_engine(e) ? " (reference)" : "")));
    }
    // Labels, the front's first: each on the side of its point where it covers the least.
    std::stable_sort(labelled.begin(), labelled.end(),
                     [](const TradeRow* a, const TradeRow* b) { return a->pareto > b->pareto; });
    const report::LabelGeometry geometry{kAreaWidth, kAreaHeight};
    const auto to_area = [&](const TradeRow& row) {
        const double y = r.steady_mrays_per_s(row);
        const double fy = log_y ? std::log(y / y_low) / std::log(y_high / y_low) : (y - y_low) / (y_high - y_low);
        return report::LabelledPoint{kAreaWidth * std::log(x_of(row) / x_low) / std::log(x_high / x_low),
                                     kAreaHeight * fy, 0};
    };
    std::vector<report::LabelledPoint> anchors, markers;
    for (const TradeRow* row : labelled) {
        anchors.push_back(to_area(*row));
        anchors.back().characters = row->setting.label.size();
    }
    for (const TradeRow* row : rows) markers.push_back(to_area(*row));
    const std::vector<report::LabelSide> sides = report::place_labels(anchors, markers, geometry);
    std::string labels[4];
    for (std::size_t i = 0; i < labelled.size(); ++i)
        labels[int(sides[i])] += number(x_of(*labelled[i])) + " " + number(r.steady_mrays_per_s(*labelled[i])) + " " +
                                 data_string(labelled[i]->setting.label) + "\n";
    const char* label_styles[4] = {"left offset char 1,0.5", "left offset char 1,-0.5", "right offset char -1,0.5",
                                   "right offset char -1,-0.5"};
    for (int k = 0; k < 4; ++k) {
        if (labels[k].empty()) continue;
        const std::string file = "labels-" + std::to_string(k) + ".dat";
        plot.data_files.emplace_back(file, labels[k]);
        parts.push_back(quoted(file) + " using 1:2:3 with labels " + label_styles[k] + " font ',8' notitle");
    }
    for (std::size_t i = 0; i < parts.size(); ++i) s += (i ? ", \\\n     " : "") + parts[i];
    s += "\n";
    plot.script = s;
    return plot;
}

void plot_trade(const TradeResult& result, const std::string& png_path) {
    const TradePlot p = trade_plot(result);
    report::plot_with_gnuplot(png_path, p.script, p.data_files);
}

}  // namespace beamtrace::workload
