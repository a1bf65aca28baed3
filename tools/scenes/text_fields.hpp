#pragma once
// Parsing of the small comma-separated texts users type (--camera, --light, scene specs), with error
// messages that name the offending field. Shared by camera.cpp and scene_source.cpp.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace beamtrace::scenes {

// Splits `text` at commas into exactly field_names.size() finite numbers (surrounding blanks allowed).
// Throws beamtrace::Error starting with `what`, e.g.
//   camera: expected 7 comma-separated numbers EX,EY,EZ,AX,AY,AZ,FOVY, got 5 in "1,2,3,4,5"
//   camera: field AY (5th) is not a number: "abc"
std::vector<float> parse_numbers(std::string_view text, std::span<const std::string_view> field_names,
                                 std::string_view what);

// A whole decimal number in [lowest, highest] (blanks around it allowed). Throws beamtrace::Error
// "<what>: <field> "<text>" is not a whole number" or "... must be between lowest and highest".
std::int64_t parse_integer(std::string_view text, std::int64_t lowest, std::int64_t highest, std::string_view what,
                           std::string_view field);

// Removes leading and trailing blanks.
std::string_view trim(std::string_view text);

}  // namespace beamtrace::scenes
