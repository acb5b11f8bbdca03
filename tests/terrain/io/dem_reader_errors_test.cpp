// Bad input never crashes: every rule returns an error of the right kind whose one-line
// message names the file and the problem.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <polder/terrain/dem_reader.hpp>
#include <polder/terrain/dem_rows.hpp>
#include <polder/terrain/dem_validation.hpp>

#include "dem_test_files.hpp"
#include "test_support.hpp"

namespace polder::terrain {
namespace {

using test::ScratchDir;

// Reads, expects failure of `kind`, and checks the message names the file and `problem`.
void expectError(const std::filesystem::path& path, const DemOptions& options, ErrorKind kind,
                 const std::string& problem) {
  const auto dem = readDem(path, options);
  ASSERT_FALSE(dem.ok()) << path << " was read";
  const std::string& message = dem.error().message;
  EXPECT_EQ(int(dem.error().kind), int(kind)) << message;
  EXPECT_NE(message.find(path.string()), std::string::npos) << "file not named: " << message;
  EXPECT_NE(message.find(problem), std::string::npos) << "expected '" << problem << "' in: " << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
}

std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xffffffffu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string bigEndian32(std::uint32_t value) {
  return {char(value >> 24), char(value >> 16), char(value >> 8), char(value)};
}

std::string pngChunk(const std::string& type, const std::string& data) {
  return bigEndian32(std::uint32_t(data.size())) + type + data + bigEndian32(crc32(type + data));
}

// A PNG whose header claims width x height 16-bit grey samples (its pixels are missing).
std::string pngHeaderOnly(std::uint32_t width, std::uint32_t height) {
  const std::string ihdr = bigEndian32(width) + bigEndian32(height) + std::string("\x10\x00\x00\x00\x00", 5);
  const std::string emptyStream("\x78\x9c\x03\x00\x00\x00\x00\x01", 8);  // zlib's whole stream of no bytes
  return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) + pngChunk("IDAT", emptyStream) +
         pngChunk("IEND", "");
}

// A little-endian 8-bit grey TIFF with one strip at offset 256 of `stripBytes`, followed by
// `present` bytes of data (fewer than the strip when truncated).
std::string handMadeTiff(std::uint32_t width, std::uint32_t height, std::uint32_t stripBytes, std::size_t present) {
  std::string tiff = "II*" + std::string(1, '\0') + test::littleEndian(8, 4) +
                     test::tiffDirectory({{256, 4, 1, width},
                                          {257, 4, 1, height},
                                          {258, 3, 1, 8},
                                          {259, 3, 1, 1},
                                          {262, 3, 1, 1},
                                          {273, 4, 1, 256},
                                          {277, 3, 1, 1},
                                          {278, 4, 1, height},
                                          {279, 4, 1, stripBytes}});
  tiff.resize(256, '\0');
  tiff += std::string(present, '\x40');
  return tiff;
}

TEST(ReadDemErrors, MissingFileAndDirectory) {
  ScratchDir dir;
  expectError(dir.file("absent.png"), {}, ErrorKind::Io, "no such file");
  expectError(dir.path(), {}, ErrorKind::Io, "is a directory");
}

TEST(ReadDemErrors, EmptyFile) {
  ScratchDir dir;
  test::writeFile(dir.file("empty.png"), "");
  expectError(dir.file("empty.png"), {}, ErrorKind::InvalidData, "empty");
  test::writeFile(dir.file("empty.hgt"), "");
  expectError(dir.file("empty.hgt"), {}, ErrorKind::InvalidData, "empty");
}

TEST(ReadDemErrors, UnknownFormat) {
  ScratchDir dir;
  test::writeFile(dir.file("notes.txt"), "these are not heights\n");
  expectError(dir.file("notes.txt"), {}, ErrorKind::Unsupported, "unknown DEM format");
  test::writeFile(dir.file("model.obj"), "v 0 0 0\n");
  expectError(dir.file("model.obj"), {}, ErrorKind::Unsupported, "unknown DEM format");
}

TEST(ReadDemErrors, ImageExtensionWithoutImageContent) {
  ScratchDir dir;
  test::writeFile(dir.file("fake.png"), "GIF89a not a png at all");
  expectError(dir.file("fake.png"), {}, ErrorKind::InvalidData, "PNG signature");
  test::writeFile(dir.file("fake.tif"), "nothing");
  expectError(dir.file("fake.tif"), {}, ErrorKind::InvalidData, "TIFF header");
  test::writeFile(dir.file("fake.exr"), "nothing");
  expectError(dir.file("fake.exr"), {}, ErrorKind::InvalidData, "EXR");
}

TEST(ReadDemErrors, TruncatedAndCorruptPng) {
  ScratchDir dir;
  std::mt19937 random(3);
  std::vector<std::uint16_t> noise(64 * 64);
  for (auto& v : noise) v = std::uint16_t(random());
  test::writeImage(dir.file("good.png"), 64, 64, 1, noise);
  const std::string bytes = test::readBytes(dir.file("good.png"));
  ASSERT_GT(bytes.size(), 4000u);

  test::writeFile(dir.file("truncated.png"), bytes.substr(0, bytes.size() * 6 / 10));
  expectError(dir.file("truncated.png"), {}, ErrorKind::InvalidData, "truncated PNG: chunk IDAT");

  test::writeFile(dir.file("header_only.png"), bytes.substr(0, 20));
  expectError(dir.file("header_only.png"), {}, ErrorKind::InvalidData, "truncated PNG: chunk IHDR");

  test::writeFile(dir.file("no_end.png"), bytes.substr(0, bytes.size() - 12));  // IEND cut off
  expectError(dir.file("no_end.png"), {}, ErrorKind::InvalidData, "before the IEND chunk");

  std::string corrupt = bytes;
  for (std::size_t i = 200; i < 260; ++i) corrupt[i] = char(corrupt[i] ^ 0x5a);
  test::writeFile(dir.file("corrupt.png"), corrupt);
  expectError(dir.file("corrupt.png"), {}, ErrorKind::InvalidData, "corrupt PNG: chunk IDAT at byte");
}

// Compressed data that is corrupt inside chunks and strips whose framing is intact: the
// decoders' complaints become errors (never garbage heights, never a line from libpng), in
// the whole-raster reader and the row reader alike.
TEST(ReadDemErrors, CorruptCompressedDataWithIntactFraming) {
  ScratchDir dir;
  std::vector<std::uint16_t> ramp(64 * 64);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = std::uint16_t(i * 7);
  test::writeImage(dir.file("good.png"), 64, 64, 1, ramp);
  const std::string png = test::readBytes(dir.file("good.png"));
  const std::size_t idat = png.find("IDAT") - 4;
  const std::uint32_t length = std::uint32_t(std::uint8_t(png[idat])) << 24 |
                               std::uint32_t(std::uint8_t(png[idat + 1])) << 16 |
                               std::uint32_t(std::uint8_t(png[idat + 2])) << 8 | std::uint8_t(png[idat + 3]);
  ASSERT_GT(length, 100u);
  std::string data = png.substr(idat + 8, length);
  const auto withData = [&](const std::string& replaced) {
    return png.substr(0, idat) + pngChunk("IDAT", replaced) + png.substr(idat + 12 + length);
  };
  std::string scrambled = data;
  for (std::size_t i = 20; i < 80; ++i) scrambled[i] = char(scrambled[i] ^ 0x33);
  test::writeFile(dir.file("scrambled.png"), withData(scrambled));
  test::writeFile(dir.file("unfinished.png"), withData(data.substr(0, data.size() / 2)));
  for (const char* name : {"scrambled.png", "unfinished.png"}) {
    expectError(dir.file(name), {}, ErrorKind::InvalidData, "corrupt PNG: the image data");
    const auto rows = openDemRows(dir.file(name), {});
    ASSERT_FALSE(rows.ok()) << name;
    EXPECT_EQ(rows.error().kind, ErrorKind::InvalidData);
  }

  // LZW strips: OpenImageIO reports success and only records libtiff's error.
  std::vector<std::uint16_t> noise(64 * 64);
  std::mt19937 random(5);
  for (auto& v : noise) v = std::uint16_t(random());
  test::writeImage(dir.file("lzw.tif"), 64, 64, 1, noise, {0, "lzw"});
  ASSERT_TRUE(readDem(dir.file("lzw.tif"), {}).ok());
  std::string tiff = test::readBytes(dir.file("lzw.tif"));
  for (std::size_t i = tiff.size() / 4; i < tiff.size() / 4 + 8; ++i) tiff[i] = char(tiff[i] ^ 0xa5);
  test::writeFile(dir.file("lzw_damaged.tif"), tiff);
  expectError(dir.file("lzw_damaged.tif"), {}, ErrorKind::InvalidData, "cannot read the pixels");
  auto rows = openDemRows(dir.file("lzw_damaged.tif"), {});
  if (rows.ok()) {
    std::vector<float> band(std::size_t(64) * 64);
    Status read = (*rows)->readRows(0, 64, band);
    ASSERT_FALSE(read.ok());
    EXPECT_NE(read.error().message.find("cannot read the pixels"), std::string::npos) << read.error().message;
  }
}

TEST(ReadDemErrors, TruncatedAndCorruptTiff) {
  ScratchDir dir;
  test::writeFile(dir.file("ok.tif"), handMadeTiff(16, 16, 256, 256));
  ASSERT_TRUE(readDem(dir.file("ok.tif"), {}).ok()) << readDem(dir.file("ok.tif"), {}).error().message;

  // OpenImageIO would read the missing bytes as zeros without complaint.
  test::writeFile(dir.file("short_strip.tif"), handMadeTiff(16, 16, 256, 100));
  expectError(dir.file("short_strip.tif"), {}, ErrorKind::InvalidData, "truncated TIFF: strip 0 ends at byte 512");

  test::writeFile(dir.file("garbage.tif"), "II*" + std::string(1, '\0') + std::string(64, '\xff'));
  expectError(dir.file("garbage.tif"), {}, ErrorKind::InvalidData, "cannot read");

  std::vector<std::int16_t> values(64 * 64, 7);
  test::writeImage(dir.file("tiled.tif"), 64, 64, 1, values, {16, "zip"});
  const std::string bytes = test::readBytes(dir.file("tiled.tif"));
  test::writeFile(dir.file("tiled_cut.tif"), bytes.substr(0, bytes.size() / 2));
  expectError(dir.file("tiled_cut.tif"), {}, ErrorKind::InvalidData, "truncated TIFF: tile");

  // Complete, but the deflate data of the first tile is garbage.
  std::vector<std::int16_t> ramp(64 * 64);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = std::int16_t(i);
  test::writeGeoTiff(dir.file("deflate.tif"), 64, 64, ramp, {}, true);
  std::string damaged = test::readBytes(dir.file("deflate.tif"));
  for (std::size_t i = 8; i < 48; ++i) damaged[i] = char(0xa5);
  test::writeFile(dir.file("damaged.tif"), damaged);
  expectError(dir.file("damaged.tif"), {}, ErrorKind::InvalidData, "cannot read the pixels");
}

TEST(ReadDemErrors, NaNAndInfinityAreRejected) {
  ScratchDir dir;
  std::vector<float> values(8 * 8, 1.0f);
  values[2 * 8 + 5] = std::numeric_limits<float>::quiet_NaN();
  test::writeImage(dir.file("nan.tif"), 8, 8, 1, values);
  expectError(dir.file("nan.tif"), {}, ErrorKind::InvalidData, "(column 5, row 2 from the north) is NaN");

  values[2 * 8 + 5] = std::numeric_limits<float>::infinity();
  test::writeImage(dir.file("inf.exr"), 8, 8, 1, values);
  expectError(dir.file("inf.exr"), {}, ErrorKind::InvalidData, "is infinite");
}

TEST(ReadDemErrors, AllVoids) {
  ScratchDir dir;
  std::vector<std::int16_t> values(10 * 10, -32768);
  test::writeImage(dir.file("voids.tif"), 10, 10, 1, values);
  expectError(dir.file("voids.tif"), {}, ErrorKind::InvalidData, "all 100 samples are no-data");
}

TEST(ReadDemErrors, AbsurdDimensionsAreRefusedBeforeAllocating) {
  ScratchDir dir;
  test::writeFile(dir.file("huge.png"), pngHeaderOnly(100000, 100000));
  expectError(dir.file("huge.png"), {}, ErrorKind::OutOfMemory, "100000 x 100000 samples is more than");

  test::writeFile(dir.file("huge.tif"), handMadeTiff(100000, 100000, 1000, 1000));
  expectError(dir.file("huge.tif"), {}, ErrorKind::OutOfMemory, "100000 x 100000 samples is more than");

  test::writeFile(dir.file("huge.r16"), std::string(64, '\0'));
  DemOptions options;
  options.raw = RawLayout{100000, 100000, SampleType::U16, false};
  expectError(dir.file("huge.r16"), options, ErrorKind::OutOfMemory, "100000 x 100000 samples is more than");

  // Under 2^31 samples but (on most machines) over the physical memory.
  const std::uint64_t side = 46000;
  if (physicalMemoryBytes() < side * side * demBytesPerSample(2)) {
    test::writeFile(dir.file("big.png"), pngHeaderOnly(std::uint32_t(side), std::uint32_t(side)));
    expectError(dir.file("big.png"), {}, ErrorKind::OutOfMemory, "physical memory");
  }
}

TEST(ReadDemErrors, MemoryLimit) {
  ScratchDir dir;
  std::vector<std::uint16_t> values(64 * 64, 9);
  test::writeImage(dir.file("small.png"), 64, 64, 1, values);
  DemOptions options;
  options.memoryLimitBytes = 10000;
  expectError(dir.file("small.png"), options, ErrorKind::OutOfMemory, "more than the memory limit of");
  options.memoryLimitBytes = 1 << 20;
  EXPECT_TRUE(readDem(dir.file("small.png"), options).ok());
}

TEST(ReadDemErrors, RawFiles) {
  ScratchDir dir;
  test::writeFile(dir.file("heights.r16"), std::string(2 * 10 * 10 - 2, '\0'));
  expectError(dir.file("heights.r16"), {}, ErrorKind::InvalidArgument, "needs its layout");
  DemOptions options;
  options.raw = RawLayout{10, 10, SampleType::U16, false};
  expectError(dir.file("heights.r16"), options, ErrorKind::InvalidData,
              "raw layout 10x10:u16:le needs 200 bytes but the file has 198");
  options.raw = RawLayout{0, 10, SampleType::U16, false};
  expectError(dir.file("heights.r16"), options, ErrorKind::InvalidArgument, "no samples");
}

TEST(ReadDemErrors, HgtOfTheWrongSize) {
  ScratchDir dir;
  test::writeFile(dir.file("N46W122.hgt"), std::string(1000, '\0'));
  expectError(dir.file("N46W122.hgt"), {}, ErrorKind::InvalidData, "2884802");
}

TEST(ReadDemErrors, BadOptions) {
  ScratchDir dir;
  std::vector<std::uint8_t> grey(4 * 4, 10);
  test::writeImage(dir.file("grey.png"), 4, 4, 1, grey);
  DemOptions options;
  options.spacingM = -5.0;
  expectError(dir.file("grey.png"), options, ErrorKind::InvalidArgument, "spacing");
  options = {};
  options.zScale = std::numeric_limits<double>::quiet_NaN();
  expectError(dir.file("grey.png"), options, ErrorKind::InvalidArgument, "height scale");
  options = {};
  options.encoding = HeightEncoding::TerrainRgb;
  expectError(dir.file("grey.png"), options, ErrorKind::InvalidArgument, "needs an 8-bit RGB(A) image");
}

TEST(ReadDemErrors, RgbThatIsNoKnownEncoding) {
  ScratchDir dir;
  std::vector<std::uint8_t> colours;
  for (int i = 0; i < 16 * 16; ++i) colours.insert(colours.end(), {220, std::uint8_t(i), 40});
  test::writeImage(dir.file("photo.png"), 16, 16, 3, colours);
  expectError(dir.file("photo.png"), {}, ErrorKind::InvalidData, "neither Terrain-RGB");
}

TEST(ReadDemErrors, RandomDamageNeverCrashes) {
  // Flipped bytes, cut files: each read either succeeds or fails with a proper message.
  ScratchDir dir;
  std::vector<std::int16_t> heights(40 * 30);
  for (std::size_t i = 0; i < heights.size(); ++i) heights[i] = std::int16_t(i * 7 % 3000);
  std::vector<float> floats(heights.begin(), heights.end());
  test::writeImage(dir.file("a.png"), 40, 30, 1, std::vector<std::uint16_t>(heights.begin(), heights.end()));
  test::writeImage(dir.file("a.tif"), 40, 30, 1, heights, {16, "zip"});
  test::writeImage(dir.file("a.exr"), 40, 30, 1, floats);
  std::mt19937 random(11);
  for (const char* name : {"a.png", "a.tif", "a.exr"}) {
    const std::string original = test::readBytes(dir.file(name));
    const auto damagedPath = dir.file(std::string("damaged_") + name);
    for (int attempt = 0; attempt < 40; ++attempt) {
      std::string bytes = original;
      if (attempt % 2) {
        bytes.resize(random() % bytes.size());
      } else {
        for (int k = 0; k < 4; ++k) bytes[random() % bytes.size()] = char(random());
      }
      test::writeFile(damagedPath, bytes);
      const auto dem = readDem(damagedPath, {});
      if (dem.ok()) continue;
      EXPECT_NE(dem.error().message.find(damagedPath.string()), std::string::npos) << dem.error().message;
      EXPECT_EQ(dem.error().message.find('\n'), std::string::npos) << dem.error().message;
    }
  }
}

}  // namespace
}  // namespace polder::terrain
