// Validations 2-4 (docs/validation.md): a stock multisphere block on a
// mesh shake table driven by fix shaketable (fix move/mesh linear/variable
// with v = f_shake[4]), measured through compute rockslide:
//   * uplift at table acceleration g b/h and slip at mu g under a slowly
//     ramped table acceleration (benchmarks.md 1.2, 2.1-2.2), within 2 %;
//   * sliding on a sinusoidal table against a Newmark rigid-plastic
//     integration (benchmarks.md 6, tests/reference/newmark.h), within 2 %;
//   * a block at rest on a still table moves less than 0.1 mm in 5 s.
//
// Contact law of all four (inputs/validation/table_block.in): hertz,
// tangential history, E = 5e10 Pa, nu = 0.25, limitForce on, en = 0.051,
// dt = 2e-5 s. The references are rigid-plastic (a stop is instantaneous, a
// contact only pushes), and en at the lower bound LIGGGHTS accepts (> 0.05)
// with limitForce on is the closest DEM contact to that: with en = 0.61,
// limitForce off (the contact of inputs/shake_table) the sine history error
// is about 4 % (docs/validation.md, section 3). en only damps vibrations in
// the quasi-static uplift and slip tests.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "../reference/newmark.h"
#include "validation_support.h"

namespace fs = std::filesystem;
using namespace freestand::validation;

namespace {

constexpr double kGravity = 9.81;  // the input script's fix gravity
constexpr double kDt = 2e-5;       // time step of table_block.in
constexpr double kE = 5e10, kNu = 0.25, kRbase = 0.001;  // contact (table_block.in defaults)
constexpr double kSettle = 0.2;    // s at rest before the table moves (table_block.in default)
constexpr int kPrint = 50;         // output every 50 steps = 1 ms

// The blocks of inputs/shake_table: rocking block (b/h = 1/4, only its 4 base
// corners touch the table) and squat sliding block (b/h = 1.25).
const BlockClump kRockBlock{0.25, 0.25, 1.0, 100.0};
const BlockClump kSlideBlock{0.5, 0.5, 0.4, 200.0, 4, 3};

// Runs inputs/validation/table_block.in; returns its output rows
// (t, a_table, d_table, rock_x, rock_y, twist, slide_x, slide_y, uplift).
// `contact` may override en and limit (sensitivity runs only).
std::vector<std::vector<double>> run_table(const fs::path& dir, const std::string& clump,
                                           double mu, const std::string& motion, double t_end,
                                           double travel, int nprint = kPrint,
                                           const Variables& contact = {}) {
  const fs::path out = dir / "table.dat";
  Variables v{{"clump", clump},
              {"stl", source_path("inputs/shake_table/table.stl")},
              {"mu", num(mu)},
              {"motion", motion},
              {"tend", num(t_end)},
              {"nprint", std::to_string(nprint)},
              {"xmax", num(1.5 + travel)},
              {"out", out.string()}};
  v.insert(v.end(), contact.begin(), contact.end());
  run_input(source_path("inputs/validation/table_block.in"), v);
  return read_rows(out, 9);
}

// Hertz overlap of a sphere of radius kRbase pressed on the table by F:
// F = 4/3 Y* sqrt(r) delta^1.5, Y* = E / (2 (1 - nu^2)) for two equal materials.
double hertz_overlap(double force) {
  const double y = kE / (2 * (1 - kNu * kNu));
  return std::pow(3 * force / (4 * y * std::sqrt(kRbase)), 2.0 / 3.0);
}

// A two-segment ramp of the table acceleration written as a two-column
// record (t, a in m/s^2): 0 -> 0.8 a_ref in 1 s, then slowly at `rate` up to
// 1.1 a_ref. fix shaketable plays piecewise-linear acceleration exactly.
struct Ramp {
  double a_ref, rate;
  double t1 = 1.0;                   // end of the fast segment (motion time)
  double a1() const { return 0.8 * a_ref; }
  double t_end() const { return t1 + 0.25 * a_ref / rate; }  // stop at 1.05 a_ref
  double travel() const { return 1.1 * a_ref * t_end() * t_end() / 2; }  // bound on d(t_end)
  double velocity(double t) const {  // table velocity at motion time t
    if (t <= t1) return 0.5 * a1() / t1 * t * t;
    return 0.5 * a1() * t1 + a1() * (t - t1) + 0.5 * rate * (t - t1) * (t - t1);
  }
  std::string write(const fs::path& file) const {
    std::ofstream(file) << std::setprecision(17) << "0 0\n"
                        << t1 << " " << a1() << "\n"
                        << t1 + 0.3 * a_ref / rate << " " << 1.1 * a_ref << "\n";
    return "x record " + file.string() + " units m/s^2";
  }
};

struct Detection {
  double a = NAN;        // table acceleration when detected (m/s^2)
  double t = NAN;        // motion time (s)
  std::size_t index = 0;
};

// First time the rate of `channel` (finite difference over 10 ms) exceeds
// `threshold` in direction `sign`, over windows that lie wholly in the slow
// segment (in the fast one the elastic rates are 8 times larger; an onset
// there would be detected at once, near 0.8 a_ref, and fail the test).
Detection detect(const std::vector<std::vector<double>>& rows, std::size_t channel, double sign,
                 double threshold, const Ramp& ramp) {
  const std::vector<double> t = column(rows, 0), value = column(rows, channel);
  std::size_t first = 0;
  while (first < t.size() && t[first] - kSettle < ramp.t1) ++first;
  const long k = first_rate_above(t, value, 10, sign, threshold, first + 10);
  Detection d;
  if (k < 0) return d;
  d.index = static_cast<std::size_t>(k);
  d.t = t[d.index] - kSettle;
  d.a = rows[d.index][1];
  return d;
}

}  // namespace

