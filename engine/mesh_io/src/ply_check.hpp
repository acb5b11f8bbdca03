// A structural walk over a whole PLY file, run before Assimp sees it. Assimp 5.2's PLY reader
// hangs on an ascii file cut inside a vertex, reads past its buffer on a binary file cut inside
// the face list, and silently invents faces when the face list is short; the walk rejects such
// files with "truncated" (or "malformed") instead. It decodes no values beyond list lengths.
#pragma once

#include <string_view>

#include <polder/result.hpp>

namespace polder::mesh_io::detail {

// InvalidData with a message that does not name the file (the caller prefixes it).
Status checkPlyStructure(std::string_view bytes);

}  // namespace polder::mesh_io::detail
