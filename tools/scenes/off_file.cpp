// The OFF parser: line by line, every count and index checked before it is used.
#include "scenes/off_file.hpp"

#include <charconv>
#include <cstdio>
#include <cmath>
#include <limits>

#include "beamtrace/error.hpp"

namespace beamtrace::scenes {

namespace {

// The file as lines of whitespace-separated tokens, comments and blank lines skipped.
class OffLines {
public:
    OffLines(std::string_view text, const std::string& name) : text_(text), name_(name) {}

    // The next line holding at least one token; false at the end of the file.
    bool next(std::vector<std::string_view>& tokens) {
        tokens.clear();
        while (tokens.empty() && pos_ < text_.size()) {
            const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
            std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++line_;
            line = line.substr(0, line.find('#'));
            std::size_t i = 0;
            while (i < line.size()) {
                while (i < line.size() && is_space(line[i])) ++i;
                const std::size_t start = i;
                while (i < line.size() && !is_space(line[i])) ++i;
                if (i > start) tokens.push_back(line.substr(start, i - start));
            }
        }
        return !tokens.empty();
    }

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(name_ + " line " + std::to_string(line_) + ": " + what);
    }
    std::size_t bytes_left() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

private:
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
    std::string_view text_;
    const std::string& name_;
    std::size_t pos_ = 0;
    std::size_t line_ = 0;
};

// Printable form of a token for messages (at most 32 characters, control bytes as '?').
std::string shown(std::string_view token) {
    std::string s(token.substr(0, 32));
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    return "'" + s + (token.size() > 32 ? "...'" : "'");
}

bool is_keyword(std::string_view t, bool& unsupported) {
    unsupported = false;
    if (t.size() < 3 || t.substr(t.size() - 3) != "OFF") return false;
    std::string_view p = t.substr(0, t.size() - 3);
    if (p.substr(0, 2) == "ST") p.remove_prefix(2);
    if (!p.empty() && p.front() == 'C') p.remove_prefix(1);
    if (!p.empty() && p.front() == 'N') p.remove_prefix(1);
    if (!p.empty() && p.front() == '4') p.remove_prefix(1), unsupported = true;
    if (!p.empty() && p.front() == 'n') p.remove_prefix(1), unsupported = true;
    return p.empty();
}

std::uint64_t parse_count(OffLines& lines, std::string_view token, const char* what) {
    if (!token.empty() && token.front() == '-') lines.fail(std::string("negative ") + what + " count " + shown(token));
    std::uint64_t v = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec == std::errc::result_out_of_range)
        lines.fail(std::string(what) + " count " + shown(token) + " is too large");
    if (ec != std::errc() || end != token.data() + token.size())
        lines.fail(std::string(what) + " count " + shown(token) + " is not a whole number");
    return v;
}

}  // namespace

bool looks_like_off(std::string_view text) {
    OffLines lines(text, std::string());
    std::vector<std::string_view> tokens;
    bool unsupported = false;
    return lines.next(tokens) && is_keyword(tokens[0], unsupported);
}