// Uplift (rocking initiation) of the slender block, mu = 0.8 (far above the
// friction needed for pure rocking at uplift, benchmarks.md 2.1: 0.25), at
// |a| = g b/h.
//
// Detection: the rocking angular velocity d(rock_x)/dt (finite difference
// over 10 ms) exceeds omega_th. Before uplift the block tilts elastically on
// its Hertz corners: from 0 at rest to phi_e = delta(m g / 2) / (2b) (all the
// weight on the two pivot-side spheres) at uplift, i.e. at a mean rate
// phi_e * rate / a_ref during the slow ramp. omega_th is ten times that.
// (Near uplift the unloading corner's Hertz compliance diverges as
// F^(-1/3), but it reaches omega_th only within ~1e-4 a_ref of uplift.)
// After uplift the rigid block's angular velocity grows as
// p^2 cos(alpha) (rate / g) tau^2 / 2 (Housner's equation linearised about
// theta = 0 under a ramp), so the detection lags uplift by at most
//   delta_a = sqrt(2 omega_th g rate / (p^2 cos alpha)) + rate * 10 ms.
TEST(Validation, UpliftAtGbOverH) {
  const double start = wall_seconds();
  const fs::path dir = fresh_dir("uplift");
  const std::string clump = make_clump(dir, "rock_block", kRockBlock);
  const double b = kRockBlock.width / 2, h = kRockBlock.height / 2, m = kRockBlock.mass;
  const double a_ref = kGravity * b / h;
  // 0.25 m/s^3: slow enough for a delay bound well below 2 %, short enough
  // for a ~3 s run.
  const Ramp ramp{a_ref, 0.25};
  const auto rows = run_table(dir, clump, 0.8, ramp.write(dir / "ramp.txt"),
                              kSettle + ramp.t_end(), ramp.travel());

  const double phi_e = hertz_overlap(m * kGravity / 2) / (2 * b);
  const double omega_th = 10 * phi_e * ramp.rate / a_ref;
  const double R = std::hypot(b, h), alpha = std::atan2(b, h), p2 = 3 * kGravity / (4 * R);
  const double bound =
      std::sqrt(2 * omega_th * kGravity * ramp.rate / (p2 * std::cos(alpha))) + ramp.rate * 0.01;
  // The table accelerates toward +x: the block tips toward -x (rock_x < 0).
  const Detection d = detect(rows, 3, -1.0, omega_th, ramp);
  ASSERT_FALSE(std::isnan(d.a)) << "no uplift detected up to 1.05 g b/h";
  const double slide = rows[d.index][6];

  std::cout << std::setprecision(5) << "[validation] uplift: detected at a = " << d.a
            << " m/s^2 (t = " << d.t << " s), g b/h = " << a_ref << " m/s^2, error "
            << std::showpos << 100 * (d.a / a_ref - 1) << std::noshowpos
            << " %; detection delay bound " << 100 * bound / a_ref << " %; omega_th = "
            << omega_th << " rad/s (elastic tilt at uplift " << phi_e << " rad); slide_x then "
            << slide << " m (mesh lead (dt/2) v " << kDt / 2 * ramp.velocity(d.t) << " m); run "
            << wall_seconds() - start << " s\n";
  RecordProperty("uplift_acceleration", num(d.a));
  RecordProperty("uplift_error_percent", num(100 * (d.a / a_ref - 1)));
  // Issue 2 acceptance: 2 %. The measurement is biased by at most `bound`
  // (0.4 %) upward, and the contact-point geometry (the spheres touch the
  // table rbase below the pivot: uplift at g b/(h + rbase), -0.2 %) downward.
  EXPECT_NEAR(d.a, a_ref, 0.02 * a_ref);
  // It rocked, it did not slide (mu g = 0.8 g, far above the 0.26 g
  // reached). slide_x is not exactly zero: the mesh leads fix shaketable's
  // exact displacement by (dt/2) v (printed above, 5e-5 m at the 5 m/s the
  // table reaches), plus ~1e-5 m of tangential spring compliance. 0.1 mm
  // bounds both and catches a compute or a table that mixes rocking into
  // slide_x (the base centre moves b theta = 1e-4 m at theta = 1e-3 rad).
  EXPECT_LT(std::fabs(slide), 1e-4);
}

