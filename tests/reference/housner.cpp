#include "housner.h"

#include <cmath>

namespace freestand::reference {

double HousnerBlock::R() const { return std::hypot(half_width, half_height); }
double HousnerBlock::alpha() const { return std::atan2(half_width, half_height); }
double HousnerBlock::p() const {
  if (gyration2 < 0.0) return std::sqrt(3.0 * gravity / (4.0 * R()));
  return std::sqrt(gravity * R() / (gyration2 + R() * R()));
}
double HousnerBlock::e() const {
  const double s = std::sin(alpha());
  if (gyration2 < 0.0) return 1.0 - 1.5 * s * s;
  // Angular momentum about the new pivot is kept across the impact:
  // I_O w+ = (I_O - 2 m R^2 sin^2 alpha) w- (Housner 1963, eq. for general I_O).
  return 1.0 - 2.0 * R() * R() * s * s / (gyration2 + R() * R());
}

std::vector<double> amplitude_map(const HousnerBlock& block, double theta0, int n) {
  const double a = block.alpha(), e2 = block.e() * block.e();
  std::vector<double> theta;
  double current = theta0;
  for (int k = 0; k < n; ++k) {
    current = a - std::acos(std::cos(a) + e2 * (std::cos(a - current) - std::cos(a)));
    theta.push_back(current);
  }
  return theta;
}

double quarter_period(const HousnerBlock& block, double theta0) {
  // theta = theta0 (1 - s^2), s in [0, 1]: d(theta) = -2 theta0 s ds and the
  // 1/sqrt singularity at theta0 cancels. Composite Simpson on a smooth
  // integrand with 20000 intervals is exact to ~1e-12 relative.
  const double a = block.alpha(), p2 = block.p() * block.p();
  auto integrand = [&](double s) {
    if (s == 0.0) {
      // Limit s -> 0: cos(a - th0) - cos(a - th) ~ sin(a - th0) * th0 s^2.
      return 2.0 * theta0 / std::sqrt(2.0 * p2 * std::sin(a - theta0) * theta0);
    }
    const double th = theta0 * (1.0 - s * s);
    return 2.0 * theta0 * s / std::sqrt(2.0 * p2 * (std::cos(a - theta0) - std::cos(a - th)));
  };
  const int n = 20000;
  const double h = 1.0 / n;
  double sum = integrand(0.0) + integrand(1.0);
  for (int i = 1; i < n; ++i) sum += integrand(i * h) * (i % 2 ? 4.0 : 2.0);
  return sum * h / 3.0;
}

}  // namespace freestand::reference
