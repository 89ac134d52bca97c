// Validation 1 (docs/validation.md): free rocking of a stock multisphere
// clump against Housner's amplitude map and nonlinear period
// (../shared/data/benchmarks.md 1.4-1.5, tests/reference/housner.h), read
// through compute rockslide.
//
// The clump's energy loss per impact is set by the floor's restitution
// coefficient en, which Housner's rigid-block theory does not have. A value
// of en chosen so that this very block matches would make the comparison
// circular, so en is either
//   * calibrated on a DIFFERENT block (0.4 x 0.4 x 1.2 m, b/h = 1/3, same
//     density; not the 0.25 x 0.25 x 1.0 m, b/h = 1/4 block under test),
//     then used unchanged to predict the block under test; or
//   * not calibrated at all: Housner's impact is perfectly plastic (the new
//     pivot does not bounce) and his contacts only push, so the matching
//     contact law is the most dissipative restitution LIGGGHTS accepts
//     (en just above its lower bound 0.05) with limitForce on.
//
// Acceptance: every amplitude ratio theta_n/alpha (n = 1..4), the time from
// release to the first impact and the four half-cycle durations between
// impacts 1..5 within 3 % of Housner (each half-cycle between impacts lasts
// 2 * quarter_period(theta_n)). 3 % is the acceptance figure; the
// reference itself is exact to ~1e-12, and the clump's own geometric error
// (1 mm base spheres rolling: period +0.75 rbase/R, about +0.15 %) is far
// below it, so the budget is left to the contact model's impact loss.

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "../reference/housner.h"
#include "validation_support.h"

namespace fs = std::filesystem;
using freestand::reference::HousnerBlock;
using namespace freestand::validation;

namespace {

constexpr double kTolerance = 0.03;   // issue 2, requirement 1
constexpr double kGravity = 9.81;     // the input scripts' fix gravity
constexpr double kDt = 2e-5;          // inputs/validation/free_rocking.in default
// en must be > 0.05 in LIGGGHTS 3.8 (global_properties.cpp); 0.051 is just
// above that bound (the last digit hardly matters: en = 0.06 moves theta_4
// of the target block by 0.05 %).
constexpr double kPlasticEn = 0.051;

// The block under test: issue 2 / benchmarks.md 1.4-1.5 example.
const BlockClump kTarget{0.25, 0.25, 1.0, 100.0};
// The calibration block: other slenderness (b/h = 1/3) and size (R = 0.632 m
// against 0.515 m), same density (1600 kg/m^3 as the target) and sphere radii.
const BlockClump kCalibration{0.4, 0.4, 1.2, 1600.0 * 0.4 * 0.4 * 1.2};

struct Contact {
  double en;
  std::string limit;   // limitForce on/off
  double E = 5e10;     // Young's modulus (Pa)
  double dt = kDt;     // time step (s)
};

struct RockingResult {
  std::vector<double> ratio, ratio_ref;  // theta_n / alpha, n = 1..4
  std::vector<double> times, times_ref;  // release -> impact 1, then impacts 1-2 ... 4-5
  double cross_check = 0;                // max |rock_x - two-sphere angle| (rad)
  double out_of_plane = 0;               // max |rock_y|, |twist| (rad)
  double seconds = 0;                    // wall time of the run