// Slip of the squat block (b/h = 1.25 > mu, so it slides and never rocks),
// mu = 0.2, at |a| = mu g.
//
// Detection: the sliding velocity d(slide_x)/dt (finite difference over
// 10 ms) exceeds v_th. Before slip, slide_x drifts for two reasons: the mesh
// moves by v(t_{n+1}) dt per step, so it leads fix shaketable's exact
// displacement by (dt/2) v(t) (docs/fix_shaketable.md), an apparent rate
// (dt/2) a <= 2.2e-5 m/s; and the corners' tangential springs load
// elastically, about mu F / k_t = 1e-5 m over the ramp, 1e-6 m/s. v_th is ten
// times their sum. After slip the rigid-plastic block slides at
// rate tau^2 / 2 relative to the table, so the detection lags slip by at most
//   delta_a = sqrt(2 (v_th + (dt/2) a) rate) + rate * 10 ms.
TEST(Validation, SlipAtMuG) {
  const double start = wall_seconds();
  const fs::path dir = fresh_dir("slip");
  const std::string clump = make_clump(dir, "slide_block", kSlideBlock);
  const double mu = 0.2, a_ref = mu * kGravity;
  const Ramp ramp{a_ref, 0.25};
  const auto rows = run_table(dir, clump, mu, ramp.write(dir / "ramp.txt"),
                              kSettle + ramp.t_end(), ramp.travel());

  const double artefact = kDt / 2 * 1.1 * a_ref;
  const double elastic = 1e-5 * ramp.rate / a_ref;
  const double v_th = 10 * (artefact + elastic);
  const double bound = std::sqrt(2 * (v_th + artefact) * ramp.rate) + ramp.rate * 0.01;
  // The block lags the table, which accelerates toward +x: slide_x < 0.
  const Detection d = detect(rows, 6, -1.0, v_th, ramp);
  ASSERT_FALSE(std::isnan(d.a)) << "no slip detected up to 1.05 mu g";
  double rock = 0;
  for (std::size_t k = 0; k <= d.index; ++k) rock = std::max(rock, std::fabs(rows[k][3]));

  std::cout << std::setprecision(5) << "[validation] slip: detected at a = " << d.a
            << " m/s^2 (t = " << d.t << " s), mu g = " << a_ref << " m/s^2, error "
            << std::showpos << 100 * (d.a / a_ref - 1) << std::noshowpos
            << " %; detection delay bound " << 100 * bound / a_ref << " %; v_th = " << v_th
            << " m/s; max |rock_x| before " << rock << " rad; run " << wall_seconds() - start
            << " s\n";
  RecordProperty("slip_acceleration", num(d.a));
  RecordProperty("slip_error_percent", num(100 * (d.a / a_ref - 1)));
  // Issue 2 acceptance: 2 %; the detection bias is at most `bound` (0.55 %).
  EXPECT_NEAR(d.a, a_ref, 0.02 * a_ref);
  // It slid, it did not rock: the elastic tilt of the squat block on its
  // corners is ~3e-5 rad; a rocking block would pass 1e-3 rad.
  EXPECT_LT(rock, 1e-3);
}

