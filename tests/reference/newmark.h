#ifndef FREESTAND_TESTS_NEWMARK_H
#define FREESTAND_TESTS_NEWMARK_H

// Independent reference for a rigid block sliding on a moving base with
// Coulomb friction (Newmark 1965 rigid-plastic model, two-way sliding),
// used only by tests. The block sticks while the friction needed to follow
// the base, m |a_g|, is below mu_s m g; while it slips, the relative
// acceleration is -a_g - mu_k g sgn(u').

#include <functional>
#include <vector>

namespace freestand::reference {

struct SlidingHistory {
  std::vector<double> t;  // s
  std::vector<double> u;  // block displacement relative to the base (m)
};

// Integrates from rest to t_end, sampling every `sample` seconds. dt is
// the internal step; slip stops are located inside a step by linear
// interpolation of the relative velocity.
SlidingHistory newmark_sliding(const std::function<double(double)>& base_acceleration,
                               double mu_s, double mu_k, double gravity, double t_end,
                               double sample, double dt = 1e-6);

}  // namespace freestand::reference

#endif