  double error(const std::vector<double>& a, const std::vector<double>& b, std::size_t i) const {
    return a[i] / b[i] - 1.0;
  }
  double theta4_error() const { return ratio.size() == 4 ? error(ratio, ratio_ref, 3) : NAN; }
  double max_error() const {
    double m = 0;
    for (std::size_t i = 0; i < ratio.size(); ++i) m = std::max(m, std::fabs(error(ratio, ratio_ref, i)));
    for (std::size_t i = 0; i < times.size(); ++i) m = std::max(m, std::fabs(error(times, times_ref, i)));
    return m;
  }
};

// Releases `block` from rest at alpha/2 and measures its first four
// half-cycles through compute rockslide.
RockingResult free_rocking(const fs::path& dir, const std::string& clump, const BlockClump& block,
                           const Contact& contact, const std::string& tag) {
  const HousnerBlock ref{block.width / 2, block.height / 2, kGravity};
  const double alpha = ref.alpha(), theta0 = 0.5 * alpha;
  RockingResult r;
  const std::vector<double> amplitudes = freestand::reference::amplitude_map(ref, theta0, 4);
  r.times_ref.push_back(freestand::reference::quarter_period(ref, theta0));
  for (double a : amplitudes) {
    r.ratio_ref.push_back(a / alpha);
    r.times_ref.push_back(2.0 * freestand::reference::quarter_period(ref, a));
  }
  // Long enough for the 5th impact even with no loss at all (every
  // half-cycle as long as the first, 2 quarter_period(theta0)), +5 % and
  // 50 ms to see the angle leave zero after it.
  const double t_end = 1.05 * 9 * r.times_ref[0] + 0.05;

  const fs::path out = dir / (tag + ".dat");
  const double start = wall_seconds();
  // Output every 1e-4 s.
  run_input(source_path("inputs/validation/free_rocking.in"),
            {{"clump", clump}, {"en", num(contact.en)}, {"limit", contact.limit},
             {"E", num(contact.E)}, {"dt", num(contact.dt)}, {"tend", num(t_end)},
             {"nprint", std::to_string(std::lround(1e-4 / contact.dt))}, {"out", out.string()}});
  r.seconds = wall_seconds() - start;

  const auto rows = read_rows(out, 7);
  const std::vector<double> t = column(rows, 0), rock_x = column(rows, 1);
  for (const auto& row : rows) {
    r.cross_check = std::max(r.cross_check, std::fabs(row[1] - row[6]));
    r.out_of_plane = std::max({r.out_of_plane, std::fabs(row[2]), std::fabs(row[3])});
  }
  // Hysteresis 1e-3 rad: 1/35 of the smallest amplitude measured here
  // (theta_4 of the calibration block, 0.035 rad), far above contact chatter.
  const RockingCycles cycles = rocking_cycles(t, rock_x, 1e-3);
  if (cycles.impacts.size() < 5) {
    ADD_FAILURE() << tag << ": only " << cycles.impacts.size() << " impacts in " << t_end << " s";
    return r;
  }
  // Released at the end of the insertion step (t = dt): the pose is the
  // insertion pose until then.
  r.times.push_back(cycles.impacts[0] - contact.dt);
  for (int n = 0; n < 4; ++n) {
    r.ratio.push_back(cycles.amplitudes[n] / alpha);
    r.times.push_back(cycles.impacts[n + 1] - cycles.impacts[n]);
  }
  return r;
}

void print(const std::string& title, const RockingResult& r, const Contact& c) {
  std::cout << std::fixed;
  std::cout << "[validation] " << title << " (en = " << std::setprecision(4) << c.en
            << ", limitForce " << c.limit << ", E = " << std::scientific << std::setprecision(1)
            << c.E << ", dt = " << c.dt << std::fixed << ", run " << std::setprecision(2) << r.seconds << " s)\n";
  for (std::size_t n = 0; n < r.ratio.size(); ++n)
    std::cout << "[validation]   theta_" << n + 1 << "/alpha  measured " << std::setprecision(5)
              << r.ratio[n] << "  Housner " << r.ratio_ref[n] << "  error " << std::showpos
              << std::setprecision(2) << 100 * r.error(r.ratio, r.ratio_ref, n) << " %"
              << std::noshowpos << "\n";
  for (std::size_t i = 0; i < r.times.size(); ++i)
    std::cout << "[validation]   " << (i == 0 ? "release->impact 1  " : "impact " + std::to_string(i) +
                                                 "->" + std::to_string(i + 1) + "     ")
              << "measured " << std::setprecision(5) << r.times[i] << " s  Housner "
              << r.times_ref[i] << " s  error " << std::showpos << std::setprecision(2)
              << 100 * r.error(r.times, r.times_ref, i) << " %" << std::noshowpos << "\n";
  std::cout << std::scientific << std::setprecision(2) << "[validation]   max |rock_x - two-sphere angle| "
            << r.cross_check << " rad, max out-of-plane |rock_y|,|twist| " << r.out_of_plane
            << " rad\n" << std::defaultfloat;
}

void expect_housner(const RockingResult& r) {
  ASSERT_EQ(r.ratio.size(), 4u);
  for (std::size_t n = 0; n < 4; ++n)
    EXPECT_NEAR(r.ratio[n], r.ratio_ref[n], kTolerance * r.ratio_ref[n]) << "theta_" << n + 1 << "/alpha";
  for (std::size_t i = 0; i < 5; ++i)
    EXPECT_NEAR(r.times[i], r.times_ref[i], kTolerance * r.times_ref[i])
        << (i == 0 ? std::string("release to impact 1") : "half-cycle " + std::to_string(i));
  // compute rockslide's rock_x and the independent two-sphere angle of
  // inputs/free_rocking/free_rocking.in are functions of the same pose: they
  // differ by round-off only (15 printed digits, sphere positions rebuilt
  // from the quaternion each step: ~1e-15 rad). 1e-12 rad would still catch
  // any offset of the compute's frame, the smallest plausible being the
  // ~1e-9 rad the block turns in its first step after release.
  EXPECT_LT(r.cross_check, 1e-12);
  // Planar problem: out-of-plane rocking or twist could only be numerical
  // symmetry breaking; 1e-6 rad is 1e-4 of the smallest amplitude.
  EXPECT_LT(r.out_of_plane, 1e-6);
}

struct Calibration {
  double en = NAN;        // calibrated restitution
  double residual = NAN;  // theta_4 error of the calibration block at en
  int runs = 0;
  double seconds = 0;
};

// The en at which `block`'s theta_4 matches Housner. The theta_4 error rises
// with en (less loss per impact), so the bracket [0.051, 0.95], the whole
// range LIGGGHTS admits up to nearly elastic, holds the root; the Illinois
// variant of regula falsi finds it in a few runs. It stops at |theta_4
// error| < 0.05 % (60 times below the 3 % acceptance, so the calibration's
// residual is negligible in a prediction), or once the bracket is narrower
// than 1e-3 in en: with limitForce off theta_4 is not smooth in en at that
// scale (it jumps by ~0.3 % for changes of en of 4e-5), so no finer
// calibration exists. The best en seen is kept.
Calibration calibrate(const fs::path& dir, const std::string& clump, const BlockClump& block,
                      const std::string& limit, const std::string& tag) {
  Calibration c;
  const double start = wall_seconds();
  auto f = [&](double en) {
    const RockingResult r =
        free_rocking(dir, clump, block, {en, limit}, tag + "_" + std::to_string(c.runs++));
    std::cout << "[validation] calibration run " << c.runs << ": en = " << std::setprecision(6)
              << en << "  theta_4 error " << std::setprecision(4) << 100 * r.theta4_error()
              << " %\n";
    if (std::isnan(r.theta4_error())) throw std::runtime_error("calibration run failed");
    return r.theta4_error();
  };
  double lo = kPlasticEn, hi = 0.95;
  double flo = f(lo), fhi = f(hi);
  if (!(flo < 0 && fhi > 0)) {
    ADD_FAILURE() << "calibration bracket [" << lo << ", " << hi << "] gives theta_4 errors "
                  << flo << ", " << fhi << ": no sign change";
    return c;
  }
  c.en = std::fabs(flo) < std::fabs(fhi) ? lo : hi;
  double best = std::min(std::fabs(flo), std::fabs(fhi));
  c.residual = std::fabs(flo) < std::fabs(fhi) ? flo : fhi;
  int side = 0;
  for (int iteration = 0; iteration < 12 && best > 5e-4 && hi - lo > 1e-3; ++iteration) {
    const double x = hi - fhi * (hi - lo) / (fhi - flo);
    const double fx = f(x);
    if (std::fabs(fx) < best) best = std::fabs(fx), c.en = x, c.residual = fx;
    if (fx < 0) {
      lo = x, flo = fx;
      if (side == -1) fhi /= 2;
      side = -1;
    } else {
      hi = x, fhi = fx;
      if (side == +1) flo /= 2;
      side = +1;
    }
  }
  c.seconds = wall_seconds() - start;
  return c;
}

// Calibrates en on the calibration block so that its theta_4 matches
// Housner, then predicts the block under test with that en.
void calibrate_then_predict(const std::string& limit, const std::string& name) {
  const fs::path dir = fresh_dir(name);
  const std::string cal_clump = make_clump(dir, "calibration", kCalibration);
  const std::string target_clump = make_clump(dir, "target", kTarget);
  const Calibration cal_en = calibrate(dir, cal_clump, kCalibration, limit, "cal");
  // The calibration block itself must match within 0.5 % (1/6 of the
  // acceptance), so that the prediction tests transfer, not calibration.
  ASSERT_LT(std::fabs(cal_en.residual), 5e-3) << "calibration did not converge";
  const double en = cal_en.en;
  const int runs = cal_en.runs;
  const double calibration_seconds = cal_en.seconds;

  const Contact contact{en, limit};
  const RockingResult cal = free_rocking(dir, cal_clump, kCalibration, contact, "cal_final");
  print("calibration block 0.4 x 0.4 x 1.2 m, b/h = 1/3, at the calibrated en", cal, contact);
  const RockingResult r = free_rocking(dir, target_clump, kTarget, contact, "prediction");
  print("PREDICTION, block 0.25 x 0.25 x 1.0 m, b/h = 1/4, 100 kg, from alpha/2", r, contact);
  std::cout << "[validation] calibration: " << runs << " runs, " << std::setprecision(3)
            << calibration_seconds << " s; largest prediction error " << std::setprecision(3)
            << 100 * r.max_error() << " %\n";
  ::testing::Test::RecordProperty("calibrated_en", num(en));
  ::testing::Test::RecordProperty("prediction_theta4_error_percent",
                                  std::to_string(100 * r.theta4_error()));
  ::testing::Test::RecordProperty("prediction_max_error_percent", std::to_string(100 * r.max_error()));
  expect_housner(r);
}

}  // namespace

