#include "aar/renderer/msaa.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "aar/error.h"

namespace aar {
namespace {

TEST(Msaa, NativeLevelsUseOnePass) {
  const MsaaPlan plan = PlanMsaa(4, {1, 4});
  EXPECT_EQ(plan.method, "native");
  EXPECT_EQ(plan.passes, 1);
  EXPECT_EQ(plan.native_samples, 4);
  EXPECT_EQ(PlanMsaa(8, {1, 2, 4, 8}).method, "native");
}

TEST(Msaa, LavapipeComposesHigherLevelsFromFourSamplePasses) {
  for (int level : {8, 16, 32}) {
    const MsaaPlan plan = PlanMsaa(level, {1, 4});
    EXPECT_EQ(plan.method, "composed");
    EXPECT_EQ(plan.native_samples, 4);
    EXPECT_EQ(plan.passes, level / 4);
    EXPECT_EQ(static_cast<int>(CompositeSamplePattern(plan).size()), level);
  }
}

TEST(Msaa, ComposedPatternIsNRooksInsideThePixel) {
  for (int level : {8, 16, 32}) {
    const std::vector<Vec2> pattern = CompositeSamplePattern(PlanMsaa(level, {1, 4}));
    std::set<int> columns, rows;
    for (const Vec2& s : pattern) {
      EXPECT_GE(s.x, 0.0);
      EXPECT_LT(s.x, 1.0);
      EXPECT_GE(s.y, 0.0);
      EXPECT_LT(s.y, 1.0);
      columns.insert(static_cast<int>(std::floor(s.x * level)));
      rows.insert(static_cast<int>(std::floor(s.y * level)));
    }
    EXPECT_EQ(static_cast<int>(columns.size()), level) << "level " << level;
    EXPECT_EQ(static_cast<int>(rows.size()), level) << "level " << level;
  }
}

TEST(Msaa, ComposedPatternIsCentredOnThePixel) {
  const std::vector<Vec2> pattern = CompositeSamplePattern(PlanMsaa(16, {1, 4}));
  double mx = 0, my = 0;
  for (const Vec2& s : pattern) {
    mx += s.x / pattern.size();
    my += s.y / pattern.size();
  }
  EXPECT_NEAR(mx, 0.5, 0.02);
  EXPECT_NEAR(my, 0.5, 0.02);
}

TEST(Msaa, UnknownLevelIsRejected) {
  try {
    PlanMsaa(6, {1, 4});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown MSAA level"), std::string::npos);
  }
}

}  // namespace
}  // namespace aar
