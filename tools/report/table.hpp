#pragma once
// A plain-text table with aligned columns, as text for terminals or as Markdown.
//
// Columns whose body cells all look like numbers (with an optional short unit such as "%", "x" or
// " ms") are right-aligned, the others left-aligned. Widths count UTF-8 characters, not bytes.
#include <cstddef>
#include <string>
#include <vector>

namespace beamtrace::report {

class Table {
public:
    // Throws beamtrace::Error if there are no headers.
    explicit Table(std::vector<std::string> headers);

    // Throws beamtrace::Error unless the row has exactly one cell per header.
    void add_row(std::vector<std::string> cells);

    // Columns separated by two spaces, a dashed rule under the headers, no trailing spaces; every
    // line ends with '\n'.
    std::string text() const;
    // A GitHub-flavoured Markdown table ('|' in cells escaped), alignment marked in the rule.
    std::string markdown() const;

    std::size_t columns() const { return headers_.size(); }
    std::size_t rows() const { return rows_.size(); }

private:
    std::vector<bool> right_aligned() const;
    std::vector<std::size_t> widths(bool escape_pipes) const;

    std::vector<std::string> headers_;
    std::vector<std::vector<std::string>> rows_;
};

// Whether a cell reads as a number with an optional short unit ("12", "-3.5e4", "42%", "3.1 s").
bool looks_numeric(const std::string& cell);
// Characters in a UTF-8 string (code points).
std::size_t display_width(const std::string& text);
// A cell of a number with `digits` digits after the point ("%.*f").
std::string fixed(double value, int digits);

}  // namespace beamtrace::report