// Contact law: hertz, tangential history, E = 5e10 Pa, nu = 0.25, mu = 0.6,
// dt = 2e-5 s, limitForce on (a contact only pushes); en calibrated.
TEST(Validation, FreeRockingCalibratedOnOtherBlock) {
  calibrate_then_predict("on", "free_rocking_calibrated");
}

// The same with stock LIGGGHTS' default limitForce off (the contact law of
// inputs/free_rocking and inputs/shake_table), whose normal damping pulls
// on a pivot while it lifts off.
TEST(Validation, FreeRockingCalibratedOnOtherBlockStockContact) {
  calibrate_then_predict("off", "free_rocking_calibrated_stock");
}

// No calibration: the contact closest to Housner's perfectly plastic impact
// (en = 0.051, limitForce on). Also the one-off cross-check of compute
// rockslide against the independent two-sphere angle (in expect_housner).
TEST(Validation, FreeRockingPlasticContactNoCalibration) {
  const fs::path dir = fresh_dir("free_rocking_plastic");
  const std::string clump = make_clump(dir, "target", kTarget);
  const Contact contact{kPlasticEn, "on"};
  const RockingResult r = free_rocking(dir, clump, kTarget, contact, "target");
  print("block 0.25 x 0.25 x 1.0 m, 100 kg, from alpha/2, plastic contact, no calibration", r, contact);
  ::testing::Test::RecordProperty("theta4_error_percent", std::to_string(100 * r.theta4_error()));
  ::testing::Test::RecordProperty("max_error_percent", std::to_string(100 * r.max_error()));
  ::testing::Test::RecordProperty("rock_x_cross_check_rad", std::to_string(r.cross_check));
  expect_housner(r);
}

