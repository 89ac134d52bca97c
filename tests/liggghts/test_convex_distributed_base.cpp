// Convex bodies, distributed base (docs/validation.md, "Convex bodies:
// distributed base (impact dissipation)"): the angular-velocity ratio r
// across the impacts of the free-rocking block of
// inputs/convex/free_rocking_block.json when the whole base carries a contact
// grid (`layout surface`, per_edge n). As n grows the grid's quadrature of the
// pressure converges to a tensionless Winkler foundation, and r to that of the
// independent reference tests/reference/winkler_rocking.h; with the corners
// only (n = 1) it is Housner's r = 1 - 1.5 sin^2(alpha).
//
// How r is measured. A compliant base's impact lasts milliseconds (tens at
// k_a = 1e8 N/m^3), so "omega just before and after" depends on where the
// impact is said to start. Instead: omega^2 at theta = 0 of the rigid
// rocking before and after impact n, from the amplitudes on either side by
// energy conservation about the pivot (Housner's own relation),
//   r_n = sqrt([cos(alpha - theta_n) - cos(alpha)] / [cos(alpha - theta_{n-1}) - cos(alpha)]),
// theta_0 the release tilt. It is the r that, put into Housner's amplitude
// map, reproduces the measured decay; fix and reference are read alike.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../reference/housner.h"
#include "../reference/winkler_rocking.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;
namespace ref = freestand::reference;

namespace {

// The block of free_rocking_block.json: 0.25 x 0.25 x 1.0 m, 100 kg, box inertia.
constexpr double kHalfWidth = 0.125, kHalfHeight = 0.5, kDepth = 0.25, kMass = 100.0;
const ref::HousnerBlock kHousner{kHalfWidth, kHalfHeight};
const double kTheta0 = 0.5 * kHousner.alpha();  // the scene's release tilt
// Hysteresis of the impact detection, as in test_convex_rocking.cpp: far above
// the contact's elastic tilt, far below the smallest amplitude.
const double kHysteresis = 0.02 * kHousner.alpha();
constexpr double kEndTime = 2.2;  // four impacts: r_1..r_3

struct Contact {
  double stiffness;    // k_a (N/m^3)
  double restitution;  // e of a flat impact
};

// r_n of impacts 1..n from the release tilt and the amplitudes after each impact.
std::vector<double> ratios(const std::vector<double>& t, const std::vector<double>& theta) {
  const fv::RockingCycles cycles = fv::rocking_cycles(t, theta, kHysteresis);
  const double alpha = kHousner.alpha();
  auto energy = [alpha](double amplitude) { return std::cos(alpha - amplitude) - std::cos(alpha); };
  std::vector<double> r;
  double before = std::fabs(theta.front());
  for (double after : cycles.amplitudes) {
    r.push_back(std::sqrt(energy(after) / energy(before)));
    before = after;
  }
  return r;
}

// fix rigid/convex with the scene's block on `per_edge` cells per base edge
// (0: `layout vertices`), `tangential_damping normal` as in the free-rocking tests;
// `refine` "bearing": the side faces keep their corners only.
std::vector<double> grid_ratios(int per_edge, const Contact& contact, double dt, const std::string& refine = "all") {
  const std::string tag = "distributed_base_" + std::to_string(::getpid()) + "_n" +
                          std::to_string(per_edge) + "_k" + fv::num(contact.stiffness) + "_e" +
                          fv::num(contact.restitution) + "_dt" + fv::num(dt) + "_" + refine;
  const fs::path dir = fv::fresh_dir(tag);
  nlohmann::json scene;
  std::ifstream(fv::source_path("inputs/convex/free_rocking_block.json")) >> scene;
  scene["bodies"][0]["nodes"] =
      per_edge == 0 ? nlohmann::json{{"layout", "vertices"}}
                    : nlohmann::json{{"layout", "surface"}, {"per_edge", per_edge}, {"refine", refine}};
  std::ofstream(dir / "scene.json") << scene.dump(1);
  const fs::path out = dir / "out.txt";
  std::ofstream script(dir / "run.in");
  script << fv::convex_preamble(2, 2, -1, 3) << "timestep " << fv::num(dt) << "\n"
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string()
         << " plane 0 stiffness " << fv::num(contact.stiffness) << " restitution "
         << fv::num(contact.restitution) << " tangential_damping normal\n"
         << "fix grav all gravity 9.81 vector 0 0 -1\n"
         << "compute rs all rockslide bodies\n"
         << "variable t equal time\nvariable rock equal c_rs[1][1]\n"
         << "fix out all print 5 \"${t} ${rock}\" file " << out.string() << " screen no\n"
         << "thermo 1000000\n"
         << "run " << std::llround(kEndTime / dt) << "\n";
  script.close();
  fv::run_input((dir / "run.in").string(), {});
  const auto rows = fv::read_rows(out, 2);
  const std::vector<double> r = ratios(fv::column(rows, 0), fv::column(rows, 1));
  fs::remove_all(dir);
  return r;
}

// The Winkler reference for the same block and law (RK4 step dt, sampled every 5 steps).
std::vector<double> winkler_ratios(const Contact& contact, double dt) {
  ref::WinklerBlock block{kHalfWidth, kDepth, kHalfHeight, kMass,
                          kMass * (kHalfWidth * kHalfWidth + kHalfHeight * kHalfHeight) / 3.0,
                          contact.stiffness, 0.0};
  block.damping = ref::winkler_damping(block, ref::single_dof_damping_ratio(contact.restitution));
  const auto samples = ref::winkler_rocking(block, kTheta0, kEndTime, dt, 5);
  std::vector<double> t, theta;
  for (const auto& s : samples) {
    t.push_back(s.t);
    theta.push_back(s.theta);
  }
  return ratios(t, theta);
}

// 1 - r relative to Housner's 1 - r.
double loss_ratio(double r) { return (1.0 - r) / (1.0 - kHousner.e()); }

std::string row(const std::string& label, const std::vector<double>& r) {
  std::ostringstream line;
  line << "[measured] " << label << ": r" << std::fixed << std::setprecision(5);
  for (double x : r) line << " " << x;
  line << "; (1-r)/(1-r_Housner)" << std::setprecision(4);
  for (double x : r) line << " " << loss_ratio(x);
  return line.str();
}

}  // namespace

