// An output file that appears whole or not at all: it is written under a temporary name
// beside its destination (`<destination>.partial-<pid>`), synced, and renamed into place by
// commit(); destroyed uncommitted, it is removed. A process killed while writing leaves only
// the temporary file, never a destination that looks complete.
#pragma once

#include <cstdint>
#include <filesystem>

#include <polder/result.hpp>

namespace polder::core {

class PartialFile {
 public:
  explicit PartialFile(std::filesystem::path destination);
  ~PartialFile();
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  const std::filesystem::path& destination() const { return m_destination; }
  const std::filesystem::path& path() const { return m_path; }
  // The open descriptor, -1 before create() and after commit().
  int fd() const { return m_fd; }

  // Creates the temporary file. Fails (Io, naming the destination) when it cannot be created
  // or when the disk has less than `bytesNeeded` free; `preallocate` sizes the file to
  // `bytesNeeded` at once (for writers that place their parts at fixed offsets).
  Status create(std::uint64_t bytesNeeded, bool preallocate);

  // Syncs, closes and renames the file into place, then syncs the folder.
  Status commit();

 private:
  std::filesystem::path m_destination;
  std::filesystem::path m_path;
  int m_fd = -1;
  bool m_committed = false;
};

}  // namespace polder::core
