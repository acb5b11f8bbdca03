// The terrain pyramid: what buildPyramid writes agrees with the block quadtree built from the
// whole field (exact ranges, exact level-0 errors, bounds at coarser levels), tiles hold the
// strided samples, and a pyramid that is corrupt, truncated or unfinished does not open or
// read as valid.
#include <polder/terrain/pyramid.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <polder/terrain/block_quadtree.hpp>
#include <polder/terrain/dike_errors.hpp>
#include <polder/terrain/pyramid_build.hpp>
#include <polder/terrain/rtin.hpp>
#include <polder/thread_pool.hpp>

namespace polder::terrain {
namespace {

namespace fs = std::filesystem;

// Hills, a ridge, a plateau, a lake and per-sample noise, at a size that clips edge blocks.
Heightfield makeField(int width, int height, std::uint64_t seed) {
  Heightfield field(width, height, 30.0, 25.0);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> noise(-4.0, 4.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double h = 400.0 + 250.0 * std::sin(x * 0.031) * std::cos(y * 0.027) +
                 120.0 * std::abs(std::sin(0.011 * (x + 2 * y))) + 40.0 * std::sin(x * 0.21 + y * 0.17) + noise(rng);
      if (x > width / 2 && y > height / 2) h = std::min(h, 520.0);
      if (x < width / 4 && y < height / 4) h = 300.0;
      field.at(x, y) = float(h);
    }
  return field;
}

class TempFolder {
 public:
  TempFolder() : m_path(fs::temp_directory_path() / ("polder-pyramid-" + std::to_string(::getpid()))) {
    fs::create_directories(m_path);
  }
  ~TempFolder() { fs::remove_all(m_path); }
  const fs::path& path() const { return m_path; }

 private:
  fs::path m_path;
};

fs::path buildOrFail(const Heightfield& field, const fs::path& out, PyramidBuildOptions options = {}) {
  HeightfieldRows rows(field);
  auto report = buildPyramid(rows, out, options);
  EXPECT_TRUE(report.ok()) << (report.ok() ? "" : report.error().message);
  return out;
}

std::unique_ptr<Pyramid> openOrFail(const fs::path& path) {
  auto pyramid = Pyramid::open(path);
  EXPECT_TRUE(pyramid.ok()) << (pyramid.ok() ? "" : pyramid.error().message);
  return pyramid.ok() ? std::move(pyramid).value() : nullptr;
}

template <class F>
void forEachNode(const BlockLayout& layout, F&& f) {
  for (int level = 0; level <= layout.rootLevel(); ++level)
    for (int by = 0; by < layout.nodesY(level); ++by)
      for (int bx = 0; bx < layout.nodesX(level); ++bx)
        f(NodeId{std::uint8_t(level), std::uint32_t(bx), std::uint32_t(by)});
}

std::string name(const NodeId& n) {
  return "node " + std::to_string(n.level) + "/" + std::to_string(n.bx) + "/" + std::to_string(n.by);
}

// f(node, tile) for every node whose tile reads; a tile that does not read fails the test.
template <class F>
void forEachTile(const Pyramid& pyramid, F&& f) {
  PyramidTile tile;
  forEachNode(pyramid.layout(), [&](const NodeId& node) {
    const Status read = pyramid.readTile(node, tile);
    EXPECT_TRUE(read.ok()) << name(node) << ": " << (read.ok() ? "" : read.error().message);
    if (read.ok()) f(node, tile);
  });
}

TEST(Pyramid, NodesAgreeWithTheQuadtreeOfTheWholeField) {
  const Heightfield field = makeField(301, 219, 11);
  TempFolder folder;
  core::ThreadPool pool(2);
  PyramidBuildOptions options;
  options.pool = &pool;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "hills.pyr", options));
  ASSERT_NE(pyramid, nullptr);
  const auto layout = BlockLayout::create(field.width, field.height).value();
  ASSERT_EQ(pyramid->layout().rootLevel(), layout.rootLevel());
  ASSERT_GE(layout.rootLevel(), 3);
  const auto tree = BlockQuadtree::build(field, layout).value();
  const auto [lo, hi] = field.heightRange();
  EXPECT_EQ(pyramid->header().minHeight, lo);
  EXPECT_EQ(pyramid->header().maxHeight, hi);
  int boundedStrictly = 0;
  forEachNode(layout, [&](const NodeId& node) {
    const PyramidNode& p = pyramid->node(node);
    const NodeInfo& t = tree.info(node);
    EXPECT_EQ(p.minHeight, t.minHeight) << name(node);
    EXPECT_EQ(p.maxHeight, t.maxHeight) << name(node);
    EXPECT_EQ(p.dikeRange, dikeErrorBound(field, layout, node)) << name(node);
    if (node.level == 0) {
      EXPECT_EQ(p.residual, 0.0f);
      EXPECT_EQ(p.lodError, t.lodError) << name(node);
      EXPECT_EQ(p.floorError, t.floorError) << name(node);
      return;
    }
    EXPECT_GT(p.residual, 0.0f) << name(node);
    // Bounds of the full-resolution errors, never below them.
    EXPECT_GE(p.lodError, t.lodError) << name(node);
    EXPECT_GE(p.floorError, t.floorError) << name(node);
    EXPECT_GE(p.floorError, p.residual) << name(node);
    if (std::isfinite(t.lodError) && p.lodError > t.lodError) ++boundedStrictly;
    EXPECT_EQ(std::isfinite(p.lodError), std::isfinite(t.lodError)) << name(node);
  });
  EXPECT_GT(boundedStrictly, 0);
}

