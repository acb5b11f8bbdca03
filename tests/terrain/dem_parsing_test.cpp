#include <gtest/gtest.h>

#include <polder/terrain/dem_parsing.hpp>

namespace polder::terrain {
namespace {

TEST(ParseRawLayout, ReadsSizeTypeAndByteOrder) {
  auto layout = parseRawLayout("1024x512:u16");
  ASSERT_TRUE(layout.ok()) << layout.error().message;
  EXPECT_EQ(layout->width, 1024);
  EXPECT_EQ(layout->height, 512);
  EXPECT_EQ(layout->type, SampleType::U16);
  EXPECT_FALSE(layout->bigEndian);

  layout = parseRawLayout("3x7:i16:be");
  ASSERT_TRUE(layout.ok());
  EXPECT_EQ(layout->type, SampleType::I16);
  EXPECT_TRUE(layout->bigEndian);

  layout = parseRawLayout("5x5:f32:le");
  ASSERT_TRUE(layout.ok());
  EXPECT_EQ(layout->type, SampleType::F32);
  EXPECT_FALSE(layout->bigEndian);
}

TEST(ParseRawLayout, RoundTripsThroughItsName) {
  for (const char* text : {"1x1:u16:le", "513x257:f32:be", "2x9:i16:le"}) {
    const auto layout = parseRawLayout(text);
    ASSERT_TRUE(layout.ok()) << text;
    EXPECT_EQ(rawLayoutName(*layout), text);
  }
}

TEST(ParseRawLayout, RejectsMalformedTextNamingIt) {
  for (const char* text : {"", "1024", "1024x1024", "1024x:u16", "x5:u16", "0x5:u16", "5x0:u16", "-5x5:u16", "5x5:u8",
                           "5x5:u16:middle", "5x5:u16:le:x", "99999999999x5:u16", "5 x5:u16", "5x5u16"}) {
    const auto layout = parseRawLayout(text);
    ASSERT_FALSE(layout.ok()) << "accepted '" << text << "'";
    EXPECT_EQ(layout.error().kind, ErrorKind::InvalidArgument);
    const std::string quoted = std::string(1, '\'').append(text).append(1, '\'');
    EXPECT_NE(layout.error().message.find(quoted), std::string::npos) << layout.error().message;
    EXPECT_NE(layout.error().message.find("WxH:u16|i16|f32"), std::string::npos);
  }
}

TEST(ParseHeightEncoding, ReadsEveryNameAndRejectsOthers) {
  EXPECT_EQ(*parseHeightEncoding("auto"), HeightEncoding::Auto);
  EXPECT_EQ(*parseHeightEncoding("greyscale"), HeightEncoding::Greyscale);
  EXPECT_EQ(*parseHeightEncoding("terrain-rgb"), HeightEncoding::TerrainRgb);
  EXPECT_EQ(*parseHeightEncoding("terrarium"), HeightEncoding::Terrarium);
  for (HeightEncoding e :
       {HeightEncoding::Auto, HeightEncoding::Greyscale, HeightEncoding::TerrainRgb, HeightEncoding::Terrarium})
    EXPECT_EQ(*parseHeightEncoding(heightEncodingName(e)), e);

  const auto bad = parseHeightEncoding("mapbox");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().kind, ErrorKind::InvalidArgument);
  EXPECT_NE(bad.error().message.find("'mapbox'"), std::string::npos);
  EXPECT_FALSE(parseHeightEncoding("").ok());
  EXPECT_FALSE(parseHeightEncoding("Terrarium ").ok());
}

}  // namespace
}  // namespace polder::terrain
