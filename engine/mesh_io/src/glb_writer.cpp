// glbBytes (glb_writer.hpp): the JSON chunk by hand, the binary chunk little-endian.
#include "glb_writer.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "float_text.hpp"
#include "little_endian.hpp"

namespace polder::mesh_io::detail {
namespace {

constexpr std::uint32_t kMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kBinChunk = 0x004E4942;   // "BIN\0"
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

void appendFloatList(std::string& json, const float* values, int count) {
  json += '[';
  for (int k = 0; k < count; ++k) {
    if (k > 0) json += ',';
    appendFloat(json, values[k]);
  }
  json += ']';
}

// One attribute or the indices: a buffer view over its bytes and an accessor.
struct Section {
  std::string bytes;
  std::string accessor;  // the accessor's JSON after "bufferView"
  int target = kArrayBuffer;
};

template <class Vector>
Section floatSection(const std::vector<Vector>& values, const char* type, bool withBounds, bool flipV = false) {
  Section section;
  constexpr int n = Vector::length();
  std::array<float, n> lo, hi;
  lo.fill(std::numeric_limits<float>::infinity());
  hi.fill(-std::numeric_limits<float>::infinity());
  section.bytes.reserve(values.size() * n * sizeof(float));
  for (const Vector& value : values)
    for (int k = 0; k < n; ++k) {
      const float f = (flipV && k == 1) ? 1.0f - value[k] : value[k];
      appendLittleEndian(section.bytes, f);
      lo[std::size_t(k)] = std::min(lo[std::size_t(k)], f);
      hi[std::size_t(k)] = std::max(hi[std::size_t(k)], f);
    }
  section.accessor = ",\"componentType\":" + std::to_string(kFloat) + ",\"count\":" + std::to_string(values.size()) +
                     ",\"type\":\"" + type + "\"";
  if (withBounds) {
    section.accessor += ",\"min\":";
    appendFloatList(section.accessor, lo.data(), n);
    section.accessor += ",\"max\":";
    appendFloatList(section.accessor, hi.data(), n);
  }
  return section;
}

void padTo4(std::string& bytes, char with) {
  while (bytes.size() % 4 != 0) bytes += with;
}

}  // namespace

Result<std::string> glbBytes(const mesh::TriangleMesh& mesh) {
  std::vector<Section> sections;
  std::string attributes = "\"POSITION\":0";
  sections.push_back(floatSection(mesh.positions, "VEC3", true));
  if (mesh.hasNormals()) {
    attributes += ",\"NORMAL\":" + std::to_string(sections.size());
    sections.push_back(floatSection(mesh.normals, "VEC3", false));
  }
  if (mesh.hasColours()) {
    attributes += ",\"COLOR_0\":" + std::to_string(sections.size());
    sections.push_back(floatSection(mesh.colours, "VEC4", false));
  }
  if (mesh.hasUvs()) {
    attributes += ",\"TEXCOORD_0\":" + std::to_string(sections.size());
    sections.push_back(floatSection(mesh.uvs, "VEC2", false, true));
  }
  const std::size_t indexAccessor = sections.size();
  Section indices;
  indices.bytes.reserve(mesh.indices.size() * sizeof(std::uint32_t));
  for (const std::uint32_t index : mesh.indices) appendLittleEndian(indices.bytes, index);
  indices.accessor = ",\"componentType\":" + std::to_string(kUnsignedInt) +
                     ",\"count\":" + std::to_string(mesh.indices.size()) + ",\"type\":\"SCALAR\"";
  indices.target = kElementArrayBuffer;
  sections.push_back(std::move(indices));

  std::uint64_t binaryBytes = 0;
  for (const Section& section : sections) binaryBytes += section.bytes.size();  // each a multiple of 4
  // 12 header bytes, two 8-byte chunk headers, the JSON (a few hundred bytes per section).
  if (binaryBytes + 28 + 4096 + 512 * sections.size() > std::numeric_limits<std::uint32_t>::max())
    return makeError(ErrorKind::Unsupported, "the mesh is too large for a .glb (4 GiB at most)");

  std::string json =
      "{\"asset\":{\"version\":\"2.0\",\"generator\":\"Polder\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
      "\"nodes\":[{\"mesh\":0,\"rotation\":[-0.70710678,0,0,0.70710678]}],"
      "\"meshes\":[{\"primitives\":[{\"attributes\":{" +
      attributes + "},\"indices\":" + std::to_string(indexAccessor) + ",\"mode\":4}]}],";
  json += "\"buffers\":[{\"byteLength\":" + std::to_string(binaryBytes) + "}],\"bufferViews\":[";
  std::uint64_t offset = 0;
  for (std::size_t s = 0; s < sections.size(); ++s) {
    if (s > 0) json += ',';
    json += "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
            ",\"byteLength\":" + std::to_string(sections[s].bytes.size()) +
            ",\"target\":" + std::to_string(sections[s].target) + "}";
    offset += sections[s].bytes.size();
  }
  json += "],\"accessors\":[";
  for (std::size_t s = 0; s < sections.size(); ++s) {
    if (s > 0) json += ',';
    json += "{\"bufferView\":" + std::to_string(s) + sections[s].accessor + "}";
  }
  json += "]}";
  padTo4(json, ' ');

  std::string out;
  const std::uint64_t total = 12 + 8 + json.size() + 8 + binaryBytes;
  out.reserve(std::size_t(total));
  appendLittleEndian(out, kMagic);
  appendLittleEndian(out, std::uint32_t(2));
  appendLittleEndian(out, std::uint32_t(total));
  appendLittleEndian(out, std::uint32_t(json.size()));
  appendLittleEndian(out, kJsonChunk);
  out += json;
  appendLittleEndian(out, std::uint32_t(binaryBytes));
  appendLittleEndian(out, kBinChunk);
  for (const Section& section : sections) out += section.bytes;
  return out;
}

}  // namespace polder::mesh_io::detail