// White noise: the level surfaces miss most of it, so the bounds rest on the residuals.
TEST(Pyramid, ErrorBoundsHoldOnRoughTerrain) {
  Heightfield field(203, 171, 10.0, 10.0);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> noise(-50.0, 50.0);
  for (float& h : field.heights) h = float(100.0 + noise(rng));
  TempFolder folder;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "rough.pyr"));
  ASSERT_NE(pyramid, nullptr);
  const auto tree = BlockQuadtree::build(field, pyramid->layout()).value();
  forEachNode(pyramid->layout(), [&](const NodeId& node) {
    EXPECT_GE(pyramid->node(node).lodError, tree.info(node).lodError) << name(node);
    EXPECT_GE(pyramid->node(node).floorError, tree.info(node).floorError) << name(node);
  });
}

// The level surface of a tile (cells cut from (x + 1, y) to (x, y + 1)) at full-resolution
// sample (x, y) of a cell, (x0, y0) the tile's first sample and s its stride.
double levelSurface(const Heightfield& tile, int s, int x0, int y0, int x, int y) {
  const int i = (x - x0) / s, j = (y - y0) / s;
  const double u = double(x - x0 - i * s) / s, v = double(y - y0 - j * s) / s;
  const int i1 = std::min(i + 1, tile.width - 1), j1 = std::min(j + 1, tile.height - 1);
  const double h00 = tile.at(i, j), h10 = tile.at(i1, j), h01 = tile.at(i, j1), h11 = tile.at(i1, j1);
  if (u + v <= 1.0) return h00 + u * (h10 - h00) + v * (h01 - h00);
  return h11 + (1.0 - u) * (h01 - h11) + (1.0 - v) * (h10 - h11);
}

// Over each cell the full resolution lies within the cell's residual of the level surface (the
// two surfaces differ most at full-resolution samples: every level edge runs along full-
// resolution edges or crosses them at samples), and the residuals follow the terrain: most
// cells' are well below their node's largest.
TEST(Pyramid, EachCellsResidualBoundsTheFullResolutionOverIt) {
  const Heightfield field = makeField(203, 171, 12);
  TempFolder folder;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "cells.pyr"));
  ASSERT_NE(pyramid, nullptr);
  const BlockLayout& layout = pyramid->layout();
  std::size_t cells = 0, wellBelow = 0;
  forEachTile(*pyramid, [&](const NodeId& node, const PyramidTile& tile) {
    const int w = tile.samples.width - 1, h = tile.samples.height - 1;
    ASSERT_EQ(tile.cellResidual.size(), std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0))) << name(node);
    const SampleRect area = layout.footprint(node);
    const int s = layout.stride(node);
    float largest = 0.0f;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const float r = tile.cellResidual[std::size_t(j) * std::size_t(w) + std::size_t(i)];
        largest = std::max(largest, r);
        double worst = 0.0;
        for (int y = area.y0 + j * s; y <= area.y0 + (j + 1) * s; ++y)
          for (int x = area.x0 + i * s; x <= area.x0 + (i + 1) * s; ++x)
            worst = std::max(worst, std::abs(field.at(x, y) - levelSurface(tile.samples, s, area.x0, area.y0, x, y)));
        ASSERT_GE(double(r), worst - 1e-3) << name(node) << " cell " << i << "," << j;
        if (node.level == 0) ASSERT_EQ(r, 0.0f) << name(node);
      }
    EXPECT_EQ(largest, pyramid->node(node).residual) << name(node);
    if (node.level == 0) return;
    for (const float r : tile.cellResidual) {
      ++cells;
      wellBelow += r < 0.5f * largest;
    }
  });
  EXPECT_GT(wellBelow, cells / 2);
}