// Runs the sine sliding case (see SineSlidingMatchesNewmark) and compares
// it with Newmark.
namespace {

struct SineResult {
  double peak = 0, peak_ref = 0, worst = 0, worst_t = 0, final_sim = 0, final_ref = 0;
  double peak_error() const { return peak / peak_ref - 1; }
  double history_error() const { return worst / peak_ref; }
};

SineResult sine_sliding(const std::string& name, const Variables& contact = {}) {
  const double start = wall_seconds();
  const fs::path dir = fresh_dir(name);
  const std::string clump = make_clump(dir, "slide_block", kSlideBlock);
  const double mu = 0.2, A = 0.35 * kGravity, f = 1.5, duration = 2.0, tail = 0.4;
  const double w = 2 * M_PI * f;
  const auto rows = run_table(dir, clump, mu,
                              "x sine amplitude " + num(A) + " m/s^2 frequency " + num(f) +
                                  " duration " + num(duration),
                              kSettle + duration + tail, 1.2 * A / w * duration, kPrint, contact);

  auto ag = [&](double t) { return t > 0 && t <= duration ? A * std::sin(w * t) : 0.0; };
  const auto ref = freestand::reference::newmark_sliding(ag, mu, mu, kGravity, duration + tail,
                                                         1e-4, 1e-6);
  SineResult r;
  for (double u : ref.u) r.peak_ref = std::max(r.peak_ref, std::fabs(u));
  for (const auto& row : rows) {
    const double tm = row[0] - kSettle;  // motion time
    const double s = row[6];
    r.peak = std::max(r.peak, std::fabs(s));
    if (tm < 0) continue;
    const double u = interpolate(ref.t, ref.u, tm);
    if (std::fabs(s - u) > r.worst) r.worst = std::fabs(s - u), r.worst_t = tm;
    r.final_ref = u, r.final_sim = s;
  }
  std::string label;
  for (const auto& [k, v] : contact) label += " " + k + " = " + v;
  std::cout << std::setprecision(5) << "[validation] sine sliding" << label << ": peak |slide_x| "
            << r.peak << " m, Newmark " << r.peak_ref << " m, error " << std::showpos
            << 100 * r.peak_error() << std::noshowpos << " %; max |slide_x - u| " << r.worst
            << " m at t = " << r.worst_t << " s = " << 100 * r.history_error()
            << " % of the peak; residual " << r.final_sim << " m (Newmark " << r.final_ref
            << " m); run " << wall_seconds() - start << " s\n";
  return r;
}

}  // namespace

// Sliding on a sinusoidal table: fix shaketable's analytic sine, 0.35 g
// (g = 9.81 as the simulation's gravity), 1.5 Hz, 3 cycles, then 0.4 s at
// rest; squat block, mu = 0.2. Reference: Newmark's rigid-plastic block,
// mu_s = mu_k = 0.2 (LIGGGHTS' Coulomb friction has one coefficient).
// Metrics, with u the Newmark slide and s the measured slide_x:
//   peak error = max|s| / max|u| - 1,
//   history error = max_t |s(t) - u(t)| / max|u| (every 1 ms),
// both within 2 % (issue 2). The reference is converged to ~1e-6 of the
// peak (dt = 1e-6 s); the mesh table's position error is < 1e-5 m (< 0.03 %
// of the 35 mm peak).
TEST(Validation, SineSlidingMatchesNewmark) {
  const SineResult r = sine_sliding("sine_sliding");
  ASSERT_GT(r.peak_ref, 0.01);  // the test slides centimetres
  RecordProperty("peak_error_percent", num(100 * r.peak_error()));
  RecordProperty("history_error_percent", num(100 * r.history_error()));
  EXPECT_LT(std::fabs(r.peak_error()), 0.02);
  EXPECT_LT(r.history_error(), 0.02);
}

