#include <polder/terrain/heightfield_crop.hpp>

#include <gtest/gtest.h>

namespace polder::terrain {
namespace {

TEST(HeightfieldCrop, CopiesTheRectangleWithItsSpacing) {
  Heightfield field(10, 8, 2.0, 3.0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 10; ++x) field.at(x, y) = float(100 * y + x);
  auto crop = cropHeightfield(field, 3, 2, 4, 5);
  ASSERT_TRUE(crop.ok());
  EXPECT_EQ(crop->width, 4);
  EXPECT_EQ(crop->height, 5);
  EXPECT_EQ(crop->spacingY, 3.0);
  EXPECT_EQ(crop->at(0, 0), 203.0f);
  EXPECT_EQ(crop->at(3, 4), 606.0f);
  auto centre = cropCentre(field, 4, 4);
  ASSERT_TRUE(centre.ok());
  EXPECT_EQ(centre->at(0, 0), field.at(3, 2));
}

TEST(HeightfieldCrop, RefusesRectanglesOutsideTheField) {
  Heightfield field(10, 8);
  EXPECT_FALSE(cropHeightfield(field, 8, 0, 4, 4).ok());
  EXPECT_FALSE(cropHeightfield(field, -1, 0, 4, 4).ok());
  EXPECT_FALSE(cropHeightfield(field, 0, 0, 1, 4).ok());
  const auto tooBig = cropCentre(field, 660, 660);
  ASSERT_FALSE(tooBig.ok());
  EXPECT_NE(tooBig.error().message.find("660 x 660"), std::string::npos);
}

}  // namespace
}  // namespace polder::terrain