// A tile's hierarchy with its cells' residuals bounds the full-resolution one vertex by vertex,
// and is tighter than one residual for the whole node.
TEST(Pyramid, ATilesHierarchyBoundsTheFullResolutionVertexByVertex) {
  const Heightfield field = makeField(203, 171, 13);
  TempFolder folder;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "lod.pyr"));
  ASSERT_NE(pyramid, nullptr);
  const BlockLayout& layout = pyramid->layout();
  std::size_t vertices = 0, tighter = 0;
  forEachTile(*pyramid, [&](const NodeId& node, const PyramidTile& tile) {
    if (node.level == 0) return;
    const BlockFootprint fp = layout.interior(node);
    auto exact = BlockLod::build(field, fp);
    if (!exact) return;  // no whole cell inside the DEM at this stride
    const auto perCell = BlockLod::buildFromLevel(tile.samples, fp, tile.cellResidual).value();
    const auto uniform = BlockLod::buildFromLevel(tile.samples, fp, pyramid->node(node).residual).value();
    EXPECT_GE(perCell.maxError(), exact->maxError()) << name(node);
    EXPECT_GE(perCell.floorError(), exact->floorError()) << name(node);
    EXPECT_LE(perCell.maxError(), uniform.maxError()) << name(node);
    for (int j = 0; j <= exact->cellsY(); ++j)
      for (int i = 0; i <= exact->cellsX(); ++i) {
        ASSERT_GE(perCell.vertexError(i, j), exact->vertexError(i, j)) << name(node) << " vertex " << i << "," << j;
        ASSERT_LE(perCell.vertexError(i, j), uniform.vertexError(i, j)) << name(node) << " vertex " << i << "," << j;
        ++vertices;
        tighter += perCell.vertexError(i, j) < uniform.vertexError(i, j);
      }
  });
  EXPECT_GT(tighter, vertices / 4);
}

TEST(Pyramid, TilesHoldTheStridedSamplesOfTheirFootprint) {
  const Heightfield field = makeField(170, 140, 5);
  TempFolder folder;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "t.pyr"));
  ASSERT_NE(pyramid, nullptr);
  const BlockLayout& layout = pyramid->layout();
  forEachTile(*pyramid, [&](const NodeId& node, const PyramidTile& tile) {
    const SampleRect area = layout.footprint(node);
    const int s = layout.stride(node);
    EXPECT_EQ(tile.node, node);
    ASSERT_EQ(tile.samples.width, (area.x1 - area.x0) / s + 1) << name(node);
    ASSERT_EQ(tile.samples.height, (area.y1 - area.y0) / s + 1) << name(node);
    EXPECT_EQ(tile.samples.spacingX, field.spacingX * s);
    for (int j = 0; j < tile.samples.height; ++j)
      for (int i = 0; i < tile.samples.width; ++i)
        ASSERT_EQ(tile.samples.at(i, j), field.at(area.x0 + i * s, area.y0 + j * s)) << name(node);
  });
  for (int y = 0; y < field.height; ++y) EXPECT_EQ(pyramid->eastBorder()[std::size_t(y)], field.at(field.width - 1, y));
  for (int x = 0; x < field.width; ++x)
    EXPECT_EQ(pyramid->northBorder()[std::size_t(x)], field.at(x, field.height - 1));
}

TEST(Pyramid, GivesBackTheFullResolution) {
  const Heightfield field = makeField(211, 150, 6);
  TempFolder folder;
  const fs::path path = buildOrFail(field, folder.path() / "full.pyr");
  EXPECT_TRUE(looksLikePyramid(path));
  auto pyramid = openOrFail(path);
  ASSERT_NE(pyramid, nullptr);
  auto back = readFullResolution(*pyramid);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->width, field.width);
  EXPECT_EQ(back->height, field.height);
  EXPECT_EQ(back->spacingY, field.spacingY);
  EXPECT_TRUE(back->heights == field.heights);
}