// Informational, not part of the suite (run with
// --gtest_also_run_disabled_tests): what the restitution that matches
// Housner depends on. Prints, for both contact laws, the en each block
// needs to match its own theta_4 (does it depend on slenderness?), and the
// plastic contact's error as the contact stiffens (does the residual loss
// come from the contact's compliance?). Asserts nothing.
TEST(Validation, DISABLED_FreeRockingContactSensitivity) {
  const fs::path dir = fresh_dir("free_rocking_sensitivity");
  const std::string cal_clump = make_clump(dir, "calibration", kCalibration);
  const std::string target_clump = make_clump(dir, "target", kTarget);
  for (const std::string limit : {"on", "off"}) {
    const Calibration target = calibrate(dir, target_clump, kTarget, limit, "target_" + limit);
    const Calibration other = calibrate(dir, cal_clump, kCalibration, limit, "cal_" + limit);
    std::cout << std::setprecision(4) << "[validation] limitForce " << limit
              << ": en matching theta_4: b/h = 1/4 block " << target.en << " (residual "
              << 100 * target.residual << " %), b/h = 1/3 block " << other.en << " (residual "
              << 100 * other.residual << " %)\n";
  }
  for (const Contact& c : {Contact{kPlasticEn, "on", 1e10}, Contact{kPlasticEn, "on", 5e10},
                           Contact{kPlasticEn, "on", 2e11}, Contact{kPlasticEn, "on", 2e11, 1e-5},
                           Contact{0.61, "off", 5e10}}) {
    print("block 0.25 x 0.25 x 1.0 m", free_rocking(dir, target_clump, kTarget, c, "target_E"), c);
    print("block 0.4 x 0.4 x 1.2 m", free_rocking(dir, cal_clump, kCalibration, c, "cal_E"), c);
  }
}
