// PNG chunk layout and CRC-32 as in the PNG specification (ISO/IEC 15948), sections 5.3, D;
// the image data is one zlib stream across the IDAT chunks (section 10), inflated by zlib.
#include "polder/png_check.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace polder::image_check {
namespace {

constexpr std::array<std::uint32_t, 256> makeCrcTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kCrcTable = makeCrcTable();

std::uint32_t updateCrc(std::uint32_t crc, const unsigned char* bytes, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) crc = kCrcTable[(crc ^ bytes[i]) & 0xffu] ^ (crc >> 8);
  return crc;
}

std::uint32_t bigEndian32(const unsigned char* bytes) {
  return std::uint32_t(bytes[0]) << 24 | std::uint32_t(bytes[1]) << 16 | std::uint32_t(bytes[2]) << 8 | bytes[3];
}

bool isChunkType(const unsigned char* type) {
  for (int i = 0; i < 4; ++i)
    if (!((type[i] >= 'A' && type[i] <= 'Z') || (type[i] >= 'a' && type[i] <= 'z'))) return false;
  return true;
}

// Inflates the concatenated IDAT data into a scratch buffer, only to find a corrupt stream
// before libpng does (libpng prints its complaint to stderr).
class ImageDataCheck {
 public:
  ImageDataCheck() { m_ready = inflateInit(&m_stream) == Z_OK; }
  ~ImageDataCheck() {
    if (m_ready) inflateEnd(&m_stream);
  }
  ImageDataCheck(const ImageDataCheck&) = delete;
  ImageDataCheck& operator=(const ImageDataCheck&) = delete;

  // Empty while the data so far is a valid stream, else zlib's reason.
  std::string feed(unsigned char* bytes, std::size_t count) {
    if (!m_ready) return "zlib could not start";
    m_stream.next_in = bytes;
    m_stream.avail_in = uInt(count);
    while (m_stream.avail_in > 0 && !m_ended) {
      m_stream.next_out = m_scratch.data();
      m_stream.avail_out = uInt(m_scratch.size());
      const int result = inflate(&m_stream, Z_NO_FLUSH);
      if (result == Z_STREAM_END)
        m_ended = true;
      else if (result != Z_OK)
        return m_stream.msg ? m_stream.msg : "the compressed data is corrupt";
    }
    return {};
  }
  bool ended() const { return m_ended; }

 private:
  z_stream m_stream{};
  std::array<unsigned char, 1 << 16> m_scratch{};
  bool m_ready = false;
  bool m_ended = false;
};

}  // namespace

Status checkPngStructure(const std::filesystem::path& path, std::uint64_t fileLength) {
  constexpr std::uint64_t kSignatureBytes = 8;
  constexpr std::uint32_t kMaxChunkLength = 0x7fffffffu;  // the specification's limit
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(ErrorKind::Io, "cannot open the file");
  in.seekg(std::streamoff(kSignatureBytes));

  std::vector<unsigned char> buffer(1 << 16);
  ImageDataCheck imageData;
  std::uint64_t offset = kSignatureBytes;
  while (true) {
    unsigned char header[8];
    if (offset + sizeof header > fileLength || !in.read(reinterpret_cast<char*>(header), sizeof header))
      return makeError(ErrorKind::InvalidData,
                       "truncated PNG: the file ends at byte " + std::to_string(fileLength) + " before the IEND chunk");
    const std::uint32_t length = bigEndian32(header);
    const std::string type(reinterpret_cast<const char*>(header + 4), 4);
    if (length > kMaxChunkLength || !isChunkType(header + 4))
      return makeError(ErrorKind::InvalidData,
                       "corrupt PNG: the chunk header at byte " + std::to_string(offset) + " is not valid");
    if (offset + 12 + length > fileLength)
      return makeError(ErrorKind::InvalidData, "truncated PNG: chunk " + type + " at byte " + std::to_string(offset) +
                                                   " needs " + std::to_string(length + 12) +
                                                   " bytes, the file ends at byte " + std::to_string(fileLength));
    std::uint32_t crc = updateCrc(0xffffffffu, header + 4, 4);
    for (std::uint32_t left = length; left > 0;) {
      const std::size_t part = std::min<std::size_t>(left, buffer.size());
      if (!in.read(reinterpret_cast<char*>(buffer.data()), std::streamsize(part)))
        return makeError(ErrorKind::Io, "cannot read chunk " + type + " at byte " + std::to_string(offset));
      crc = updateCrc(crc, buffer.data(), part);
      if (type == "IDAT")
        if (const std::string problem = imageData.feed(buffer.data(), part); !problem.empty())
          return makeError(ErrorKind::InvalidData, "corrupt PNG: the image data in chunk IDAT at byte " +
                                                       std::to_string(offset) + " does not decompress (" + problem +
                                                       ")");
      left -= std::uint32_t(part);
    }
    unsigned char stored[4];
    if (!in.read(reinterpret_cast<char*>(stored), 4))
      return makeError(ErrorKind::Io, "cannot read chunk " + type + " at byte " + std::to_string(offset));
    if (bigEndian32(stored) != (crc ^ 0xffffffffu))
      return makeError(ErrorKind::InvalidData,
                       "corrupt PNG: chunk " + type + " at byte " + std::to_string(offset) + " fails its CRC check");
    if (type == "IEND") {
      if (!imageData.ended())
        return makeError(ErrorKind::InvalidData, "corrupt PNG: the image data ends before its compressed stream does");
      return {};
    }
    offset += 12 + std::uint64_t(length);
  }
}

Status checkIfPng(const std::filesystem::path& path) {
  char head[8] = {};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in.read(head, sizeof head) || std::memcmp(head, "\x89PNG\r\n\x1a\n", sizeof head) != 0) return {};
  }
  std::error_code error;
  const std::uint64_t length = std::filesystem::file_size(path, error);
  if (error) return makeError(ErrorKind::Io, "cannot read the file size: " + error.message());
  return checkPngStructure(path, length);
}

}  // namespace polder::image_check
