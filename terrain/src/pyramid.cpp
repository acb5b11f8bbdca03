// Reading a terrain pyramid (pyramid.hpp): every size is checked against the header and the
// layout before it is used, and every byte read is checked against its CRC.
#include <polder/terrain/pyramid.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <new>
#include <vector>

#include <polder/checksum.hpp>

#include "pyramid_layout.hpp"

namespace polder::terrain {
namespace {

using namespace pyramid_layout;

Error dataError(const std::filesystem::path& path, const std::string& problem) {
  return Error{ErrorKind::InvalidData, path.string() + ": " + problem};
}

std::string nodeName(const NodeId& node) {
  return "node (level " + std::to_string(node.level) + ", " + std::to_string(node.bx) + ", " + std::to_string(node.by) +
         ")";
}

// Reads exactly `size` bytes at `offset`, or says why not.
Status readExactly(int fd, void* data, std::size_t size, std::uint64_t offset, const std::filesystem::path& path,
                   const std::string& what) {
  auto* bytes = static_cast<unsigned char*>(data);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t got = ::pread(fd, bytes + done, size - done, off_t(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return makeError(ErrorKind::Io, path.string() + ": cannot read " + what + ": " + std::strerror(errno));
    if (got == 0) return dataError(path, what + " is cut short (truncated file)");
    done += std::size_t(got);
  }
  return {};
}

}  // namespace

Result<std::unique_ptr<Pyramid>> Pyramid::open(const std::filesystem::path& path) {
  std::unique_ptr<Pyramid> pyramid(new (std::nothrow) Pyramid());
  if (!pyramid) return makeError(ErrorKind::OutOfMemory, path.string() + ": no memory to open the pyramid");
  pyramid->m_path = path;
  pyramid->m_fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (pyramid->m_fd < 0) return makeError(ErrorKind::Io, path.string() + ": cannot open: " + std::strerror(errno));
  struct stat info {};
  if (::fstat(pyramid->m_fd, &info) != 0)
    return makeError(ErrorKind::Io, path.string() + ": cannot stat: " + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) return dataError(path, "not a regular file");
  const auto actualBytes = std::uint64_t(info.st_size);
  if (actualBytes < kPyramidHeaderBytes) return dataError(path, "too short to be a Polder pyramid");

  unsigned char bytes[kPyramidHeaderBytes];
  if (Status read = readExactly(pyramid->m_fd, bytes, sizeof bytes, 0, path, "the header"); !read) return read.error();
  if (std::memcmp(bytes, kPyramidMagic, sizeof kPyramidMagic) != 0)
    return dataError(path, "not a Polder pyramid (no PLDRPYR1 magic; an unfinished prep leaves none)");
  if (get<std::uint32_t>(bytes, kCrcAt) != core::crc32c(bytes + kVersionAt, kCrcAt - kVersionAt))
    return dataError(path, "the header's checksum does not match (corrupt file)");
  if (const auto version = get<std::uint32_t>(bytes, kVersionAt); version != kPyramidVersion)
    return makeError(ErrorKind::Unsupported, path.string() + ": pyramid version " + std::to_string(version) +
                                                 " (this Polder reads version " + std::to_string(kPyramidVersion) +
                                                 "; prepare it again)");
  if (get<std::uint32_t>(bytes, kHeaderBytesAt) != kPyramidHeaderBytes) return dataError(path, "bad header size");

  PyramidHeader& h = pyramid->m_header;
  h.width = get<std::int32_t>(bytes, kWidthAt);
  h.height = get<std::int32_t>(bytes, kHeightAt);
  h.spacingX = get<double>(bytes, kSpacingXAt);
  h.spacingY = get<double>(bytes, kSpacingYAt);
  h.k = get<std::int32_t>(bytes, kKAt);
  h.rootLevel = get<std::int32_t>(bytes, kRootLevelAt);
  h.minHeight = get<float>(bytes, kMinAt);
  h.maxHeight = get<float>(bytes, kMaxAt);
  h.nodeCount = get<std::uint64_t>(bytes, kNodeCountAt);
  h.nodesOffset = get<std::uint64_t>(bytes, kNodesOffsetAt);
  h.borderOffset = get<std::uint64_t>(bytes, kBorderOffsetAt);
  h.tilesOffset = get<std::uint64_t>(bytes, kTilesOffsetAt);
  h.tileSlotBytes = get<std::uint32_t>(bytes, kTileSlotAt);
  h.tileSide = get<std::uint32_t>(bytes, kTileSideAt);
  h.fileBytes = get<std::uint64_t>(bytes, kFileBytesAt);
  const auto sourceLength = get<std::uint32_t>(bytes, kSourceLengthAt);
  if (sourceLength > kMaxSourceBytes) return dataError(path, "bad source name length");
  h.source.assign(reinterpret_cast<const char*>(bytes + kSourceAt), sourceLength);

  if (!(std::isfinite(h.spacingX) && h.spacingX > 0.0 && std::isfinite(h.spacingY) && h.spacingY > 0.0))
    return dataError(path, "the sample spacing is not a positive number");
  if (!(std::isfinite(h.minHeight) && std::isfinite(h.maxHeight) && h.minHeight <= h.maxHeight))
    return dataError(path, "bad height range");
  auto layout = BlockLayout::create(h.width, h.height, h.k);
  if (!layout) return dataError(path, "bad size: " + layout.error().message);
  pyramid->m_layout = *layout;
  if (h.rootLevel != layout->rootLevel()) return dataError(path, "the root level disagrees with the size");
  std::uint64_t nodes = 0;
  pyramid->m_levelOffset.resize(std::size_t(h.rootLevel) + 1);
  for (int level = 0; level <= h.rootLevel; ++level) {
    pyramid->m_levelOffset[std::size_t(level)] = nodes;
    nodes += std::uint64_t(layout->nodesX(level)) * std::uint64_t(layout->nodesY(level));
  }
  if (h.nodeCount != nodes) return dataError(path, "the node count disagrees with the size");
  if (h.tileSide != tileSide(h.k) || h.tileSlotBytes != tileSlotBytes(h.k))
    return dataError(path, "the tile size disagrees with the block size");
  if (h.nodesOffset < kPyramidHeaderBytes || h.borderOffset != h.nodesOffset + nodeTableBytes(h.nodeCount) ||
      h.tilesOffset < h.borderOffset + borderBytes(h.width, h.height) ||
      h.fileBytes != h.tilesOffset + h.nodeCount * h.tileSlotBytes)
    return dataError(path, "the section offsets disagree with the sizes");
  if (actualBytes != h.fileBytes)
    return dataError(path, "is " + std::to_string(actualBytes) + " bytes, its header says " +
                               std::to_string(h.fileBytes) + " (truncated or extended)");

  try {
    pyramid->m_nodes.resize(std::size_t(h.nodeCount));
    pyramid->m_eastBorder.resize(std::size_t(h.height));
    pyramid->m_northBorder.resize(std::size_t(h.width));
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory,
                     path.string() + ": no memory for " + std::to_string(h.nodeCount) + " node records");
  }
  const std::size_t chunks = (h.nodeCount + kPyramidNodeChunk - 1) / kPyramidNodeChunk;
  std::vector<std::uint32_t> crcs(chunks);
  const std::uint64_t crcOffset = h.nodesOffset + h.nodeCount * sizeof(PyramidNode);
  if (Status read = readExactly(pyramid->m_fd, pyramid->m_nodes.data(), pyramid->m_nodes.size() * sizeof(PyramidNode),
                                h.nodesOffset, path, "the node table");
      !read)
    return read.error();
  if (Status read = readExactly(pyramid->m_fd, crcs.data(), chunks * 4, crcOffset, path, "the node table"); !read)
    return read.error();
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t first = chunk * kPyramidNodeChunk;
    const std::size_t count = std::min<std::size_t>(kPyramidNodeChunk, h.nodeCount - first);
    if (core::crc32c(pyramid->m_nodes.data() + first, count * sizeof(PyramidNode)) != crcs[chunk])
      return dataError(path, "the node table's checksum does not match at records " + std::to_string(first) + ".." +
                                 std::to_string(first + count - 1) + " (corrupt file)");
  }
  std::uint64_t at = h.borderOffset;
  for (auto* border : {&pyramid->m_eastBorder, &pyramid->m_northBorder}) {
    std::uint32_t crc = 0;
    const std::size_t size = border->size() * sizeof(float);
    if (Status read = readExactly(pyramid->m_fd, border->data(), size, at, path, "the border samples"); !read)
      return read.error();
    if (Status read = readExactly(pyramid->m_fd, &crc, 4, at + size, path, "the border samples"); !read)
      return read.error();
    if (core::crc32c(border->data(), size) != crc)
      return dataError(path, "the border samples' checksum does not match (corrupt file)");
    at += size + 4;
  }
  return pyramid;
}