// k_a = 1e8 N/m^3, e = 0.1 (zeta 1.24). Soft enough that the grid resolves
// the contact strip of the rocking phase (width sqrt(2 m g / (k_a theta D)),
// 36 mm at theta = alpha/4, 4.6 cells at 32 per edge): at 1e9 (11 mm) the
// grid converges only beyond 32 cells per edge (docs/validation.md). dt 1e-5 s:
// r identical to 1e-5 at 5e-6 s (32 cells).
TEST(ConvexDistributedBase, GridConvergesToWinklerFoundation) {
  const Contact contact{1e8, 0.1};
  const double dt = 1e-5;
  const std::vector<int> grids{4, 8, 16, 32};
  std::vector<std::vector<double>> r;
  for (int n : grids) {
    r.push_back(grid_ratios(n, contact, dt));
    std::cout << row("k_a 1e8, e 0.1, per_edge " + std::to_string(n), r.back()) << "\n";
    ASSERT_GE(r.back().size(), 2u);
  }
  const std::vector<double> winkler = winkler_ratios(contact, 2e-6);
  std::cout << row("k_a 1e8, e 0.1, Winkler reference", winkler) << "\n";
  ASSERT_GE(winkler.size(), 2u);
  for (int impact = 0; impact < 2; ++impact) {
    // (a) Successive differences shrink: each refinement changes r less than
    // the one before, by at least the factor 2 of first-order convergence.
    for (std::size_t g = 2; g < grids.size(); ++g) {
      const double previous = std::fabs(r[g - 1][impact] - r[g - 2][impact]);
      const double change = std::fabs(r[g][impact] - r[g - 1][impact]);
      EXPECT_LT(change, 0.5 * previous) << "impact " << impact + 1 << ", per_edge " << grids[g];
    }
    // (b) The finest grid within 3 % of the reference's 1 - r (measured +2.4 %,
    // +1.3 %): the tangential compliance the rigid no-slip reference lacks
    // (1.1-1.2 %: a run with k_t/k_n = 20 instead of 6/7 is within +1.3 %,
    // +0.1 %) plus the first impact's residual of that idealisation (1.3 %);
    // the grid's own remaining error is 6e-5 in r (0.1 % of 1 - r).
    const double finest = r.back()[impact];
    EXPECT_NEAR(loss_ratio(finest) / loss_ratio(winkler[impact]), 1.0, 0.03) << "impact " << impact + 1;
  }
}

