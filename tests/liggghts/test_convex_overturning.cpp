// Convex bodies, overturning and mode initiation (docs/validation.md,
// "Convex bodies: overturning and mode initiation"): fix rigid/convex in
// Housner's limit (corner nodes `layout vertices`, stiff k_a = 1e10 N/m^3,
// pivot inelastic in both directions: restitution 0.01, tangential_damping
// normal; mu = 10 for "no sliding") on fix shaketable's analytic motions.
//
//  * Overturning thresholds found by bisection on the amplitude of a
//    `rectangle` pulse, against an independent integration of Housner's
//    nonlinear equation of motion (tests/reference/housner_pulse.h) and the
//    figures of ../shared/data/benchmarks.md 1.6-1.7: three pulse lengths
//    (p t_d = 0.5, 1, 2) on a block with alpha = atan(0.1) = 0.0997, and the
//    sudden velocity step (a 0.5 ms pulse of amplitude V / t_d) on the
//    0.25 x 1.0 m block, V_c = 0.6540 m/s. Tolerance 2 % (issue 3).
//  * Shenton's slide / rock / slide-rock initiation (benchmarks.md 2.1) under
//    a stepped table acceleration lambda g, cases straddling mu = beta and
//    mu = mu_req(lambda, beta).

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "../reference/housner_pulse.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;
namespace ref = freestand::reference;
using ref::HousnerBlock;

namespace {

constexpr double kG = 9.81;
constexpr double kStart = 0.05;  // table at rest while the block settles on its corners (s)

std::string scene(const HousnerBlock& block, double depth, double mass, double mu) {
  std::ostringstream s;
  s << std::setprecision(17) << R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [)"
    << block.half_width << ", " << 0.5 * depth << ", " << block.half_height << "], \"mass\": " << mass
    << R"(, "nodes": {"layout": "vertices"}}], "interfaces": [{"lower": "table", "upper": "block", "mu": )"
    << mu << "}]}";
  return s.str();
}

struct RunData {
  std::vector<double> t, theta, slide;
};

// One run: the block at rest on the table, then a rectangle pulse of
// amplitude A (m/s^2, +x) and length td, starting at kStart.
RunData run(const std::string& tag, const std::string& scene_json, double A, double td, double dt,
        double t_end, int every, double stiffness = 1e10) {
  const fs::path dir = fv::fresh_dir("convex_overturning_" + tag);
  std::ofstream(dir / "scene.json") << scene_json;
  const fs::path out = dir / "out.txt";
  std::ofstream script(dir / "run.in");
  script << fv::convex_preamble(3, 3, -3, 3) << "timestep " << fv::num(dt) << "\n"
         << "fix shake all shaketable x rectangle amplitude " << fv::num(A) << " m/s^2 width "
         << fv::num(td) << " start " << fv::num(kStart) << "\n"
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string()
         << " stiffness " << fv::num(stiffness) << " restitution 0.01 tangential_damping normal table shake\n"
         << "fix grav all gravity 9.81 vector 0 0 -1\n"
         << "compute rs all rockslide bodies table shake\n"
         << "variable t equal time\nvariable r equal c_rs[1][1]\nvariable s equal c_rs[1][4]\n"
         << "fix out all print " << every << " \"${t} ${r} ${s}\" file " << out.string()
         << " screen no\n"
         << "thermo 10000000\n"
         << "run " << static_cast<long>(std::llround(t_end / dt)) << "\n";
  script.close();
  fv::run_input((dir / "run.in").string(), {});
  const auto rows = fv::read_rows(out, 3);
  return {fv::column(rows, 0), fv::column(rows, 1), fv::column(rows, 2)};
}

// Overturn criterion. Once the pulse is over the motion is free; a block
// whose tilt passes alpha keeps going (nothing brings it back), one that
// returns to theta = 0 has lost energy in the impact and can never overturn.
// So: overturned if |theta| exceeds 1.5 alpha (far beyond alpha, and beyond
// any compliance effect: um overlaps tilt the block by 1e-5 rad); safe if,
// after its largest tilt, |theta| falls back below 0.1 alpha; otherwise
// undecided (the run was too short: the test fails).
enum class Outcome { kSafe, kOverturned, kUndecided };

Outcome classify(const RunData& r, double alpha) {
  double peak = 0.0;
  for (double th : r.theta) {
    peak = std::max(peak, std::fabs(th));
    if (peak > 1.5 * alpha) return Outcome::kOverturned;
    if (peak > 0.2 * alpha && std::fabs(th) < 0.1 * alpha) return Outcome::kSafe;
  }
  return peak < 0.1 * alpha ? Outcome::kSafe : Outcome::kUndecided;
}

struct Threshold {
  double value = 0.0;      // midpoint of the final bracket
  double half_width = 0.0; // relative half width of the final bracket
  int runs = 0;
  bool ok = true;
};

// Bisection on the amplitude factor f (pulse amplitude f * A_ref), starting
// from [lo, hi] around the reference threshold: both ends checked, then
// `steps` halvings. A bracket end that is on the wrong side is widened by
// 0.08 (up to 3 times), so a threshold off by more than the bracket is still
// found and reported.
Threshold bisect(const std::string& tag, const std::function<Outcome(double)>& overturns, double lo,
                 double hi, int steps) {
  Threshold th;
  auto probe = [&](double f) {
    const Outcome o = overturns(f);
    ++th.runs;
    std::cout << "[validation]   " << tag << " factor " << std::setprecision(6) << f << ": "
              << (o == Outcome::kOverturned ? "overturns" : o == Outcome::kSafe ? "safe" : "undecided")
              << "\n";
    if (o == Outcome::kUndecided) th.ok = false;
    return o == Outcome::kOverturned;
  };
  for (int k = 0; k < 3 && probe(lo); ++k) lo -= 0.08;
  for (int k = 0; k < 3 && !probe(hi); ++k) hi += 0.08;
  for (int k = 0; k < steps; ++k) {
    const double mid = 0.5 * (lo + hi);
    (probe(mid) ? hi : lo) = mid;
  }
  th.value = 0.5 * (lo + hi);
  th.half_width = 0.5 * (hi - lo) / th.value;
  return th;
}

}  // namespace

