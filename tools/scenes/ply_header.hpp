#pragma once
// A check of a PLY file's header before Assimp reads it: the header must be well formed and its
// element counts must fit in the bytes that follow it (Assimp would otherwise size its arrays by a
// hostile count, or loop over billions of missing elements).
#include <string>
#include <string_view>

namespace beamtrace::scenes {

// Whether the bytes start with the PLY magic line ("ply").
bool looks_like_ply(std::string_view bytes);

// Throws beamtrace::Error naming the file and the problem for: no "format" line or an unknown
// format, an element count that is not a whole number, a property of an unknown type, no
// "end_header", and elements that need more bytes than follow the header (at least 2 bytes per
// ASCII value, the type's size per binary one; at least one byte per element in any case).
void check_ply_header(std::string_view bytes, const std::string& name);

}  // namespace beamtrace::scenes
