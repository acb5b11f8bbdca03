#include <polder/file_contents.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include <polder/partial_file.hpp>

namespace polder::core {

Result<std::string> readFileContents(const std::filesystem::path& file, std::uint64_t maxBytes) {
  std::error_code code;
  const auto status = std::filesystem::status(file, code);
  if (!std::filesystem::exists(status)) return makeError(ErrorKind::Io, "the file does not exist");
  if (std::filesystem::is_directory(status)) return makeError(ErrorKind::Io, "is a directory, not a file");
  const std::uintmax_t size = std::filesystem::file_size(file, code);
  if (code) return makeError(ErrorKind::Io, "cannot read the file size: " + code.message());
  if (size > maxBytes)
    return makeError(ErrorKind::InvalidData, "the file has " + std::to_string(size) + " bytes, more than the " +
                                                 std::to_string(maxBytes) + " this reader takes");
  std::ifstream in(file, std::ios::binary);
  if (!in) return makeError(ErrorKind::Io, "cannot open the file: " + std::generic_category().message(errno));
  std::string bytes;
  try {
    bytes.resize(std::size_t(size));
  } catch (const std::exception&) {
    return makeError(ErrorKind::OutOfMemory, "not enough memory to read the file");
  }
  in.read(bytes.data(), std::streamsize(bytes.size()));
  if (std::uintmax_t(in.gcount()) != size)
    return makeError(ErrorKind::Io,
                     "could read only " + std::to_string(in.gcount()) + " of its " + std::to_string(size) + " bytes");
  return bytes;
}

Status writeFileContents(const std::filesystem::path& file, std::string_view bytes) {
  PartialFile output(file);
  if (Status created = output.create(bytes.size(), false); !created) return created;
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t step = ::write(output.fd(), bytes.data() + written, bytes.size() - written);
    if (step < 0 && errno == EINTR) continue;
    if (step <= 0)
      return makeError(ErrorKind::Io,
                       file.string() + ": cannot write the file: " + (step < 0 ? std::strerror(errno) : "no progress"));
    written += std::size_t(step);
  }
  return output.commit();
}

}  // namespace polder::core
