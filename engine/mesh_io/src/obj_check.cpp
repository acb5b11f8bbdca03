#include "obj_check.hpp"

#include <cstdint>
#include <vector>

#include "text_scan.hpp"

namespace polder::mesh_io::detail {
namespace {

Error malformed(std::size_t lineNumber, const std::string& message) {
  return makeError(ErrorKind::InvalidData, "line " + std::to_string(lineNumber) + ": " + message);
}

// One kind of indexed data (v, vt or vn): how many were defined so far and the largest
// positive index a face used (OBJ allows positive references to data defined later).
struct IndexedData {
  const char* what = "";
  std::int64_t defined = 0;
  std::int64_t largestReference = 0;
  std::size_t largestReferenceLine = 0;

  // Checks one index of a face corner; negative indices count back from the current end.
  Status reference(std::string_view token, std::size_t lineNumber) {
    const auto index = parseInteger(token);
    if (!index) return malformed(lineNumber, quoted(token) + " is not a " + std::string(what) + " index");
    if (*index == 0) return malformed(lineNumber, std::string(what) + " index 0 (OBJ counts from 1)");
    if (*index < 0) {
      if (-*index > defined)
        return malformed(lineNumber, std::string(what) + " index " + std::to_string(*index) +
                                         " reaches before the first of " + std::to_string(defined));
    } else if (*index > largestReference) {
      largestReference = *index;
      largestReferenceLine = lineNumber;
    }
    return {};
  }

  Status checkLargest() const {
    if (largestReference > defined)
      return malformed(largestReferenceLine, "a face refers to " + std::string(what) + " " +
                                                 std::to_string(largestReference) + " of " + std::to_string(defined));
    return {};
  }
};

Status checkNumbers(const std::vector<std::string_view>& tokens, std::size_t lineNumber) {
  for (std::size_t i = 1; i < tokens.size(); ++i)
    if (!isNumber(tokens[i])) return malformed(lineNumber, quoted(tokens[i]) + " is not a number");
  return {};
}

// Assimp picks a line's statement by its first letter or two, so "glb1 2 3" reads as a
// group and "vp 0.5" as a vertex; statements we do not read (free-form geometry, parameter
// vertices, comments, any unknown word) become empty lines and Assimp sees only these.
bool passesToAssimp(std::string_view keyword) {
  for (const std::string_view known : {"v", "vt", "vn", "f", "l", "p", "g", "o", "s", "usemtl", "mtllib"})
    if (keyword == known) return true;
  return false;
}

}  // namespace

Result<std::string> normalizeObj(std::string_view bytes) {
  std::string text;
  text.reserve(bytes.size());
  IndexedData positions{"vertex"}, uvs{"texture coordinate"}, normals{"normal"};
  std::size_t faceLines = 0;
  std::size_t colouredLine = 0, plainLine = 0;  // a 'v' line with and one without colour
  std::vector<std::string_view> tokens;
  std::string logical;
  std::size_t position = 0, lineNumber = 0;
  while (position < bytes.size()) {
    // One logical line: physical lines joined where they end in a backslash.
    const std::size_t firstLine = lineNumber + 1;
    logical.clear();
    for (;;) {
      ++lineNumber;
      std::size_t end = bytes.find('\n', position);
      const std::size_t next = end == std::string_view::npos ? bytes.size() : end + 1;
      if (end == std::string_view::npos) end = bytes.size();
      std::string_view line = bytes.substr(position, end - position);
      position = next;
      while (!line.empty() && isBlank(line.back())) line.remove_suffix(1);
      if (!line.empty() && line.back() == '\\' && position < bytes.size()) {
        line.remove_suffix(1);
        logical.append(line);
        logical += ' ';
        continue;
      }
      logical.append(line);
      break;
    }
    std::string_view line = logical;
    while (!line.empty() && isBlank(line.front())) line.remove_prefix(1);
    splitTokens(line, tokens);
    if (tokens.empty()) {
      text += '\n';
      continue;
    }
    const std::string_view keyword = tokens[0];
    if (!passesToAssimp(keyword)) {
      text += '\n';  // keeps Assimp's line numbers
      continue;
    }
    const bool isData = keyword == "v" || keyword == "vt" || keyword == "vn" || keyword == "f";
    if (isData) {
      // Data lines lose trailing comments; everything else passes through unchanged.
      const std::size_t comment = line.find('#');
      if (comment != std::string_view::npos) {
        line = line.substr(0, comment);
        splitTokens(line, tokens);
      }
    }
    if (keyword == "v") {
      if (Status numbers = checkNumbers(tokens, firstLine); !numbers) return numbers.error();
      const std::size_t count = tokens.size() - 1;
      if (count != 3 && count != 4 && count != 6)
        return malformed(firstLine,
                         "a vertex needs 3, 4 (x y z w) or 6 (x y z r g b) numbers, not " + std::to_string(count));
      (count == 6 ? colouredLine : plainLine) = firstLine;
      if (colouredLine != 0 && plainLine != 0)
        return malformed(firstLine, "vertex colours on some 'v' lines only (line " + std::to_string(colouredLine) +
                                        " has them, line " + std::to_string(plainLine) + " does not)");
      ++positions.defined;
      if (count == 4) tokens.pop_back();  // w weighs rational curves only: a polygon's vertex is x y z
    } else if (keyword == "vt") {
      if (Status numbers = checkNumbers(tokens, firstLine); !numbers) return numbers.error();
      if (tokens.size() != 3 && tokens.size() != 4)
        return malformed(firstLine,
                         "a texture coordinate needs 2 or 3 numbers, not " + std::to_string(tokens.size() - 1));
      ++uvs.defined;
    } else if (keyword == "vn") {
      if (Status numbers = checkNumbers(tokens, firstLine); !numbers) return numbers.error();
      if (tokens.size() != 4)
        return malformed(firstLine, "a normal needs 3 numbers, not " + std::to_string(tokens.size() - 1));
      ++normals.defined;
    } else if (keyword == "f") {
      ++faceLines;
      for (std::size_t i = 1; i < tokens.size(); ++i) {
        // v, v/vt, v//vn or v/vt/vn
        std::string_view corner = tokens[i];
        std::string_view parts[3];
        int partCount = 0;
        while (partCount < 3) {
          const std::size_t slash = corner.find('/');
          parts[partCount++] = corner.substr(0, slash);
          if (slash == std::string_view::npos) break;
          corner.remove_prefix(slash + 1);
          if (partCount == 3)
            return malformed(firstLine, "face corner " + quoted(tokens[i]) + " has more than three parts");
        }
        if (Status v = positions.reference(parts[0], firstLine); !v) return v.error();
        if (partCount >= 2 && !(partCount == 3 && parts[1].empty()))
          if (Status vt = uvs.reference(parts[1], firstLine); !vt) return vt.error();
        if (partCount == 3)
          if (Status vn = normals.reference(parts[2], firstLine); !vn) return vn.error();
      }
    }
    if (isData) {  // one space between tokens: Assimp splits on spaces and tabs only
      for (std::size_t i = 0; i < tokens.size(); ++i) (i ? text += ' ' : text).append(tokens[i]);
    } else {
      text.append(line);
    }
    text += '\n';
  }
  for (const IndexedData* data : {&positions, &uvs, &normals})
    if (Status largest = data->checkLargest(); !largest) return largest.error();
  if (faceLines == 0) return makeError(ErrorKind::InvalidData, "no triangles (no 'f' statement)");
  return text;
}

}  // namespace polder::mesh_io::detail