TEST(Pyramid, GivesBackAnyWindowOfTheFullResolution) {
  const Heightfield field = makeField(211, 150, 6);
  TempFolder folder;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "window.pyr"));
  ASSERT_NE(pyramid, nullptr);
  // Windows on block edges, inside one block, across many, and touching the DEM's far edges.
  for (const SampleRect window : {SampleRect{0, 0, 1, 1}, SampleRect{32, 64, 96, 128}, SampleRect{33, 5, 40, 9},
                                  SampleRect{7, 3, 210, 149}, SampleRect{190, 100, 210, 149}}) {
    auto part = readWindow(*pyramid, window);
    ASSERT_TRUE(part.ok()) << part.error().message;
    ASSERT_EQ(part->width, window.x1 - window.x0 + 1);
    ASSERT_EQ(part->height, window.y1 - window.y0 + 1);
    for (int y = window.y0; y <= window.y1; ++y)
      for (int x = window.x0; x <= window.x1; ++x)
        ASSERT_EQ(part->at(x - window.x0, y - window.y0), field.at(x, y)) << x << "," << y;
  }
  for (const SampleRect outside :
       {SampleRect{-1, 0, 5, 5}, SampleRect{0, 0, 211, 5}, SampleRect{4, 4, 4, 9}, SampleRect{9, 9, 3, 3}}) {
    auto refused = readWindow(*pyramid, outside);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(int(refused.error().kind), int(ErrorKind::InvalidArgument));
  }
}

TEST(Pyramid, ATileBuildsTheSameHierarchyAsTheFullResolutionAtLevelZero) {
  const Heightfield field = makeField(100, 100, 3);
  TempFolder folder;
  auto pyramid = openOrFail(buildOrFail(field, folder.path() / "l0.pyr"));
  ASSERT_NE(pyramid, nullptr);
  PyramidTile tile;
  const NodeId node{0, 1, 1};
  ASSERT_TRUE(pyramid->readTile(node, tile).ok());
  const BlockFootprint fp = pyramid->layout().interior(node);
  const auto fromTile = BlockLod::buildFromLevel(tile.samples, fp, 0.0f).value();
  const auto fromField = BlockLod::build(field, fp).value();
  EXPECT_EQ(fromTile.maxError(), fromField.maxError());
  EXPECT_EQ(fromTile.floorError(), fromField.floorError());
  RtinScratch scratch;
  for (float tau : {0.0f, 0.5f, 3.0f, 20.0f}) {
    BlockMesh a, b;
    fromTile.extractThreshold(tau, a, scratch);
    fromField.extractThreshold(tau, b, scratch);
    EXPECT_EQ(a.indices, b.indices) << "tau " << tau;
    EXPECT_EQ(a.maxError, b.maxError) << "tau " << tau;
    EXPECT_EQ(a.vertices.size(), b.vertices.size()) << "tau " << tau;
  }
}

TEST(Pyramid, TheResultDoesNotDependOnThreads) {
  const Heightfield field = makeField(240, 200, 8);
  TempFolder folder;
  core::ThreadPool pool(3);
  PyramidBuildOptions threaded;
  threaded.pool = &pool;
  const fs::path a = buildOrFail(field, folder.path() / "a.pyr");
  const fs::path b = buildOrFail(field, folder.path() / "b.pyr", threaded);
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string bytesA((std::istreambuf_iterator<char>(fa)), {}), bytesB((std::istreambuf_iterator<char>(fb)), {});
  EXPECT_EQ(bytesA.size(), fs::file_size(a));
  EXPECT_TRUE(bytesA == bytesB);
}

// Flips one byte of a file in place.
void flipByte(const fs::path& path, std::uint64_t offset) {
  std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
  file.seekg(std::streamoff(offset));
  char c = 0;
  file.get(c);
  file.seekp(std::streamoff(offset));
  file.put(char(c ^ 0x10));
}

TEST(Pyramid, ACorruptTileIsAnErrorNamingTheFileAndNode) {
  const Heightfield field = makeField(140, 140, 9);
  TempFolder folder;
  const fs::path path = buildOrFail(field, folder.path() / "bad.pyr");
  const NodeId victim{0, 2, 1};
  std::uint64_t slotOffset = 0;
  {
    auto pyramid = openOrFail(path);
    ASSERT_NE(pyramid, nullptr);
    slotOffset = pyramid->header().tilesOffset + pyramid->nodeIndex(victim) * pyramid->header().tileSlotBytes;
  }
  flipByte(path, slotOffset + 16 + 4 * 40);  // a sample
  auto pyramid = openOrFail(path);           // the header and tables are intact
  ASSERT_NE(pyramid, nullptr);
  PyramidTile tile;
  const Status status = pyramid->readTile(victim, tile);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(status.error().message.find(path.string()), std::string::npos) << status.error().message;
  EXPECT_NE(status.error().message.find("level 0, 2, 1"), std::string::npos) << status.error().message;
  EXPECT_TRUE(pyramid->readTile(NodeId{0, 1, 1}, tile).ok());  // the others still read
}