// Rectangular pulses on a block with b/h = 0.1 (alpha = 0.09967, the
// benchmark's 0.0997): 0.06 x 0.2 x 0.6 m, 20 kg, R = 0.3015 m, p = 4.940 rad/s
// (short period: every run lasts ~2 s of simulated time). Bisection from
// +-4 % of the reference in 6 halvings: final bracket 0.125 %, the midpoint
// within 0.07 % of the simulated threshold, well below the 2 % tolerance.
// The simulated thresholds are LOWER than Housner's (measured -0.7 to -1.3 %
// at k_a = 1e10 N/m^3): the penalty contact's response to the pulse's steps
// gives the block a small extra kick (a safe run at 0.975 A_c, p t_d = 2,
// peaks at 0.675 alpha against Housner's 0.547 alpha; 0.583 alpha at k_a =
// 1e11, the same at dt 2e-6). So p t_d = 2, the case most sensitive to it
// (A_c only 16 % above the uplift level g tan alpha), is repeated at
// k_a = 1e11 N/m^3 and must come closer to Housner.
TEST(ConvexOverturning, RectanglePulseThresholdsMatchHousner) {
  const HousnerBlock block{0.03, 0.3};
  const double alpha = block.alpha(), p = block.p();
  const std::string json = scene(block, 0.2, 20.0, 10.0);
  const double quoted[3] = {2.5425, 1.5820, 1.1563};  // benchmarks.md 1.6, alpha = 0.0997
  int i = 0;
  double error_ptd2 = 0.0;
  for (double ptd : {0.5, 1.0, 2.0}) {
    const double td = ptd / p;
    const double a_ref = ref::rectangle_pulse_threshold(block, td);
    const double linear = 1.0 / (1.0 - std::exp(-ptd));
    std::ostringstream tag;
    tag << "ptd" << ptd;
    const double t_end = kStart + td + 2.0;
    const Threshold th = bisect(
        tag.str(),
        [&](double f) {
          return classify(run(tag.str(), json, f * a_ref, td, 4e-6, t_end, 25), alpha);
        },
        0.96, 1.04, 6);
    const double measured = th.value * a_ref / (kG * alpha);
    std::cout << std::setprecision(5) << "[validation] convex overturning, rectangle pulse p t_d = "
              << ptd << " (t_d " << td << " s): A_c/(g alpha) simulated " << measured << " (+-"
              << 100 * th.half_width << " %, " << th.runs << " runs), Housner EOM " << a_ref / (kG * alpha)
              << ", error " << std::showpos << 100 * (th.value - 1.0) << std::noshowpos
              << " %; linearised " << linear << "; benchmarks.md quotes " << quoted[i]
              << " (= A_c/(g tan alpha) of the EOM: " << a_ref / (kG * std::tan(alpha)) << ")\n";
    EXPECT_TRUE(th.ok);
    EXPECT_LT(std::fabs(th.value - 1.0), 0.02);
    EXPECT_LT(std::fabs(a_ref / (kG * std::tan(alpha)) / quoted[i] - 1.0), 2e-4);
    if (ptd == 2.0) error_ptd2 = th.value - 1.0;
    ++i;
  }
  // Stiffness convergence, p t_d = 2: k_a = 1e11 N/m^3 (dt 1e-6 s).
  const double td = 2.0 / p, a_ref = ref::rectangle_pulse_threshold(block, td);
  const Threshold stiff = bisect(
      "ptd2_k1e11",
      [&](double f) {
        return classify(run("ptd2_k1e11", json, f * a_ref, td, 1e-6, kStart + td + 2.0, 100, 1e11),
                        alpha);
      },
      0.96, 1.04, 6);
  std::cout << std::setprecision(5) << "[validation] convex overturning, rectangle pulse p t_d = 2, k_a 1e11 "
            << "N/m^3: A_c/(g alpha) simulated " << stiff.value * a_ref / (kG * alpha) << " (+-"
            << 100 * stiff.half_width << " %), error " << std::showpos << 100 * (stiff.value - 1.0)
            << std::noshowpos << " % (k_a 1e10: " << std::showpos << 100 * error_ptd2 << std::noshowpos
            << " %)\n";
  EXPECT_TRUE(stiff.ok);
  EXPECT_LT(std::fabs(stiff.value - 1.0), std::fabs(error_ptd2));
}

