// The test references themselves checked against published and derived
// numbers, so a validation test cannot pass because its reference is wrong.

#include <gtest/gtest.h>

#include <cmath>

#include "../reference/housner.h"
#include "../reference/newmark.h"

using freestand::reference::HousnerBlock;

TEST(HousnerReference, MatchesBenchmarksSection1) {
  // ../shared/data/benchmarks.md 1.3-1.5, block 0.25 x 1.0 m, theta0 = alpha/2.
  const HousnerBlock block{0.125, 0.5};
  EXPECT_NEAR(block.alpha(), 0.24498, 1e-5);
  EXPECT_NEAR(block.e(), 0.91176, 1e-5);
  const auto theta = freestand::reference::amplitude_map(block, 0.5 * block.alpha(), 5);
  const double expected[] = {0.38671, 0.30640, 0.24606, 0.19931, 0.16241};
  // The benchmark prints 5 digits: agreement to the last digit.
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(theta[k] / block.alpha(), expected[k], 1e-5);
  // Full nonlinear period T_exact = 1.39669 s = 4 quarter periods.
  EXPECT_NEAR(4 * freestand::reference::quarter_period(block, 0.5 * block.alpha()), 1.39669, 1e-5);
}

TEST(HousnerReference, GeneralInertiaReducesToTheRectangleAndFollowsTheNarrowerPivot) {
  // With the rectangle's own gyration radius the general I_O gives the same p
  // and e; with pivots moved in (b' < b, inertia of the full block) both are
  // those of Housner's general formulas, worked here by hand for b = 0.15,
  // b' = 0.125, h = 0.5: I_O/m = (0.15^2 + 0.5^2)/3 + (0.125^2 + 0.5^2) =
  // 0.0908333 + 0.265625 = 0.3564583 m^2; p^2 = 9.81 * 0.5153882 / I_O/m =
  // 14.18387; e = 1 - 2 * 0.015625 / 0.3564583 = 0.9123320.
  const HousnerBlock rectangle{0.125, 0.5};
  HousnerBlock general{0.125, 0.5};
  general.gyration2 = (0.125 * 0.125 + 0.25) / 3;
  EXPECT_NEAR(general.p(), rectangle.p(), 1e-14);
  EXPECT_NEAR(general.e(), rectangle.e(), 1e-14);
  HousnerBlock crushed{0.125, 0.5};
  crushed.gyration2 = (0.15 * 0.15 + 0.25) / 3;
  EXPECT_NEAR(crushed.p() * crushed.p(), 14.18387, 1e-5);
  EXPECT_NEAR(crushed.e(), 0.9123320, 1e-7);
}

TEST(NewmarkReference, RectangularPulseMatchesClosedForm) {
  // benchmarks.md section 6: A = 0.5 g for t0 = 0.2 s, mu = 0.2:
  // u_max = V^2 / (2 g N) (1 - N/A) = 0.1472 m (one-way: the block slides back
  // with the base and stops). The sliding here is relative to the base,
  // whose pulse makes the block lag by -u_max.
  const double g = 9.81;
  auto pulse = [&](double t) { return t < 0.2 ? 0.5 * g : 0.0; };
  const auto h = freestand::reference::newmark_sliding(pulse, 0.2, 0.2, g, 2.0, 1e-3, 1e-6);
  double peak = 0;
  for (double u : h.u) peak = std::max(peak, std::fabs(u));
  const double V = 0.5 * g * 0.2, expected = V * V / (2 * g * 0.2) * (1 - 0.2 / 0.5);
  // Integration error of the stepping (dt = 1e-6) is ~1e-6 m; 1e-5 relative
  // is the printed precision of the closed form.
  EXPECT_NEAR(peak, expected, 1e-5 * expected);
  EXPECT_NEAR(expected, 0.1472, 1e-4);
}