// Informational, not part of the suite (--gtest_also_run_disabled_tests):
// the sine sliding error under other restitutions and the stock contact.
// In the DEM a stop is not instantaneous: the corners' tangential springs,
// loaded to mu F_n while sliding, swing back when the block stops, and only
// their damping (set by en; tangential_damping off removes it) keeps that
// swing from restarting the slide early. Asserts nothing.
TEST(Validation, DISABLED_SineSlidingContactSensitivity) {
  for (const Variables& contact :
       {Variables{{"en", "0.051"}, {"limit", "on"}}, Variables{{"en", "0.3"}, {"limit", "on"}},
        Variables{{"en", "0.61"}, {"limit", "on"}}, Variables{{"en", "0.61"}, {"limit", "off"}},
        Variables{{"en", "0.9"}, {"limit", "on"}},
        Variables{{"en", "0.051"}, {"limit", "on"}, {"tdamp", "off"}}})
    sine_sliding("sine_sliding_sensitivity", contact);
}

namespace {

// Block at rest on a still table (fix shaketable defined, zero motion) for
// 5 s after settling. Returns the largest displacement of any point of the
// block after settling, bounded by |d(base centre)| + L |d(angles)|, L the
// distance from the base centre to a top corner.
void at_rest(const std::string& name, const BlockClump& block) {
  const double start = wall_seconds();
  const fs::path dir = fresh_dir("rest_" + name);
  const std::string clump = make_clump(dir, name, block);
  const fs::path zero = dir / "zero.txt";
  std::ofstream(zero) << "0 0\n10 0\n";
  const auto rows = run_table(dir, clump, 0.2, "x record " + zero.string() + " units m/s^2",
                              kSettle + 5.0, 0.0, 500);
  const double L = std::sqrt(std::pow(block.width / 2, 2) + std::pow(block.depth / 2, 2) +
                             std::pow(block.height, 2));
  std::size_t k0 = 0;
  while (rows[k0][0] < kSettle - 1e-9) ++k0;
  const auto& r0 = rows[k0];
  double after = 0, total = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    // From insertion (channels are relative to the insertion pose) ...
    const double all = std::sqrt(r[6] * r[6] + r[7] * r[7] + r[8] * r[8]) +
                       L * (std::fabs(r[3]) + std::fabs(r[4]) + std::fabs(r[5]));
    total = std::max(total, all);
    if (k < k0) continue;
    // ... and after settling.
    const double moved = std::sqrt(std::pow(r[6] - r0[6], 2) + std::pow(r[7] - r0[7], 2) +
                                   std::pow(r[8] - r0[8], 2)) +
                         L * (std::fabs(r[3] - r0[3]) + std::fabs(r[4] - r0[4]) +
                              std::fabs(r[5] - r0[5]));
    after = std::max(after, moved);
  }
  // The settling sink is the static Hertz overlap of the four corners.
  const double sink = -r0[8], sink_ref = hertz_overlap(block.mass * kGravity / 4);
  std::cout << std::setprecision(4) << "[validation] at rest, " << name
            << ": largest displacement in 5 s after settling " << after
            << " m; from insertion (settling included) " << total << " m; settling sink "
            << sink << " m, Hertz " << sink_ref << " m; run " << wall_seconds() - start << " s\n";
  ::testing::Test::RecordProperty(name + "_moved_after_settling_m", num(after));
  ::testing::Test::RecordProperty(name + "_moved_from_insertion_m", num(total));
  // Issue 2: less than 0.1 mm in 5 s, counted from insertion (the stricter
  // reading: it includes the elastic sink of settling).
  EXPECT_LT(total, 1e-4);
  EXPECT_LT(after, 1e-4);
  // The four corners carry m g / 4 each, so the sink is Hertz's static
  // overlap; 1 % allows for what is left of the settling vibration.
  EXPECT_NEAR(sink, sink_ref, 0.01 * sink_ref);
}

}  // namespace

TEST(Validation, BlockAtRestStaysPut) {
  at_rest("rock_block", kRockBlock);
  at_rest("slide_block", kSlideBlock);
}
