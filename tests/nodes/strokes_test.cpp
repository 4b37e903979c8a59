// geobrush.strokes: dabs from graph rows, and which points of the domain they paint.
#include <gtest/gtest.h>

#include "direct_context.hpp"
#include "strokes.hpp"
#include "test_support.hpp"

using namespace geobrush;

TEST(Strokes, ReadsRowsInOrderAndWritesThemBack) {
  const std::vector<double> rows = {0.5, -0.25, 0.1, 1, 0.6, -0.2, 0.05, -1};
  const Strokes strokes = strokesFromRows(rows);
  ASSERT_EQ(strokes.dabs.size(), 2u);
  EXPECT_EQ(strokes.dabs[0], (Dab{{0.5, -0.25}, 0.1, false}));
  EXPECT_EQ(strokes.dabs[1], (Dab{{0.6, -0.2}, 0.05, true}));
  EXPECT_EQ(rowsFromStrokes(strokes), rows);
}

// An eraser dab removes what an earlier dab painted; painting over it again restores it.
TEST(Strokes, LaterDabsOverrideEarlierOnes) {
  Strokes strokes = strokesFromRows({0, 0, 1, 1, 0.5, 0, 0.25, -1});
  EXPECT_TRUE(strokes.contains({0, 0}));
  EXPECT_TRUE(strokes.contains({-0.99, 0}));
  EXPECT_FALSE(strokes.contains({0.5, 0}));
  EXPECT_FALSE(strokes.contains({0.74, 0}));
  EXPECT_TRUE(strokes.contains({0.76, 0}));
  EXPECT_FALSE(strokes.contains({1.01, 0}));
  strokes.dabs.push_back({{0.5, 0}, 0.1, false});
  EXPECT_TRUE(strokes.contains({0.5, 0}));
  EXPECT_FALSE(strokes.contains({0.5, 0.2}));
}

TEST(Strokes, NoDabsPaintNothing) {
  EXPECT_FALSE(Strokes().contains({0, 0}));
}

TEST(Strokes, ContentHashFollowsEveryField) {
  const Strokes base = strokesFromRows({0, 0, 1, 1});
  for (const auto& rows : std::vector<std::vector<double>>{
           {0.1, 0, 1, 1}, {0, 0.1, 1, 1}, {0, 0, 1.1, 1}, {0, 0, 1, -1}, {0, 0, 1, 1, 0, 0, 1, 1}})
    EXPECT_NE(strokesFromRows(rows).contentHash(), base.contentHash());
  EXPECT_EQ(strokesFromRows({0, 0, 1, 1}).contentHash(), base.contentHash());
}

TEST(Strokes, RefusesBadRowsNamingTheDab) {
  auto message = [](const std::vector<double>& rows) {
    try {
      strokesFromRows(rows);
    } catch (const StrokesError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_TRUE(test::contains(message({0, 0, 1}), "rows of 4 numbers"));
  EXPECT_TRUE(test::contains(message({0, 0, 1, 1, 0, 0, 0, 1}), "dab 2 has a radius <= 0"));
  EXPECT_TRUE(test::contains(message({0, 0, 1, 0.5}), "dab 1 has mode"));
  EXPECT_TRUE(test::contains(message({0, NAN, 1, 1}), "dab 1 has a non-finite number"));
}

TEST(StrokesNode, NamesTheParamOfBadDabs) {
  const NodeType* type = test::registry().find("geobrush.strokes");
  ASSERT_TRUE(type);
  ParamMap params;
  params["dabs"] = std::vector<double>{0, 0, -1, 1};
  test::DirectContext ctx(*type, {}, params);
  try {
    type->create()->compute(ctx);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'dabs'");
    EXPECT_TRUE(test::contains(e.what(), "radius"));
  }
}