// Sudden velocity step V on the 0.25 x 0.25 x 1.0 m, 100 kg block: a 0.5 ms
// rectangle pulse of amplitude V / t_d (benchmarks.md 1.7 did the same).
// V_c = sqrt(8 g R (1 - cos alpha) / 3) / cos alpha = 0.6540 m/s exactly for
// the step; Housner's EOM gives 0.6546 m/s for the 0.5 ms pulse. The pulse
// is ~130 g: mu = 10 keeps the pivot from sliding (Housner's assumption;
// the impulse needs Ft/Fn ~ 1.5 at the pivot).
TEST(ConvexOverturning, VelocityStepThresholdMatchesHousner) {
  const HousnerBlock block{0.125, 0.5};
  const double alpha = block.alpha(), td = 5e-4;
  const double vc = ref::velocity_step_threshold(block);
  const double v_pulse = ref::rectangle_pulse_threshold(block, td, 1e-7, 1e-6) * td;
  const std::string json = scene(block, 0.25, 100.0, 10.0);
  const Threshold th = bisect(
      "step",
      [&](double f) {
        return classify(run("step", json, f * vc / td, td, 4e-6, kStart + 3.0, 25), alpha);
      },
      0.96, 1.04, 6);
  std::cout << std::setprecision(5) << "[validation] convex overturning, velocity step (0.5 ms pulse): V_c "
            << "simulated " << th.value * vc << " m/s (+-" << 100 * th.half_width << " %, " << th.runs
            << " runs), exact step " << vc << " m/s (error " << std::showpos << 100 * (th.value - 1.0)
            << std::noshowpos << " %), Housner EOM for the 0.5 ms pulse " << v_pulse << " m/s (error "
            << std::showpos << 100 * (th.value * vc / v_pulse - 1.0) << std::noshowpos << " %)\n";
  EXPECT_TRUE(th.ok);
  EXPECT_LT(std::fabs(th.value - 1.0), 0.02);
  EXPECT_NEAR(vc, 0.6540, 5e-5);
}