TEST(Pyramid, ACorruptHeaderNodeTableOrBorderDoesNotOpen) {
  const Heightfield field = makeField(140, 140, 9);
  TempFolder folder;
  const fs::path clean = buildOrFail(field, folder.path() / "clean.pyr");
  std::uint64_t nodesOffset = 0, borderOffset = 0;
  {
    auto pyramid = openOrFail(clean);
    ASSERT_NE(pyramid, nullptr);
    nodesOffset = pyramid->header().nodesOffset;
    borderOffset = pyramid->header().borderOffset;
  }
  for (std::uint64_t offset : {std::uint64_t(0), std::uint64_t(20), nodesOffset + 30, borderOffset + 8}) {
    const fs::path copy = folder.path() / ("c" + std::to_string(offset) + ".pyr");
    fs::copy_file(clean, copy);
    flipByte(copy, offset);
    auto pyramid = Pyramid::open(copy);
    ASSERT_FALSE(pyramid.ok()) << "byte " << offset;
    EXPECT_EQ(pyramid.error().kind, ErrorKind::InvalidData);
    EXPECT_NE(pyramid.error().message.find(copy.string()), std::string::npos) << pyramid.error().message;
  }
}

TEST(Pyramid, ATruncatedPyramidDoesNotOpen) {
  const Heightfield field = makeField(140, 140, 9);
  TempFolder folder;
  const fs::path path = buildOrFail(field, folder.path() / "short.pyr");
  const auto size = fs::file_size(path);
  for (std::uintmax_t keep : {size - 1, size / 2, std::uintmax_t(100), std::uintmax_t(0)}) {
    fs::resize_file(path, keep);
    auto pyramid = Pyramid::open(path);
    ASSERT_FALSE(pyramid.ok()) << keep;
    EXPECT_NE(pyramid.error().message.find(path.string()), std::string::npos) << pyramid.error().message;
  }
}

// A source whose rows fail part way, as a truncated DEM does.
class FailingRows final : public HeightRows {
 public:
  explicit FailingRows(const Heightfield& field, int failAt) : m_rows(field), m_failAt(failAt) {}
  int width() const override { return m_rows.width(); }
  int height() const override { return m_rows.height(); }
  double spacingX() const override { return m_rows.spacingX(); }
  double spacingY() const override { return m_rows.spacingY(); }
  Status readRows(int y0, int count, std::span<float> out) override {
    if (y0 + count > m_failAt) return makeError(ErrorKind::InvalidData, "source.tif: cut short at row 150");
    return m_rows.readRows(y0, count, out);
  }

 private:
  HeightfieldRows m_rows;
  int m_failAt;
};

TEST(Pyramid, AFailedPrepLeavesNothingBehind) {
  Heightfield field = makeField(200, 200, 4);
  TempFolder folder;
  const fs::path out = folder.path() / "never.pyr";
  FailingRows failing(field, 150);
  auto report = buildPyramid(failing, out);
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.error().message.find("source.tif"), std::string::npos);
  field.at(17, 120) = std::nanf("");
  HeightfieldRows withNaN(field);
  PyramidBuildOptions named;
  named.sourceName = "nan.tif";
  report = buildPyramid(withNaN, out, named);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.error().kind, ErrorKind::InvalidData);
  EXPECT_NE(report.error().message.find("nan.tif: sample (17, 120)"), std::string::npos) << report.error().message;
  EXPECT_TRUE(fs::is_empty(folder.path())) << "a partial file was left";
}

TEST(Pyramid, AnUnfinishedFileDoesNotOpen) {
  // What a killed prep leaves before its rename: everything but the magic.
  const Heightfield field = makeField(120, 120, 2);
  TempFolder folder;
  const fs::path path = buildOrFail(field, folder.path() / "killed.pyr");
  {
    std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
    file.write("\0\0\0\0\0\0\0\0", 8);
  }
  auto pyramid = Pyramid::open(path);
  ASSERT_FALSE(pyramid.ok());
  EXPECT_NE(pyramid.error().message.find("not a Polder pyramid"), std::string::npos) << pyramid.error().message;
}

TEST(Pyramid, BadOptionsAreRefused) {
  const Heightfield field = makeField(64, 64, 1);
  TempFolder folder;
  HeightfieldRows rows(field);
  PyramidBuildOptions options;
  options.k = 9;
  auto report = buildPyramid(rows, folder.path() / "k.pyr", options);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.error().kind, ErrorKind::InvalidArgument);
  report = buildPyramid(rows, folder.path() / "no-such-folder" / "x.pyr");
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.error().kind, ErrorKind::Io);
  EXPECT_NE(report.error().message.find("x.pyr"), std::string::npos) << report.error().message;
}

}  // namespace
}  // namespace polder::terrain
