#ifndef FREESTAND_TESTS_HOUSNER_H
#define FREESTAND_TESTS_HOUSNER_H

// Independent reference for free rocking of a rigid rectangular block
// (Housner 1963; ../shared/data/benchmarks.md 1.3-1.5), used only by tests.
// Written from the formulas, sharing no code with freestand.

#include <vector>

namespace freestand::reference {

struct HousnerBlock {
  double half_width;   // b (m)
  double half_height;  // h (m)
  double gravity = 9.81;  // m/s^2
  // I_c / m about the rocking axis through the centroid (m^2); < 0: the
  // uniform rectangle's (b^2 + h^2) / 3. Set it when the pivots are not the
  // body's own corners (a base with crushed edges: pivots at b - d, inertia
  // of the full block).
  double gyration2 = -1.0;

  double R() const;      // pivot-to-centroid distance sqrt(b^2 + h^2)
  double alpha() const;  // slenderness atan(b/h)
  // With I_O / m = gyration2 + R^2 (rectangle: 4 R^2 / 3):
  double p() const;      // frequency parameter sqrt(g R / (I_O / m)); rectangle sqrt(3 g / (4 R))
  double e() const;      // angular-velocity ratio across an impact: 1 - 2 R^2 sin^2(alpha) / (I_O / m);
                         // rectangle 1 - 1.5 sin^2(alpha)
};

// Amplitudes theta_1..theta_n after each impact, from release at rest at
// theta0: cos(alpha - theta_{k+1}) = cos(alpha) + e^2 [cos(alpha - theta_k) - cos(alpha)].
std::vector<double> amplitude_map(const HousnerBlock& block, double theta0, int n);

// Time from rest at amplitude theta to the impact at theta = 0 (a quarter of
// the nonlinear free period): integral of d(theta) / sqrt(2 p^2 [cos(alpha - theta0) -
// cos(alpha - theta)]), by a substitution that removes the end singularity.
double quarter_period(const HousnerBlock& block, double theta);

}  // namespace freestand::reference

#endif