// Shenton (1996), benchmarks.md 2.1: the 0.25 x 0.25 x 1.0 m block (beta =
// b/h = 0.25) under a table acceleration stepped to lambda g (a 1 s
// `rectangle`), for friction coefficients on both sides of beta and of
// mu_req(lambda, beta). Margins: 10-20 % in mu from each boundary. What a
// penalty contact can blur at a step is the transient of its tangential
// spring (damping ratio 0.83 at restitution 0.01: overshoot ~1 % of Ft/Fn)
// and the micrometre elastic slip and tilt, so 10 % is far outside both.
// The last case (lambda 0.2 < beta and < mu) must stay at rest.
// Regime read 0.1 s after the step: rocking if |theta| > 1e-3 rad, sliding
// if the pivot corner's slip relative to the table exceeds 1 mm (the
// slowest mode here moves 8e-3 rad and 6 mm by then; elastic motions are
// ~1e-5 rad and ~1e-5 m). Besides the regime, the initial accelerations
// (Newton-Euler from rest, tests/reference/housner_pulse.h) are compared at
// 0.05 s with theta = theta'' t^2 / 2, slip = slip'' t^2 / 2, within 10 %.
TEST(ConvexOverturning, ShentonSlideRockInitiation) {
  const HousnerBlock block{0.125, 0.5};
  const double b = block.half_width, h = block.half_height, beta = b / h;
  struct Case {
    double lambda, mu;
  };
  const char* names[] = {"rest", "slide", "rock", "slide-rock"};
  for (const Case c : {Case{0.5, 0.20}, Case{0.5, 0.28}, Case{0.5, 0.34}, Case{0.75, 0.33},
                       Case{0.75, 0.40}, Case{0.75, 0.22}, Case{0.2, 0.3}}) {
    const double mu_req = ref::shenton_mu_required(c.lambda, beta);
    const ref::InitialMode expect = ref::shenton_initial_mode(b, h, c.mu, c.lambda, kG);
    std::ostringstream tag;
    tag << "shenton_l" << c.lambda << "_mu" << c.mu;
    const RunData r = run(tag.str(), scene(block, 0.25, 100.0, c.mu), c.lambda * kG, 1.0, 4e-6,
                      kStart + 0.1, 25);
    auto at = [&](double t, double& theta, double& slip) {
      theta = fv::interpolate(r.t, r.theta, kStart + t);
      const double slide = fv::interpolate(r.t, r.slide, kStart + t);
      slip = slide + (theta < 0 ? -1.0 : 1.0) * b * (std::cos(theta) - 1.0);  // pivot corner
    };
    double theta, slip, theta_e, slip_e;
    at(0.1, theta, slip);
    at(0.05, theta_e, slip_e);
    const bool rocks = std::fabs(theta) > 1e-3, slides = std::fabs(slip) > 1e-3;
    const int regime = rocks ? (slides ? 3 : 2) : (slides ? 1 : 0);
    const double t2 = 0.5 * 0.05 * 0.05;
    std::cout << std::setprecision(4) << "[validation] Shenton initiation, beta " << beta << ", lambda "
              << c.lambda << ", mu " << c.mu << " (mu_req " << mu_req << "): expected "
              << names[expect.regime] << ", simulated " << names[regime] << " (at 0.1 s: |theta| "
              << std::fabs(theta) << " rad, pivot slip " << std::fabs(slip) << " m); at 0.05 s |theta| "
              << std::fabs(theta_e) << " (Newton-Euler " << expect.theta_dd * t2 << "), slip "
              << std::fabs(slip_e) << " m (" << -expect.slip_dd * t2 << ")\n";
    EXPECT_EQ(regime, expect.regime) << tag.str();
    if (expect.theta_dd > 0) EXPECT_NEAR(std::fabs(theta_e), expect.theta_dd * t2, 0.1 * expect.theta_dd * t2);
    if (expect.slip_dd < 0) EXPECT_NEAR(std::fabs(slip_e), -expect.slip_dd * t2, -0.1 * expect.slip_dd * t2);
  }
}
