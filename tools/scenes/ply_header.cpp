// The PLY header check: elements, properties and the least number of bytes each element takes.
#include "scenes/ply_header.hpp"

#include <charconv>
#include <cstdint>
#include <vector>

#include "beamtrace/error.hpp"

namespace beamtrace::scenes {

namespace {

// Size in bytes of a PLY scalar type; 0 if the name is no type.
int type_size(std::string_view t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::uint64_t least_bytes = 0;  // per element
};

}  // namespace

bool looks_like_ply(std::string_view bytes) { return bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n"; }

void check_ply_header(std::string_view bytes, const std::string& name) {
    auto fail = [&](const std::string& what) -> void { throw Error(name + ": PLY header: " + what); };
    if (!looks_like_ply(bytes)) fail("the file does not start with the line \"ply\"");
    std::size_t pos = bytes.find('\n') + 1;
    bool ascii = false, have_format = false, ended = false;
    std::vector<Element> elements;
    while (pos < bytes.size()) {
        const std::size_t end = std::min(bytes.find('\n', pos), bytes.size());
        const std::vector<std::string_view> t = split(bytes.substr(pos, end - pos));
        pos = end + 1;
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
        if (t[0] == "end_header") {
            ended = true;
            break;
        }
        if (t[0] == "format") {
            if (t.size() < 2 || (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian"))
                fail("unknown format (expected ascii, binary_little_endian or binary_big_endian)");
            ascii = t[1] == "ascii";
            have_format = true;
        } else if (t[0] == "element") {
            if (t.size() < 3) fail("an element line needs a name and a count");
            Element e;
            e.name = std::string(t[1].substr(0, 40));
            const auto [p, ec] = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
            if (ec != std::errc() || p != t[2].data() + t[2].size())
                fail("the count of element '" + e.name + "' is not a whole number");
            elements.push_back(e);
        } else if (t[0] == "property") {
            if (elements.empty()) fail("a property before any element");
            std::uint64_t bytes_each = 0;
            if (t.size() >= 2 && t[1] == "list") {
                if (t.size() < 5 || type_size(t[2]) == 0 || type_size(t[3]) == 0)
                    fail("a list property needs a count type, an item type and a name");
                bytes_each = ascii ? 2 : std::uint64_t(type_size(t[2]));  // an empty list: its count alone
            } else {
                if (t.size() < 3 || type_size(t[1]) == 0) fail("a property needs a known type and a name");
                bytes_each = ascii ? 2 : std::uint64_t(type_size(t[1]));
            }
            elements.back().least_bytes += bytes_each;
        } else {
            fail("unknown header line starting with '" + std::string(t[0].substr(0, 32)) + "'");
        }
    }
    if (!ended) fail("no end_header line");
    if (!have_format) fail("no format line");
    // One byte of slack: the last ASCII line may end without a newline.
    const std::uint64_t left = (pos < bytes.size() ? bytes.size() - pos : 0) + (ascii ? 1 : 0);
    std::uint64_t needed = 0;
    for (const Element& e : elements) {
        const std::uint64_t each = e.least_bytes > 0 ? e.least_bytes : 1;
        if (e.count > left / each || needed + e.count * each > left)
            fail("it declares " + std::to_string(e.count) + " '" + e.name + "' elements (at least " +
                 std::to_string(each) + " bytes each) but only " +
                 std::to_string(bytes.size() - std::min(pos, bytes.size())) + " bytes follow the header");
        needed += e.count * each;
    }
}

}  // namespace beamtrace::scenes
