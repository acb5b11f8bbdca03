#include "test_support.hpp"

#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>

namespace polder::test {

std::optional<std::filesystem::path> sharedDataDir() {
  if (const char* env = std::getenv("POLDER_DATA_DIR"); env && *env) {
    if (std::filesystem::is_directory(env)) return std::filesystem::path(env);
    return std::nullopt;
  }
  const std::filesystem::path dir = POLDER_SHARED_DATA_DIR;
  if (std::filesystem::is_directory(dir)) return std::filesystem::canonical(dir);
  return std::nullopt;
}

std::optional<std::filesystem::path> sharedDataFile(const std::string& relative) {
  const auto dir = sharedDataDir();
  if (!dir) return std::nullopt;
  const auto path = *dir / relative;
  if (!std::filesystem::exists(path)) return std::nullopt;
  return path;
}

bool sharedDataRequired() {
  const char* ci = std::getenv("CI");
  if (!ci || !*ci) return false;
  const std::string value = ci;
  return value != "0" && value != "false";
}

std::filesystem::path sourceDir() { return POLDER_SOURCE_DIR; }

ScratchDir::ScratchDir() {
  static std::atomic<int> counter{0};
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  m_path = std::filesystem::temp_directory_path() / ("polder-test-" + std::to_string(::getpid()) + "-" +
                                                     std::to_string(stamp) + "-" + std::to_string(counter++));
  std::filesystem::create_directories(m_path);
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(m_path, ignored);
}

void writeFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace polder::test
