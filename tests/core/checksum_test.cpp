// CRC-32C: the published check values, and that a CRC continues across pieces.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <polder/checksum.hpp>

namespace polder::core {
namespace {

TEST(Crc32c, MatchesThePublishedCheckValues) {
  // RFC 3720 appendix B.4 and the CRC catalogue's check string.
  EXPECT_EQ(crc32c("123456789", 9), 0xE3069283u);
  const std::vector<std::uint8_t> zeros(32, 0x00), ones(32, 0xFF);
  EXPECT_EQ(crc32c(zeros.data(), zeros.size()), 0x8A9136AAu);
  EXPECT_EQ(crc32c(ones.data(), ones.size()), 0x62A8AB43u);
  std::vector<std::uint8_t> ascending(32);
  for (int i = 0; i < 32; ++i) ascending[std::size_t(i)] = std::uint8_t(i);
  EXPECT_EQ(crc32c(ascending.data(), ascending.size()), 0x46DD794Eu);
  EXPECT_EQ(crc32c(nullptr, 0), 0u);
}

TEST(Crc32c, ContinuesAcrossPiecesOfAnyAlignment) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += char('a' + (i * 7) % 26);
  const std::uint32_t whole = crc32c(text.data(), text.size());
  for (std::size_t cut : {std::size_t(1), std::size_t(3), std::size_t(8), std::size_t(13), std::size_t(999)}) {
    const std::uint32_t first = crc32c(text.data(), cut);
    EXPECT_EQ(crc32c(text.data() + cut, text.size() - cut, first), whole) << "cut at " << cut;
  }
}

TEST(Crc32c, DetectsEverySingleBitFlip) {
  std::vector<std::uint8_t> data(64);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = std::uint8_t(i * 31 + 5);
  const std::uint32_t reference = crc32c(data.data(), data.size());
  for (std::size_t bit = 0; bit < data.size() * 8; ++bit) {
    data[bit / 8] ^= std::uint8_t(1u << (bit % 8));
    EXPECT_NE(crc32c(data.data(), data.size()), reference) << "bit " << bit;
    data[bit / 8] ^= std::uint8_t(1u << (bit % 8));
  }
}

}  // namespace
}  // namespace polder::core
