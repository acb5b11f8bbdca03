#include <polder/partial_file.hpp>

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace polder::core {
namespace {

Error ioError(const std::filesystem::path& path, const std::string& what) {
  return Error{ErrorKind::Io, path.string() + ": cannot " + what + ": " + std::strerror(errno)};
}

std::string kibibytes(std::uint64_t bytes) { return std::to_string((bytes + 1023) >> 10) + " KiB"; }

}  // namespace

PartialFile::PartialFile(std::filesystem::path destination)
    : m_destination(std::move(destination)),
      m_path(m_destination.string() + ".partial-" + std::to_string(::getpid())) {}

PartialFile::~PartialFile() {
  if (m_fd >= 0) ::close(m_fd);
  if (!m_committed && !m_path.empty()) ::unlink(m_path.c_str());
}

Status PartialFile::create(std::uint64_t bytesNeeded, bool preallocate) {
  m_fd = ::open(m_path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (m_fd < 0) return ioError(m_destination, "create");
  struct statvfs disk {};
  if (::fstatvfs(m_fd, &disk) == 0) {
    const std::uint64_t room = std::uint64_t(disk.f_bavail) * std::uint64_t(disk.f_frsize);
    if (room < bytesNeeded)
      return makeError(ErrorKind::Io, m_destination.string() + ": needs " + kibibytes(bytesNeeded) +
                                          " and the disk has " + kibibytes(room) + " free");
  }
  if (preallocate && ::ftruncate(m_fd, off_t(bytesNeeded)) != 0) return ioError(m_destination, "size the output");
  return {};
}

Status PartialFile::commit() {
  if (::fsync(m_fd) != 0) return ioError(m_destination, "sync");
  const int fd = m_fd;
  m_fd = -1;
  if (::close(fd) != 0) return ioError(m_destination, "close");
  std::error_code error;
  std::filesystem::rename(m_path, m_destination, error);
  if (error) return makeError(ErrorKind::Io, m_destination.string() + ": cannot rename into place: " + error.message());
  m_committed = true;
  // The rename itself reaches the disk with the folder's sync.
  const std::filesystem::path folder = m_destination.has_parent_path() ? m_destination.parent_path() : ".";
  if (const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  return {};
}

}  // namespace polder::core
