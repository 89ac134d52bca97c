// Tests of the small signal tools that the analysis and the diagnosis share.

#include "signal_tools.h"

#include <gtest/gtest.h>

#include <cmath>

namespace freestand::signal {
namespace {

// The sample s.d. divides by n - 1 (unbiased variance): {1, 2, 3, 4} has mean 2.5 and squared
// deviations summing to 5, so sqrt(5 / 3). One value has no spread to estimate: NaN, not 0.
TEST(SignalTools, SampleSdDividesByNMinusOneAndNeedsTwoValues) {
  EXPECT_DOUBLE_EQ(sample_sd({1.0, 2.0, 3.0, 4.0}), std::sqrt(5.0 / 3.0));
  EXPECT_DOUBLE_EQ(sample_sd({7.0, 7.0}), 0.0);
  EXPECT_TRUE(std::isnan(sample_sd({1.0})));
  EXPECT_TRUE(std::isnan(sample_sd({})));
}

}  // namespace
}  // namespace freestand::signal
