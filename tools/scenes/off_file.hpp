#pragma once
// OFF files (Geomview's Object File Format) read by our own parser rather than Assimp's, whose OFF
// reader trusts the file: it accepts vertex indices out of range and counts larger than the file.
// Every problem is one beamtrace::Error naming the file, the line and what is wrong.
#include <string>
#include <string_view>

#include "beamtrace/scene.hpp"
#include "scenes/mesh_arrays.hpp"

namespace beamtrace::scenes {

// The text of an OFF file: an optional keyword line ("OFF", or with the prefixes ST, C, N of the
// per-vertex extras: "COFF", "NOFF", "STCNOFF", ...), the counts "vertices faces [edges]", one
// vertex per line (x y z, anything after ignored), one face per line ("n i0 .. i(n-1)", colours
// after ignored). '#' starts a comment. Polygons become triangle fans; faces of fewer than three
// corners (points, lines) are dropped. Throws for: no OFF keyword or counts (binary garbage), the 4D
// and nD variants, binary OFF, counts that are not integers, negative, or larger than the file can
// hold, a missing or non-numeric coordinate, a NaN or infinite one, a vertex index that is not an
// integer, negative, or not below the vertex count, a file that ends early, no triangle at all.
MeshArrays parse_off(std::string_view text, const std::string& name);

// Whether the text starts (after blank lines and comments) with an OFF keyword: such files go to
// parse_off whatever their extension, so that Assimp never reads one.
bool looks_like_off(std::string_view text);

// The scene as OFF text: its vertices with 9 significant digits (parse_off reads back the same
// floats) and one triangle per face, in the scene's order (so triangle ids stay the same).
std::string format_off(const Scene& scene);

}  // namespace beamtrace::scenes
