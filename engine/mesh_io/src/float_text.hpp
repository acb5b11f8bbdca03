// Decimal text for floats that Assimp reads back exactly.
//
// Assimp 5.2 parses OBJ and ascii PLY numbers with its own fast_atoreal_move, which is not
// correctly rounded (float arithmetic for the integer and exponent parts: "3.4028235e38"
// reads as 3.40282326e38). The shortest round-trip text works for most values; for the
// rest a mantissa and exponent are searched that Assimp's parser turns into the same float.
#pragma once

#include <string>

namespace polder::mesh_io::detail {

// Appends text for a finite float that Assimp reads back bit for bit (for every float tried
// so far; a value with no such text gets its shortest correctly-rounded text).
void appendFloat(std::string& out, float value);

}  // namespace polder::mesh_io::detail
