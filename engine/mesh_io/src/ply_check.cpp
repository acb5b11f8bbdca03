#include "ply_check.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "text_scan.hpp"

namespace polder::mesh_io::detail {
namespace {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
  std::string name;
  int valueSize = 0;  // bytes of a scalar, or of each list entry
  int countSize = 0;  // bytes of the list length; 0 for a scalar
  bool countSigned = false;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t bodyOffset = 0;
};

Error malformed(const std::string& message) { return makeError(ErrorKind::InvalidData, "malformed PLY: " + message); }
Error truncated(const std::string& message) { return makeError(ErrorKind::InvalidData, "truncated PLY: " + message); }

// Byte size of a PLY scalar type name (both spellings), 0 if unknown.
int typeSize(std::string_view type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

bool isSignedInteger(std::string_view type) {
  return type == "char" || type == "int8" || type == "short" || type == "int16" || type == "int" || type == "int32";
}
bool isInteger(std::string_view type) {
  return isSignedInteger(type) || type == "uchar" || type == "uint8" || type == "ushort" || type == "uint16" ||
         type == "uint" || type == "uint32";
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Where a line starting at `start` ends (its '\n' or the end) and where the next one starts.
std::pair<std::size_t, std::size_t> lineAt(std::string_view bytes, std::size_t start) {
  const std::size_t newline = bytes.find('\n', start);
  if (newline == std::string_view::npos) return {bytes.size(), bytes.size()};
  return {newline, newline + 1};
}

Result<PlyHeader> parseHeader(std::string_view bytes) {
  PlyHeader header;
  std::vector<std::string_view> tokens;
  bool sawFormat = false;
  std::size_t position = 0;
  for (int lineNumber = 1;; ++lineNumber) {
    if (position >= bytes.size())
      return truncated("the header has no end_header line (the file ends at header line " + std::to_string(lineNumber) +
                       ")");
    const auto [lineEnd, next] = lineAt(bytes, position);
    splitTokens(bytes.substr(position, lineEnd - position), tokens);
    position = next;
    const std::string where = "header line " + std::to_string(lineNumber) + ": ";
    // A last line without its newline was cut, unless it completes the header.
    if (lineEnd == bytes.size() && !(tokens.size() == 1 && tokens[0] == "end_header"))
      return truncated("the file ends inside header line " + std::to_string(lineNumber));
    if (lineNumber == 1) {
      if (tokens.size() != 1 || lower(tokens[0]) != "ply") return malformed("the file does not start with 'ply'");
      continue;
    }
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") {
      if (!sawFormat) return malformed("the header has no format line");
      header.bodyOffset = next;
      return header;
    }
    if (keyword == "format") {
      if (tokens.size() != 3) return malformed(where + "expected 'format <type> 1.0'");
      if (tokens[1] == "ascii")
        header.format = PlyFormat::Ascii;
      else if (tokens[1] == "binary_little_endian")
        header.format = PlyFormat::BinaryLittleEndian;
      else if (tokens[1] == "binary_big_endian")
        header.format = PlyFormat::BinaryBigEndian;
      else
        return malformed(where + "unknown format " + quoted(tokens[1]));
      sawFormat = true;
    } else if (keyword == "element") {
      if (tokens.size() != 3) return malformed(where + "expected 'element <name> <count>'");
      const auto count = parseInteger(tokens[2]);
      if (!count || *count < 0) return malformed(where + "element count " + quoted(tokens[2]) + " is not a count");
      header.elements.push_back({std::string(tokens[1]), std::uint64_t(*count), {}});
    } else if (keyword == "property") {
      if (header.elements.empty()) return malformed(where + "a property before any element");
      PlyProperty property;
      if (tokens.size() == 3) {
        property.valueSize = typeSize(tokens[1]);
        if (property.valueSize == 0) return malformed(where + "unknown property type " + quoted(tokens[1]));
        property.name = tokens[2];
      } else if (tokens.size() == 5 && tokens[1] == "list") {
        if (!isInteger(tokens[2]))
          return malformed(where + "list length type " + quoted(tokens[2]) + " is not an integer type");
        property.countSize = typeSize(tokens[2]);
        property.countSigned = isSignedInteger(tokens[2]);
        property.valueSize = typeSize(tokens[3]);
        if (property.valueSize == 0) return malformed(where + "unknown list entry type " + quoted(tokens[3]));
        property.name = tokens[4];
      } else {
        return malformed(where + "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
      }
      header.elements.back().properties.push_back(std::move(property));
    } else {
      return malformed(where + "unexpected keyword " + quoted(keyword));
    }
  }
}

std::string itemName(const PlyElement& element, std::uint64_t item) {
  return element.name + " " + std::to_string(item + 1) + " of " + std::to_string(element.count);
}

// Reads an unsigned or two's-complement list length of 1, 2 or 4 bytes.
std::int64_t readCount(const unsigned char* bytes, int size, bool bigEndian, bool isSigned) {
  std::uint64_t value = 0;
  for (int i = 0; i < size; ++i) value |= std::uint64_t(bytes[bigEndian ? size - 1 - i : i]) << (8 * i);
  if (isSigned && size < 8 && (value >> (8 * size - 1)) != 0)
    return std::int64_t(value) - (std::int64_t(1) << (8 * size));
  return std::int64_t(value);
}

Status walkBinary(std::string_view bytes, const PlyHeader& header) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const bool bigEndian = header.format == PlyFormat::BinaryBigEndian;
  std::uint64_t position = header.bodyOffset;
  const std::uint64_t size = bytes.size();
  for (const PlyElement& element : header.elements) {
    const bool fixedSize = std::none_of(element.properties.begin(), element.properties.end(),
                                        [](const PlyProperty& p) { return p.countSize != 0; });
    if (fixedSize) {
      std::uint64_t stride = 0;
      for (const PlyProperty& property : element.properties) stride += std::uint64_t(property.valueSize);
      if (stride == 0) continue;
      const std::uint64_t available = (size - position) / stride;
      if (available < element.count) return truncated("the data ends in " + itemName(element, available));
      position += element.count * stride;
      continue;
    }
    for (std::uint64_t item = 0; item < element.count; ++item) {
      for (const PlyProperty& property : element.properties) {
        std::uint64_t length = std::uint64_t(property.valueSize);
        if (property.countSize != 0) {
          if (size - position < std::uint64_t(property.countSize))
            return truncated("the data ends in " + itemName(element, item));
          const std::int64_t count = readCount(data + position, property.countSize, bigEndian, property.countSigned);
          if (count < 0)
            return malformed(itemName(element, item) + " has a negative list length " + std::to_string(count));
          position += std::uint64_t(property.countSize);
          length = std::uint64_t(count) * std::uint64_t(property.valueSize);
        }
        if (size - position < length) return truncated("the data ends in " + itemName(element, item));
        position += length;
      }
    }
  }
  return {};
}

Status walkAscii(std::string_view bytes, const PlyHeader& header) {
  std::vector<std::string_view> tokens;
  std::size_t position = header.bodyOffset;
  // Whether only white space follows `from`: a short line there means the file was cut.
  const auto onlyBlankAfter = [&](std::size_t from) {
    return std::all_of(bytes.begin() + std::ptrdiff_t(from), bytes.end(),
                       [](char c) { return isBlank(c) || c == '\n'; });
  };
  for (const PlyElement& element : header.elements) {
    // Assimp reads one item per line (skipping blank lines); items spread over several lines
    // or sharing one would be misread, so the walk insists on that layout too.
    if (element.properties.empty()) continue;
    for (std::uint64_t item = 0; item < element.count; ++item) {
      do {
        if (position >= bytes.size()) return truncated("the data ends before " + itemName(element, item));
        const auto [lineEnd, next] = lineAt(bytes, position);
        splitTokens(bytes.substr(position, lineEnd - position), tokens);
        position = next;
      } while (tokens.empty());
      std::size_t used = 0;
      for (const PlyProperty& property : element.properties) {
        std::size_t needed = 1;
        if (property.countSize != 0 && used < tokens.size()) {
          const auto count = parseInteger(tokens[used]);
          if (!count || *count < 0)
            return malformed(itemName(element, item) + ": list length " + quoted(tokens[used]) + " is not a count");
          ++used;
          needed = std::size_t(std::min<std::int64_t>(*count, std::int64_t(tokens.size()) + 1));
        }
        if (used + needed > tokens.size()) {
          if (onlyBlankAfter(position)) return truncated("the data ends in " + itemName(element, item));
          return malformed(itemName(element, item) + " has too few values on its line");
        }
        for (std::size_t k = 0; k < needed; ++k, ++used)
          if (!isNumber(tokens[used]))
            return malformed(itemName(element, item) + ": " + quoted(tokens[used]) + " is not a number");
      }
      if (used != tokens.size())
        return malformed(itemName(element, item) + " has more values on its line than its properties");
    }
  }
  return {};
}

}  // namespace

Status checkPlyStructure(std::string_view bytes) {
  Result<PlyHeader> header = parseHeader(bytes);
  if (!header) return header.error();
  return header->format == PlyFormat::Ascii ? walkAscii(bytes, *header) : walkBinary(bytes, *header);
}

}  // namespace polder::mesh_io::detail
