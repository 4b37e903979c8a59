// Parameters (checks, coercion, text forms) and the hasher.
#include <gtest/gtest.h>

#include <cmath>

#include "geobrush/hash.hpp"
#include "geobrush/param.hpp"
#include "geobrush/values.hpp"

using namespace geobrush;

TEST(Params, CoercionAndRanges) {
  ParamDecl radius{.name = "radius",
                   .kind = ParamKind::Double,
                   .defaultValue = 1.0,
                   .doc = "r",
                   .min = 0.0,
                   .max = 10.0,
                   .choices = {},
                   .rowSize = 1};
  EXPECT_EQ(std::get<double>(coerceParam(radius, std::int64_t(3))), 3.0);
  EXPECT_THROW(coerceParam(radius, 11.0), std::invalid_argument);
  EXPECT_THROW(coerceParam(radius, std::string("x")), std::invalid_argument);
  EXPECT_THROW(coerceParam(radius, std::nan("")), std::invalid_argument);

  ParamDecl dabs{.name = "dabs",
                 .kind = ParamKind::DoubleList,
                 .defaultValue = std::vector<double>{},
                 .doc = "d",
                 .min = {},
                 .max = {},
                 .choices = {},
                 .rowSize = 4};
  EXPECT_NO_THROW(coerceParam(dabs, std::vector<double>{1, 2, 3, 4}));
  EXPECT_THROW(coerceParam(dabs, std::vector<double>{1, 2, 3}), std::invalid_argument);

  ParamDecl origin{.name = "origin",
                   .kind = ParamKind::Vec3,
                   .defaultValue = Vec3{0, 0, 0},
                   .doc = "o",
                   .min = {},
                   .max = {},
                   .choices = {},
                   .rowSize = 1};
  EXPECT_EQ(std::get<Vec3>(coerceParam(origin, std::vector<double>{1, 2, 3})), (Vec3{1, 2, 3}));
  EXPECT_THROW(coerceParam(origin, std::vector<double>{1, 2}), std::invalid_argument);
}

TEST(Params, TextForms) {
  ParamDecl shape{.name = "shape",
                  .kind = ParamKind::Enum,
                  .defaultValue = std::string("sphere"),
                  .doc = "s",
                  .min = {},
                  .max = {},
                  .choices = {"sphere", "torus"},
                  .rowSize = 1};
  EXPECT_EQ(std::get<std::string>(parseParamText(shape, "torus")), "torus");
  EXPECT_THROW(parseParamText(shape, "cube"), std::invalid_argument);
  ParamDecl count{.name = "n",
                  .kind = ParamKind::Int,
                  .defaultValue = std::int64_t(1),
                  .doc = "n",
                  .min = 1.0,
                  .max = 8.0,
                  .choices = {},
                  .rowSize = 1};
  EXPECT_EQ(std::get<std::int64_t>(parseParamText(count, "8")), 8);
  EXPECT_THROW(parseParamText(count, "9"), std::invalid_argument);
  EXPECT_THROW(parseParamText(count, "2.5"), std::invalid_argument);
  ParamDecl flag{.name = "f",
                 .kind = ParamKind::Bool,
                 .defaultValue = false,
                 .doc = "f",
                 .min = {},
                 .max = {},
                 .choices = {},
                 .rowSize = 1};
  EXPECT_EQ(std::get<bool>(parseParamText(flag, "true")), true);
  EXPECT_THROW(parseParamText(flag, "yes please"), std::invalid_argument);
  EXPECT_EQ(formatParam(Vec3{0.1, -2, 3e-9}), "0.1,-2,3e-09");
  EXPECT_EQ(formatParam(std::vector<double>{1, 2.5}), "1,2.5");
}

// A NUL ends a path where the file system reads it: the file would be another than the one named.
TEST(Params, PathsMayNotHoldNul) {
  for (const ParamKind kind : {ParamKind::InputPath, ParamKind::OutputPath}) {
    ParamDecl path{.name = "path",
                   .kind = kind,
                   .defaultValue = std::string("a.obj"),
                   .doc = "p",
                   .min = {},
                   .max = {},
                   .choices = {},
                   .rowSize = 1};
    const std::string withNul("a.obj\0.png", 10);
    EXPECT_EQ(checkParam(path, withNul),
              "'a.obj\\x00.png': a path may not contain a NUL character");
    EXPECT_THROW(coerceParam(path, withNul), std::invalid_argument);
    EXPECT_FALSE(checkParam(path, std::string("a.obj")));
  }
}