Pyramid::~Pyramid() {
  if (m_fd >= 0) ::close(m_fd);
}

std::size_t Pyramid::nodeIndex(const NodeId& node) const {
  assert(m_layout.exists(node) && "Pyramid::nodeIndex: the node is not in the layout");
  return m_levelOffset[node.level] + std::size_t(node.by) * std::size_t(m_layout.nodesX(node.level)) + node.bx;
}

Status Pyramid::readTile(const NodeId& node, PyramidTile& out) const {
  if (!m_layout.exists(node)) return makeError(ErrorKind::InvalidArgument, "Pyramid::readTile: no such node");
  const std::size_t index = nodeIndex(node);
  const std::size_t sideSamples = std::size_t(m_header.tileSide) * m_header.tileSide;
  const std::size_t residualBytes = sizeof(float) + tileCellsMax(m_header.k);
  std::vector<unsigned char> residual;
  try {
    out.samples.heights.resize(sideSamples);  // reuses the capacity of earlier tiles
    residual.resize(residualBytes);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, "Pyramid::readTile: no memory for a tile");
  }
  unsigned char head[kPyramidTileHeaderBytes];
  iovec parts[3] = {
      {head, sizeof head}, {out.samples.heights.data(), sideSamples * sizeof(float)}, {residual.data(), residualBytes}};
  const std::uint64_t offset = m_header.tilesOffset + std::uint64_t(index) * m_header.tileSlotBytes;
  const std::size_t total = sizeof head + sideSamples * sizeof(float) + residualBytes;
  std::size_t done = 0;
  while (done < total) {
    // preadv cannot resume inside an iovec on its own: move the parts past what was read.
    iovec rest[3];
    int restCount = 0;
    std::size_t skip = done;
    for (const iovec& part : parts) {
      if (skip >= part.iov_len) {
        skip -= part.iov_len;
        continue;
      }
      rest[restCount++] = {static_cast<unsigned char*>(part.iov_base) + skip, part.iov_len - skip};
      skip = 0;
    }
    const ssize_t got = ::preadv(m_fd, rest, restCount, off_t(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0)
      return makeError(ErrorKind::Io,
                       m_path.string() + ": cannot read the tile of " + nodeName(node) + ": " + std::strerror(errno));
    if (got == 0) return dataError(m_path, "the tile of " + nodeName(node) + " is cut short (truncated file)");
    done += std::size_t(got);
  }
  std::uint32_t crc = core::crc32c(head + 4, sizeof head - 4);
  crc = core::crc32c(out.samples.heights.data(), sideSamples * sizeof(float), crc);
  crc = core::crc32c(residual.data(), residualBytes, crc);
  if (crc != get<std::uint32_t>(head, 0))
    return dataError(m_path, "the tile of " + nodeName(node) + " fails its checksum (corrupt file)");
  const SampleRect area = m_layout.footprint(node);
  const int stride = m_layout.stride(node);
  const int columns = (area.x1 - area.x0) / stride + 1, rows = (area.y1 - area.y0) / stride + 1;
  if (get<std::uint32_t>(head, 4) != index || get<std::uint16_t>(head, 8) != columns ||
      get<std::uint16_t>(head, 10) != rows)
    return dataError(m_path, "the tile stored for " + nodeName(node) + " belongs to another node");
  const float step = get<float>(residual.data(), 0);
  if (!(step >= 0.0f) || std::isinf(step))
    return dataError(m_path, "the tile of " + nodeName(node) + " has a residual step that is not finite and >= 0");
  const std::size_t cells = std::size_t(columns - 1) * std::size_t(rows - 1);
  try {
    out.cellResidual.resize(cells);
  } catch (const std::bad_alloc&) {
    return makeError(ErrorKind::OutOfMemory, "Pyramid::readTile: no memory for a tile");
  }
  for (std::size_t c = 0; c < cells; ++c) out.cellResidual[c] = float(residual[sizeof(float) + c]) * step;
  out.node = node;
  out.samples.width = columns;
  out.samples.height = rows;
  out.samples.spacingX = m_header.spacingX * stride;
  out.samples.spacingY = m_header.spacingY * stride;
  out.samples.heights.resize(std::size_t(columns) * std::size_t(rows));  // samples are stored packed
  return {};
}

std::size_t Pyramid::memoryBytes() const {
  return sizeof(*this) + m_nodes.capacity() * sizeof(PyramidNode) +
         (m_eastBorder.capacity() + m_northBorder.capacity()) * sizeof(float) +
         m_levelOffset.capacity() * sizeof(std::size_t);
}

}  // namespace polder::terrain
