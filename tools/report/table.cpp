// Aligned plain-text and Markdown tables.
#include "report/table.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>

#include "beamtrace/error.hpp"

namespace beamtrace::report {

namespace {

std::string escape_pipes(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '|') out += '\\';
        out += c;
    }
    return out;
}

void pad(std::string& line, const std::string& cell, std::size_t width, bool right) {
    const std::size_t w = display_width(cell);
    const std::string fill(width > w ? width - w : 0, ' ');
    line += right ? fill + cell : cell + fill;
}

void trim_right(std::string& line) {
    while (!line.empty() && line.back() == ' ') line.pop_back();
}

}  // namespace

std::size_t display_width(const std::string& text) {
    std::size_t n = 0;
    for (unsigned char c : text)
        if ((c & 0xC0) != 0x80) ++n;  // count every byte that is not a UTF-8 continuation byte
    return n;
}

bool looks_numeric(const std::string& cell) {
    if (cell.empty()) return false;
    const char* begin = cell.c_str();
    if (!std::isdigit(static_cast<unsigned char>(begin[0])) && begin[0] != '-' && begin[0] != '+' && begin[0] != '.')
        return false;
    char* end = nullptr;
    std::strtod(begin, &end);
    if (end == begin) return false;
    const std::string unit(end);
    if (display_width(unit) > 4) return false;
    for (unsigned char c : unit)
        if (std::isdigit(c)) return false;
    return true;
}

Table::Table(std::vector<std::string> headers) : headers_(std::move(headers)) {
    if (headers_.empty()) throw Error("table: no columns");
}

void Table::add_row(std::vector<std::string> cells) {
    if (cells.size() != headers_.size())
        throw Error("table: row " + std::to_string(rows_.size()) + " has " + std::to_string(cells.size()) +
                    " cells, the table has " + std::to_string(headers_.size()) + " columns");
    rows_.push_back(std::move(cells));
}

std::vector<bool> Table::right_aligned() const {
    std::vector<bool> right(headers_.size(), !rows_.empty());
    for (const auto& row : rows_)
        for (std::size_t c = 0; c < row.size(); ++c)
            if (!row[c].empty() && !looks_numeric(row[c])) right[c] = false;
    return right;
}

std::vector<std::size_t> Table::widths(bool escape) const {
    std::vector<std::size_t> w(headers_.size(), 0);
    auto grow = [&](const std::vector<std::string>& cells) {
        for (std::size_t c = 0; c < cells.size(); ++c)
            w[c] = std::max(w[c], display_width(escape ? escape_pipes(cells[c]) : cells[c]));
    };
    grow(headers_);
    for (const auto& row : rows_) grow(row);
    return w;
}

std::string Table::text() const {
    const auto w = widths(false);
    const auto right = right_aligned();
    std::string out;
    auto emit = [&](const std::vector<std::string>& cells) {
        std::string line;
        for (std::size_t c = 0; c < cells.size(); ++c) {
            if (c > 0) line += "  ";
            pad(line, cells[c], w[c], right[c]);
        }
        trim_right(line);
        out += line + '\n';
    };
    emit(headers_);
    std::vector<std::string> rule;
    for (std::size_t width : w) rule.push_back(std::string(width, '-'));
    emit(rule);
    for (const auto& row : rows_) emit(row);
    return out;
}

std::string Table::markdown() const {
    auto w = widths(true);
    for (auto& width : w) width = std::max<std::size_t>(width, 3);  // room for the rule's dashes
    const auto right = right_aligned();
    std::string out;
    auto emit = [&](const std::vector<std::string>& cells) {
        std::string line = "|";
        for (std::size_t c = 0; c < cells.size(); ++c) {
            line += ' ';
            pad(line, escape_pipes(cells[c]), w[c], right[c]);
            line += " |";
        }
        out += line + '\n';
    };
    emit(headers_);
    std::string rule = "|";
    for (std::size_t c = 0; c < w.size(); ++c) {
        const std::size_t dashes = w[c];
        rule += right[c] ? ' ' + std::string(dashes - 1, '-') + ": |" : " :" + std::string(dashes - 1, '-') + " |";
    }
    out += rule + '\n';
    for (const auto& row : rows_) emit(row);
    return out;
}

std::string fixed(double value, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, value);
    return buf;
}

}  // namespace beamtrace::report
