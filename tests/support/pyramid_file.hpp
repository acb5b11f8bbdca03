// A pyramid prepared from a heightfield into a temporary file, removed with the object; and a
// byte of one tile flipped on purpose, for the tests of corrupt tiles (link polder::terrain).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include <polder/terrain/height_rows.hpp>
#include <polder/terrain/pyramid.hpp>
#include <polder/terrain/pyramid_build.hpp>

namespace polder::test {

class PyramidFile {
 public:
  PyramidFile(const terrain::Heightfield& field, const std::string& name,
              const terrain::PyramidBuildOptions& options = {})
      : m_path(std::filesystem::temp_directory_path() /
               ("polder-test-" + std::to_string(::getpid()) + "-" + name + ".pyr")) {
    terrain::HeightfieldRows rows(field);
    auto report = terrain::buildPyramid(rows, m_path, options);
    EXPECT_TRUE(report.ok()) << (report.ok() ? "" : report.error().message);
  }
  ~PyramidFile() { std::filesystem::remove(m_path); }
  PyramidFile(const PyramidFile&) = delete;
  PyramidFile& operator=(const PyramidFile&) = delete;

  const std::filesystem::path& path() const { return m_path; }
  std::shared_ptr<const terrain::Pyramid> open() const {
    auto pyramid = terrain::Pyramid::open(m_path);
    EXPECT_TRUE(pyramid.ok()) << (pyramid.ok() ? "" : pyramid.error().message);
    return pyramid.ok() ? std::shared_ptr<const terrain::Pyramid>(std::move(*pyramid)) : nullptr;
  }

  // Flips one byte among the samples of `node`'s tile; its CRC no longer matches.
  void corruptTile(const terrain::NodeId& node) const {
    auto pyramid = open();
    ASSERT_NE(pyramid, nullptr);
    const std::uint64_t offset = pyramid->header().tilesOffset +
                                 pyramid->nodeIndex(node) * pyramid->header().tileSlotBytes +
                                 terrain::kPyramidTileHeaderBytes + 4 * 100;
    std::fstream bytes(m_path, std::ios::in | std::ios::out | std::ios::binary);
    bytes.seekg(std::streamoff(offset));
    char c = 0;
    bytes.read(&c, 1);
    c = char(c ^ 0x5a);
    bytes.seekp(std::streamoff(offset));
    bytes.write(&c, 1);
  }

 private:
  std::filesystem::path m_path;
};

}  // namespace polder::test
