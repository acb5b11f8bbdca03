// A pass over an OBJ file before Assimp sees it. It rewrites the text into the shape Assimp
// 5.2 reads reliably and rejects what Assimp would silently get wrong:
//   - indented lines: Assimp skips them (an indented 'f' or 'vt' line is lost), so leading
//     white space is removed; so are '#' comments after the data of v/vt/vn/f lines (Assimp
//     fails on them) and '\' line continuations (joined);
//   - a texture-coordinate or normal index out of range: Assimp drops the whole attribute;
//   - colours on some 'v' lines only: Assimp shifts them onto the wrong vertices;
//   - a 'v' line with other than 3, 4 or 6 numbers: Assimp skips it, renumbering the rest;
//   - a weight after x y z (4 numbers) is dropped, and the data lines are rewritten with one
//     space between tokens (Assimp splits on spaces and tabs only, so a vertical tab or a
//     form feed between numbers made it lose vertices);
//   - statements other than v, vt, vn, f, l, p, g, o, s, usemtl and mtllib: Assimp picks a
//     statement by its first letters ("glb1 2 3" is a group), so they become empty lines;
//   - non-numeric values, index 0 or vertex indices out of range (clear messages).
#pragma once

#include <string>
#include <string_view>

#include <polder/result.hpp>

namespace polder::mesh_io::detail {

// The normalised text, or InvalidData with a message that does not name the file.
Result<std::string> normalizeObj(std::string_view bytes);

}  // namespace polder::mesh_io::detail
