// Helpers shared by the test programs: scratch folders, the shared data folder, and
// running the polder program.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <gtest/gtest.h>

namespace polder::test {

// The folder with the real DEMs, meshes and models (the shared data folder beside the
// checkout, or $POLDER_DATA_DIR), if it exists.
std::optional<std::filesystem::path> sharedDataDir();

// The path of a file in the shared data folder, or nullopt when the folder or file is absent.
std::optional<std::filesystem::path> sharedDataFile(const std::string& relative);

// Whether a missing shared data file is a failure rather than a skip: under CI (the CI
// variable set and not "false" or "0"), where the shared data folder is always laid out.
bool sharedDataRequired();

// The repository's top folder (for data/ and shaders/).
std::filesystem::path sourceDir();

// A fresh folder for one test, removed with the object.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return m_path; }
  std::filesystem::path file(const std::string& name) const { return m_path / name; }

 private:
  std::filesystem::path m_path;
};

// Writes bytes to a file (for hand-made and corrupt inputs).
void writeFile(const std::filesystem::path& path, const std::string& bytes);
// Bytes of a file, for truncating and corrupting.
std::string readBytes(const std::filesystem::path& path);

}  // namespace polder::test

// Skips the current test with a message naming the missing shared file (fails under CI).
#define POLDER_REQUIRE_SHARED_FILE(var, relative)                                              \
  const auto var##_optional = ::polder::test::sharedDataFile(relative);                        \
  if (!var##_optional && ::polder::test::sharedDataRequired())                                 \
    GTEST_FAIL() << "shared data file " << (relative)                                          \
                 << " is absent (shared data folder or $POLDER_DATA_DIR), and CI requires it"; \
  if (!var##_optional)                                                                         \
    GTEST_SKIP() << "shared data file " << (relative)                                          \
                 << " is absent (shared data folder or $POLDER_DATA_DIR); skipped";            \
  const std::filesystem::path var = *var##_optional