// Only the bearing faces refined (`refine bearing`): a block rocking on its base presses
// the base's nodes only (a side face's nodes on the base edge act with the base's share,
// plane_contact_nodes.h), so the side faces' grid cannot change the motion: r equal to
// the full grid's to round-off (1e-9 allows the summation order of the forces). That the
// side faces are then coarse is Nodes.RefinedFacesOnlyKeepEveryFaceExact's.
TEST(ConvexDistributedBase, RefiningOnlyTheBearingFacesIsTheFullGrid) {
  const Contact contact{1e8, 0.1};
  const std::vector<double> all = grid_ratios(8, contact, 1e-5);
  const std::vector<double> bearing = grid_ratios(8, contact, 1e-5, "bearing");
  std::cout << row("k_a 1e8, e 0.1, per_edge 8, bearing faces only", bearing) << "\n";
  ASSERT_GE(all.size(), 2u);
  ASSERT_EQ(bearing.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_NEAR(bearing[i], all[i], 1e-9) << "impact " << i + 1;
}

// Corner contact (per_edge 1 = `layout vertices`, a quarter of the base on
// each corner) is Housner's impact: stiff (k_a = 1e10 N/m^3) and inelastic
// (e = 0.01, tangential dashpot), 1 - r within 1 % of Housner's 1 - 1.5 sin^2(alpha)
// (measured +0.11..+0.22 %: the contact's compliance, as in test_convex_rocking.cpp).
TEST(ConvexDistributedBase, OneCellPerEdgeIsHousner) {
  const std::vector<double> r = grid_ratios(1, {1e10, 0.01}, 2e-6);
  std::cout << row("k_a 1e10, e 0.01, per_edge 1", r) << "\n";
  ASSERT_GE(r.size(), 3u);
  for (double x : r) EXPECT_NEAR(loss_ratio(x), 1.0, 0.01);
}

// The tables of docs/validation.md ("Convex bodies: distributed base"): r of
// the first three impacts against grid, stiffness and restitution, with the
// Winkler reference and Housner. About 10 minutes; run with
// --gtest_also_run_disabled_tests.
TEST(ConvexDistributedBase, DISABLED_Sweep) {
  // dt: converged to 1e-5 in r (halved at 1e8 and 1e10); scales as 1/sqrt(k_a).
  auto step = [](double k) { return k <= 1e8 ? 1e-5 : k <= 1e9 ? 3e-6 : k <= 1e10 ? 1e-6 : 3e-7; };
  auto sweep = [&](const Contact& c, const std::vector<int>& grids) {
    std::ostringstream label_stream;
    label_stream << "k_a " << c.stiffness << ", e " << c.restitution;
    const std::string label = label_stream.str();
    for (int n : grids)
      std::cout << row(label + ", per_edge " + std::to_string(n), grid_ratios(n, c, step(c.stiffness)))
                << std::endl;
    std::cout << row(label + ", Winkler reference", winkler_ratios(c, std::min(2e-6, step(c.stiffness) / 2)))
              << std::endl;
  };
  std::cout << "[measured] Housner r = " << kHousner.e() << std::endl;
  sweep({1e8, 0.1}, {1, 2, 4, 8, 16, 32, 64});
  sweep({1e10, 0.01}, {1, 2, 4, 8, 16, 32});
  for (double k : {1e8, 1e9, 1e11}) sweep({k, 0.01}, {1, 16, 32});
  for (double e : {0.1, 0.3, 0.5}) sweep({1e10, e}, {1, 16, 32});
}
