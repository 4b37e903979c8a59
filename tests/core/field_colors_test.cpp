#include "geobrush/field_colors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace geobrush {
namespace {

TEST(FieldColors, SignedFieldsSpanASymmetricRangeAroundZero) {
  std::vector<double> values;
  for (int i = -50; i <= 100; ++i)
    values.push_back(0.01 * i);
  values.push_back(1e6);  // one spike does not set the range
  const FieldRange range = fieldRange(values);
  EXPECT_TRUE(range.diverging);
  EXPECT_EQ(range.low, -range.high);
  EXPECT_NEAR(range.high, 0.97, 0.02);
  const auto colors = fieldColors({0.0, -5.0, 5.0, std::nan("")}, range);
  EXPECT_EQ(colors[0][0], colors[0][1]);  // zero is the grey-white middle
  EXPECT_GT(colors[1][2], colors[1][0]);  // below: blue
  EXPECT_GT(colors[2][0], colors[2][2]);  // above: red
  EXPECT_EQ(colors[3], (Rgb{0.5f, 0.5f, 0.5f}));
}

TEST(FieldColors, OneSignedFieldsUseTheirOwnRangeAndConstantsGetOne) {
  std::vector<double> values;
  for (int i = 0; i <= 100; ++i)
    values.push_back(2.0 + i);
  const FieldRange range = fieldRange(values);
  EXPECT_FALSE(range.diverging);
  EXPECT_NEAR(range.low, 4.0, 1e-12);
  EXPECT_NEAR(range.high, 100.0, 1e-12);
  const auto colors = fieldColors({range.low, range.high}, range);
  EXPECT_LT(colors[0][0] + colors[0][1], colors[1][0] + colors[1][1]);  // dark to light

  const FieldRange constant = fieldRange(std::vector<double>(5, 3.0));
  EXPECT_DOUBLE_EQ(constant.low, 2.5);
  EXPECT_DOUBLE_EQ(constant.high, 3.5);
  const FieldRange none = fieldRange({std::nan("")});
  EXPECT_LT(none.low, none.high);
}

TEST(FieldColors, TheLegendIsDrawnAtTheBottomLeft) {
  Image image(320, 240);
  std::fill(image.rgba.begin(), image.rgba.end(), std::uint8_t(255));
  const Image blank = image;
  if (!drawFieldLegend(image, "h1", {-1.0, 1.0, true})) GTEST_SKIP() << "no font";
  bool topChanged = false, bottomLeftChanged = false;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const bool changed = std::memcmp(image.pixel(x, y), blank.pixel(x, y), 4) != 0;
      if (changed && y < image.height / 2) topChanged = true;
      if (changed && y > image.height / 2 && x < image.width / 2) bottomLeftChanged = true;
    }
  EXPECT_FALSE(topChanged);
  EXPECT_TRUE(bottomLeftChanged);
}

}  // namespace
}  // namespace geobrush
