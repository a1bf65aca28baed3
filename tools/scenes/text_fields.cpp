// Comma-separated numbers and whole numbers from user text, with messages naming the field.
#include "scenes/text_fields.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::scenes {

namespace {

std::string ordinal(std::size_t n) {
    const std::size_t tens = n % 100, ones = n % 10;
    const char* suffix = (tens >= 11 && tens <= 13) ? "th"
                         : ones == 1                ? "st"
                         : ones == 2                ? "nd"
                         : ones == 3                ? "rd"
                                                    : "th";
    return std::to_string(n) + suffix;
}

std::string quoted(std::string_view text) {
    std::string s(1, '"');
    s.append(text);
    s.push_back('"');
    return s;
}

// from_chars refuses a leading '+', which people type; accept one in front of a digit or a dot.
std::string_view skip_plus(std::string_view s) {
    if (s.size() >= 2 && s[0] == '+' && (std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.'))
        s.remove_prefix(1);
    return s;
}

}  // namespace

std::string_view trim(std::string_view text) {
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
    while (!text.empty() && blank(text.front())) text.remove_prefix(1);
    while (!text.empty() && blank(text.back())) text.remove_suffix(1);
    return text;
}

std::vector<float> parse_numbers(std::string_view text, std::span<const std::string_view> field_names,
                                 std::string_view what) {
    std::vector<std::string_view> fields;
    for (std::size_t start = 0;;) {
        const std::size_t comma = text.find(',', start);
        fields.push_back(
            trim(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    std::string names;
    for (std::string_view n : field_names) {
        if (!names.empty()) names.push_back(',');
        names.append(n);
    }
    if (fields.size() != field_names.size())
        throw Error(std::string(what) + ": expected " + std::to_string(field_names.size()) +
                    " comma-separated numbers " + names + ", got " + std::to_string(fields.size()) + " in " +
                    quoted(text));
    std::vector<float> values(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
        const std::string field_label = "field " + std::string(field_names[i]) + " (" + ordinal(i + 1) + ")";
        const std::string_view s = skip_plus(fields[i]);
        float v = 0.0f;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || end != s.data() + s.size() || ec == std::errc::invalid_argument)
            throw Error(std::string(what) + ": " + field_label + " is not a number: " + quoted(fields[i]));
        if (ec == std::errc::result_out_of_range || !std::isfinite(v))
            throw Error(std::string(what) + ": " + field_label + " is not a finite number: " + quoted(fields[i]));
        values[i] = v;
    }
    return values;
}

std::int64_t parse_integer(std::string_view text, std::int64_t lowest, std::int64_t highest, std::string_view what,
                           std::string_view field) {
    const std::string_view s = skip_plus(trim(text));
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    const std::string range = "must be between " + std::to_string(lowest) + " and " + std::to_string(highest);
    if (s.empty() || end != s.data() + s.size() || ec == std::errc::invalid_argument)
        throw Error(std::string(what) + ": " + std::string(field) + " " + quoted(text) + " is not a whole number");
    if (ec == std::errc::result_out_of_range || v < lowest || v > highest)
        throw Error(std::string(what) + ": " + std::string(field) + " " + quoted(text) + " " + range);
    return v;
}

}  // namespace beamtrace::scenes