TEST(Params, TextsMustBeUtf8AsGraphFilesHoldThem) {
  // A --set value reaches a graph only as text that a graph file can be saved with.
  for (const ParamKind kind : {ParamKind::String, ParamKind::InputPath, ParamKind::OutputPath}) {
    ParamDecl text{.name = "text",
                   .kind = kind,
                   .defaultValue = std::string("a.obj"),
                   .doc = "t",
                   .min = {},
                   .max = {},
                   .choices = {},
                   .rowSize = 1};
    EXPECT_EQ(checkParam(text, std::string("a\xff.obj")),
              "'a\\xff.obj' is not UTF-8 text, as graph files hold");
    EXPECT_THROW(parseParamText(text, "a\xc3.obj"), std::invalid_argument);
    EXPECT_FALSE(checkParam(text, std::string("t\xc3\xaate.obj")));
  }
}

TEST(Params, NumberTextsOutOfRangeOrNotFiniteSaySo) {
  ParamDecl zoom{.name = "zoom",
                 .kind = ParamKind::Double,
                 .defaultValue = 1.0,
                 .doc = "z",
                 .min = 0.05,
                 .max = 400.0,
                 .choices = {},
                 .rowSize = 1};
  const auto error = [&](const std::string& text) -> std::string {
    try {
      parseParamText(zoom, text);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error("1e400"), "number out of range: '1e400'");
  EXPECT_EQ(error("nan"), "must be a finite number");
  EXPECT_EQ(error("500"), "500 is outside [0.05, 400]");
  EXPECT_EQ(error("2\x1b"), "'2\\x1b' is not a number");
  ParamDecl count{.name = "n",
                  .kind = ParamKind::Int,
                  .defaultValue = std::int64_t(1),
                  .doc = "n",
                  .min = 1.0,
                  .max = 8.0,
                  .choices = {},
                  .rowSize = 1};
  EXPECT_THROW(
      {
        try {
          parseParamText(count, "99999999999999999999");
        } catch (const std::invalid_argument& e) {
          EXPECT_STREQ(e.what(), "number out of range: '99999999999999999999'");
          throw;
        }
      },
      std::invalid_argument);
}

TEST(Params, WholeNumbersPrintWhole) {
  EXPECT_EQ(formatParam(400.0), "400");
  EXPECT_EQ(formatParam(-360.0), "-360");
  EXPECT_EQ(formatParam(1e9), "1e+09");  // shorter than 1000000000
  EXPECT_EQ(formatParam(0.05), "0.05");
  EXPECT_EQ(formatParam(1e300), "1e+300");
}

TEST(Hasher, StableOrderSensitiveAndContentBased) {
  EXPECT_EQ(Hasher().str("abc").u64(7).digest(), Hasher().str("abc").u64(7).digest());
  EXPECT_NE(Hasher().u64(1).u64(2).digest(), Hasher().u64(2).u64(1).digest());
  EXPECT_NE(Hasher().str("ab").str("c").digest(), Hasher().str("a").str("bc").digest());
  EXPECT_EQ(Hasher().f64(0.0).digest(), Hasher().f64(-0.0).digest());
  EXPECT_EQ(Scalar(2.5).contentHash(), Scalar(2.5).contentHash());
  EXPECT_NE(Scalar(2.5).contentHash(), Scalar(2.5000001).contentHash());
  Metrics a, b;
  a.values["x"] = 1;
  b.values["x"] = 2;
  EXPECT_NE(a.contentHash(), b.contentHash());
  // A fixed digest: the hash must not change between builds or runs.
  EXPECT_EQ(toHex(Hasher().str("geobrush").digest()), toHex(Hasher().str("geobrush").digest()));
  EXPECT_EQ(toHex(0xabcull), "0000000000000abc");
}