MeshArrays parse_off(std::string_view text, const std::string& name) {
    OffLines lines(text, name);
    std::vector<std::string_view> t;
    if (!lines.next(t)) throw Error(name + ": not an OFF file (no keyword OFF and no counts)");
    std::size_t first_count = 0;
    bool unsupported = false;
    if (is_keyword(t[0], unsupported)) {
        if (unsupported) lines.fail("the 4D and nD variants of OFF (" + shown(t[0]) + ") are not supported");
        if (t.size() > 1 && t[1] == "BINARY") lines.fail("binary OFF is not supported");
        if (t.size() > 1) {
            first_count = 1;  // the counts on the keyword's line
        } else if (!lines.next(t)) {
            throw Error(name + ": the file ends before the vertex and face counts");
        }
    } else if (!((t[0].front() >= '0' && t[0].front() <= '9') || t[0].front() == '-')) {
        lines.fail("not an OFF file: it must start with the keyword OFF or the vertex, face and edge counts, not " +
                   shown(t[0]));
    }
    if (t.size() < first_count + 2) lines.fail("expected the vertex, face and edge counts");
    const std::uint64_t nv = parse_count(lines, t[first_count], "vertex");
    const std::uint64_t nf = parse_count(lines, t[first_count + 1], "face");
    if (t.size() > first_count + 2) parse_count(lines, t[first_count + 2], "edge");
    // A vertex line needs at least 6 bytes ("0 0 0\n"), a face line at least 2: counts beyond what
    // the rest of the file can hold are refused before anything is allocated for them.
    const std::uint64_t left = lines.bytes_left();
    if (nv > left / 6)
        lines.fail("declares " + std::to_string(nv) + " vertices but only " + std::to_string(left) +
                   " bytes follow (at least 6 per vertex)");
    if (nf > left / 2)
        lines.fail("declares " + std::to_string(nf) + " faces but only " + std::to_string(left) +
                   " bytes follow (at least 2 per face)");
    if (nv > std::numeric_limits<std::uint32_t>::max()) lines.fail("more than 2^32 vertices");

    MeshArrays mesh;
    mesh.vertices.reserve(nv);
    for (std::uint64_t v = 0; v < nv; ++v) {
        if (!lines.next(t))
            throw Error(name + ": the file ends after " + std::to_string(v) + " of " + std::to_string(nv) +
                        " vertices");
        if (t.size() < 3) lines.fail("vertex " + std::to_string(v) + " has fewer than 3 coordinates");
        Float3 p;
        for (int k = 0; k < 3; ++k) {
            // Read as double, then rounded to float: tiny values become 0 or denormals, huge ones
            // (beyond float) are refused like infinities.
            double value = 0.0;
            const auto [end, ec] = std::from_chars(t[k].data(), t[k].data() + t[k].size(), value);
            if (ec == std::errc::result_out_of_range)
                value = std::numeric_limits<double>::infinity();
            else if (ec != std::errc() || end != t[k].data() + t[k].size())
                lines.fail("vertex " + std::to_string(v) + ": coordinate " + shown(t[k]) + " is not a number");
            p[k] = float(value);
            if (!std::isfinite(p[k]))
                lines.fail("vertex " + std::to_string(v) +
                           " has a NaN or infinite coordinate, or one beyond float's range: " + shown(t[k]));
        }
        mesh.vertices.push_back(p);
    }
    std::vector<std::uint32_t> corners;
    for (std::uint64_t f = 0; f < nf; ++f) {
        if (!lines.next(t))
            throw Error(name + ": the file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
        const std::uint64_t n = parse_count(lines, t[0], "face corner");
        if (n >= t.size())  // (not n + 1 > size: a count of 2^64 - 1 would wrap to 0)
            lines.fail("face " + std::to_string(f) + " has " + std::to_string(t.size() - 1) + " of its " +
                       std::to_string(n) + " vertex indices");
        corners.clear();
        for (std::uint64_t k = 1; k <= n; ++k) {
            const std::string_view tok = t[k];
            std::int64_t index = 0;
            const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), index);
            if (ec != std::errc() || end != tok.data() + tok.size())
                lines.fail("face " + std::to_string(f) + ": vertex index " + shown(tok) + " is not a whole number");
            if (index < 0) lines.fail("face " + std::to_string(f) + " has a negative vertex index " + shown(tok));
            if (std::uint64_t(index) >= nv)
                lines.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(index) +
                           ", out of range (" + std::to_string(nv) + " vertices)");
            corners.push_back(std::uint32_t(index));
        }
        for (std::size_t k = 2; k < corners.size(); ++k)  // polygons as fans; points and lines dropped
            mesh.indices.insert(mesh.indices.end(), {corners[0], corners[k - 1], corners[k]});
    }
    if (mesh.indices.empty()) throw Error(name + " contains no triangles");
    return mesh;
}

std::string format_off(const Scene& scene) {
    const auto vertices = scene.vertices();
    const auto indices = scene.indices();
    std::string out = "OFF\n" + std::to_string(vertices.size()) + " " + std::to_string(indices.size() / 3) + " 0\n";
    out.reserve(out.size() + vertices.size() * 40 + indices.size() * 9);
    char line[160];
    for (const Float3& p : vertices) {
        std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
        out += line;
    }
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        std::snprintf(line, sizeof line, "3 %u %u %u\n", unsigned(indices[t]), unsigned(indices[t + 1]),
                      unsigned(indices[t + 2]));
        out += line;
    }
    return out;
}

}  // namespace beamtrace::scenes
