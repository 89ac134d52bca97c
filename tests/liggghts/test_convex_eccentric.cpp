// Eccentric convex bodies on the shake table (fix rigid/convex): a block
// whose centre of mass is off its base centre uplifts about the edge the
// statics predicts, at the table acceleration the statics predicts, and a
// body eccentric in both x and y twists under x-only shaking while a body
// symmetric about the x-z plane does not. docs/validation.md, section
// "Convex bodies: eccentricity and twist". The same uplift thresholds for
// bases that are not flat (body "base"): crushed edges and a sloped base,
// section "Convex bodies: bases that are not flat".

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;

namespace {

constexpr double kG = 9.81;

const std::string kSetup = fv::convex_preamble(40, 10, -1, 4);

// Columns of the rows run_body returns.
enum Column { kTime, kTableAx, kRockX, kRockY, kTwist, kSlideX, kContacts, kColumns };

// Writes the scene and a script printing the columns above every `every`
// steps (fix rigid/convex, tangential_damping normal, k_a = 1e10 N/m^3);
// runs it; returns the rows.
std::vector<std::vector<double>> run_body(const std::string& name, const std::string& scene,
                                          const std::string& motion, double dt, double tend,
                                          int every) {
  const fs::path dir = fv::fresh_dir(name);
  std::ofstream(dir / "scene.json") << scene;
  const fs::path out = dir / "out.txt";
  std::ofstream script(dir / "run.in");
  script << kSetup << "timestep " << fv::num(dt) << "\n"
         << "fix shake all shaketable " << motion << "\n"
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string()
         << " table shake stiffness 1e10 restitution 0.1 tangential_damping normal\n"
         << "fix grav all gravity 9.81 vector 0 0 -1\n"
         << "compute rs all rockslide bodies table shake\n"
         << "variable t equal time\nvariable a equal f_shake[1]\n"
         << "variable rx equal c_rs[1][1]\nvariable ry equal c_rs[1][2]\n"
         << "variable tw equal c_rs[1][3]\nvariable sx equal c_rs[1][4]\n"
         << "variable nc equal f_bodies[2]\n"
         << "fix out all print " << every << " \"${t} ${a} ${rx} ${ry} ${tw} ${sx} ${nc}\" file "
         << out.string() << " screen no\n"
         << "run " << static_cast<long>(std::llround(tend / dt)) << "\n";
  script.close();
  fv::run_input((dir / "run.in").string(), {});
  return fv::read_rows(out, kColumns);
}

// The eccentric block: 0.5 x 0.5 x 1.0 m (half widths b = d = 0.25 m), 600 kg,
// centre of mass stated at (e, 0, h) = (0.05, 0, 0.5) m, corner contact.
// Friction 1.5 is far above what rocking needs at these accelerations
// (benchmarks.md 2.1: mu_req = beta at lambda = beta, beta <= 0.6), so it
// cannot slide.
const double kB = 0.25, kE = 0.05, kH = 0.5;
const char* kEccentricBlock = R"({"bodies": [{"name": "block", "shape": "box",
    "half_extents": [0.25, 0.25, 0.5], "mass": 600, "com": [0.05, 0, 0.5],
    "nodes": {"layout": "vertices"}}],
    "interfaces": [{"lower": "table", "upper": "block", "mu": 1.5}]})";

struct Onset {
  double table_acceleration;  // f_shake[1] at the first sample with a base corner off the table
  double rock_x;              // rock_x 0.2 s later (sign: the side it leans to)
};

// Table acceleration along x: 0 for 0.3 s (the block settles on its
// corners), then a linear ramp to `a_end` over 2 s. Uplift is detected
// exactly, without a rate threshold: the linear contact's force is
// proportional to the overlap, so a corner's force reaches zero in the
// same step as its overlap, and fix rigid/convex's contact count
// (f_bodies[2]) drops from 4 to 2 when the heel corners' force does.
Onset ramp_onset(const std::string& name, const std::string& scene, double a_end) {
  const fs::path dir = fv::fresh_dir(name + "_record");
  const fs::path record = dir / "ramp.txt";
  std::ofstream(record) << std::setprecision(17) << "0 0\n0.3 0\n2.3 " << a_end << "\n";
  const auto rows = run_body(name, scene,
                             "x record " + record.string() + " units m/s^2", 2e-5, 2.3, 5);
  Onset onset{NAN, NAN};
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (rows[k][kTime] < 0.3 || rows[k][kContacts] > 3.5) continue;
    onset.table_acceleration = rows[k][kTableAx];
    EXPECT_EQ(rows[k][kContacts], 2.0) << "a whole edge lifts, not one corner";
    for (std::size_t j = k; j < rows.size(); ++j)
      if (rows[j][kTime] <= rows[k][kTime] + 0.2) onset.rock_x = rows[j][kRockX];
    break;
  }
  return onset;
}

}  // namespace

TEST(ConvexEccentric, EccentricBlockUpliftsAtTheStaticThresholdOnThePredictedSide) {
  // Statics (benchmarks.md section 4 for one block): the block uplifts about
  // a base edge when the moment of the inertial force -m a_table about that
  // edge exceeds the moment of its weight: |a| h = g x_pivot, x_pivot the
  // horizontal distance from the edge to the COM.
  //   about the +x edge (table accelerating toward -x, it leans toward +x):
  //     |a| = g (b - e) / h = 9.81 * 0.20 / 0.5 = 3.924 m/s^2
  //   about the -x edge (table accelerating toward +x, it leans toward -x):
  //     |a| = g (b + e) / h = 9.81 * 0.30 / 0.5 = 5.886 m/s^2
  // (a centred block: g b / h = 4.905 m/s^2 both ways.)
  // What separates the model from the rigid statics: the compliant corners
  // let the block tilt elastically before uplift, by phi = (m g / 2) /
  // (k_node 2b) with k_node = k_a A / 4 = 6.25e8 N/m: 9.4e-6 rad, which moves
  // the COM toward the pivot by h phi = 4.7e-6 m, 2.4e-5 of (b - e); and the
  // ramp (rate 3.24 m/s^3) against the contact's vibration (about 2000
  // rad/s, damping ratio 0.59) lags the quasi-static load by 2 zeta rate /
  // omega = 1.9e-3 m/s^2, 5e-4 of 3.924 (measured: +0.064 %, and +0.011 %
  // with the ramp 5 times slower, so it is this lag). Tolerance: 2 %
  // (issue 3), far above both.
  const double plus_edge = kG * (kB - kE) / kH, minus_edge = kG * (kB + kE) / kH;
  const Onset toward_plus = ramp_onset("eccentric_ramp_minus_x", kEccentricBlock, -1.1 * minus_edge);
  const Onset toward_minus = ramp_onset("eccentric_ramp_plus_x", kEccentricBlock, 1.1 * minus_edge);
  std::cout << "[validation] eccentric block, table toward -x: uplift at |a| = "
            << -toward_plus.table_acceleration << " m/s^2 (statics about the +x edge "
            << plus_edge << ", error "
            << 100 * (-toward_plus.table_acceleration / plus_edge - 1) << " %), rock_x 0.2 s later "
            << toward_plus.rock_x << " rad\n";
  std::cout << "[validation] eccentric block, table toward +x: uplift at |a| = "
            << toward_minus.table_acceleration << " m/s^2 (statics about the -x edge "
            << minus_edge << ", error " << 100 * (toward_minus.table_acceleration / minus_edge - 1)
            << " %), rock_x 0.2 s later " << toward_minus.rock_x << " rad\n";
  ASSERT_TRUE(std::isfinite(toward_plus.table_acceleration)) << "no uplift toward +x";
  ASSERT_TRUE(std::isfinite(toward_minus.table_acceleration)) << "no uplift toward -x";
  EXPECT_NEAR(-toward_plus.table_acceleration, plus_edge, 0.02 * plus_edge);
  EXPECT_NEAR(toward_minus.table_acceleration, minus_edge, 0.02 * minus_edge);
  EXPECT_GT(toward_plus.rock_x, 1e-3);    // leans toward +x, about the +x edge
  EXPECT_LT(toward_minus.rock_x, -1e-3);  // leans toward -x, about the -x edge
}

namespace {

// A statue-like clump: a 0.6 x 0.6 x 0.3 m plinth and a 0.3 x 0.3 x 0.9 m
// upper block whose centre is at (ox, oy) from the plinth's axis; 2700
// kg/m^3, corner contact, friction 0.8.
std::string statue(double ox, double oy) {
  return R"({"bodies": [{"name": "statue", "shape": "clump", "density": 2700,
    "nodes": {"layout": "vertices"}, "pieces": [
      {"shape": "box", "half_extents": [0.3, 0.3, 0.15]},
      {"shape": "box", "half_extents": [0.15, 0.15, 0.45], "offset": [)" +
         fv::num(ox) + ", " + fv::num(oy) + R"(, 0.3]}]}],
    "interfaces": [{"lower": "table", "upper": "statue", "mu": 0.8}]})";
}

double peak_abs(const std::vector<std::vector<double>>& rows, int column) {
  double peak = 0;
  for (const auto& row : rows) peak = std::max(peak, std::fabs(row[column]));
  return peak;
}

}  // namespace

TEST(ConvexEccentric, BodyEccentricInXAndYTwistsUnderXShakingSymmetricOneDoesNot) {
  // x-only table motion: 0.8 g sine at 2 Hz for 3 s, then 1 s at rest.
  // Both statues lean toward +x (upper block 0.12 m off axis in x); the
  // first also 0.12 m in y. Mirror symmetry about the x-z plane: a body
  // symmetric about it, shaken along x, gets mirror-symmetric contact
  // forces, so its torque about z, and its twist, rock_y and slide_y, are
  // zero up to round-off. Round-off bound: the mirror nodes' coordinates
  // differ by ~1e-16 m (the COM's y from the mass integrals), a relative
  // torque imbalance of ~1e-16; at most it grows like the rocking's
  // instability, e^(p t) with p = sqrt(m g R / I_O) = 3.6 rad/s for this
  // clump (m 510 kg, R 0.48 m from the +x edge to the COM, I_O 190 kg m^2),
  // so by 1.5e6 over 4 s: 1.5e-10 rad. 1e-9 rad is above that and six
  // orders below the twist asked of the eccentric body (> 1e-3 rad).
  const std::string motion = "x sine amplitude 0.8 g frequency 2 duration 3";
  const auto eccentric = run_body("eccentric_twist_xy", statue(0.12, 0.12), motion, 2e-5, 4.0, 25);
  const auto symmetric = run_body("eccentric_twist_x", statue(0.12, 0.0), motion, 2e-5, 4.0, 25);
  const double twist_xy = peak_abs(eccentric, kTwist), twist_x = peak_abs(symmetric, kTwist);
  std::cout << "[validation] statue eccentric in x and y: peak |twist| " << twist_xy
            << " rad, final " << eccentric.back()[kTwist] << " rad, peak |rock_x| "
            << peak_abs(eccentric, kRockX) << " rad, peak |rock_y| " << peak_abs(eccentric, kRockY)
            << " rad\n";
  std::cout << "[validation] statue eccentric in x only: peak |twist| " << twist_x
            << " rad, peak |rock_x| " << peak_abs(symmetric, kRockX) << " rad, peak |rock_y| "
            << peak_abs(symmetric, kRockY) << " rad\n";
  EXPECT_GT(peak_abs(symmetric, kRockX), 1e-2);  // it rocks: the test is not trivial
  EXPECT_GT(twist_xy, 1e-3);
  EXPECT_LT(twist_x, 1e-9);
  EXPECT_LT(peak_abs(symmetric, kRockY), 1e-9);
}

namespace {

// A centred 0.5 x 0.5 x 1.0 m block, 600 kg, corner contact, with `base`,
// turned by `lean` about y (about its -x base edge, which stays at the origin).
std::string block_with_base(const std::string& base, double lean = 0.0) {
  return R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.25, 0.25, 0.5],
    "mass": 600, "nodes": {"layout": "vertices"}, "base": )" + base + R"(,
    "position": [)" + fv::num(kB * (std::cos(lean) - 1)) + ", 0, " + fv::num(-kB * std::sin(lean)) + R"(],
    "orientation": [)" + fv::num(std::cos(lean / 2)) + ", 0, " + fv::num(std::sin(lean / 2)) + R"(, 0]}],
    "interfaces": [{"lower": "table", "upper": "block", "mu": 1.5}]})";
}

}  // namespace

TEST(ConvexEccentric, CrushedEdgesUpliftAtTheNarrowerBasesThreshold) {
  // Edges crushed by d = 0.05 m: the pivots are the inset corners, the
  // effective half width b - d, so the block uplifts at |a| = g (b - d) / h
  // = 3.924 m/s^2 (the flat base's 4.905 m/s^2 would be 25 % off). The
  // model's departures from rigid statics are those of the eccentric block
  // above (same mass, stiffness, ramp): below 0.1 %; tolerance 2 %.
  const double d = 0.05, threshold = kG * (kB - d) / kH;
  const Onset onset = ramp_onset("crushed_edges_ramp", block_with_base(R"({"edge_inset": 0.05})"),
                                 1.1 * threshold);
  std::cout << "[validation] block with edges crushed by " << d << " m: uplift at |a| = "
            << onset.table_acceleration << " m/s^2 (statics g (b - d)/h = " << threshold << ", error "
            << 100 * (onset.table_acceleration / threshold - 1) << " %)\n";
  ASSERT_TRUE(std::isfinite(onset.table_acceleration)) << "no uplift";
  EXPECT_NEAR(onset.table_acceleration, threshold, 0.02 * threshold);
}

TEST(ConvexEccentric, SlopedBaseRocksAsymmetricallyAsItsStaticsSays) {
  // Both +x corners short by g = 10 mm: the base is the plane z = g (1 +
  // x/b) / 2, so the block stands leaning toward +x by atan(g / 2b). What is
  // checked: the uplift threshold toward each side is the rigid statics of
  // the leaning block, |a| = g_n (horizontal distance pivot-COM) / (height of
  // the COM above the pivot), measured along and across the base plane:
  //   pivot +x (body (b, 0, g)), pivot -x (body (-b, 0, 0)), COM (0, 0, h);
  //   u = (2b, 0, g)/L along the base, n = (-g, 0, 2b)/L into the body.
  // The two thresholds differ by about 10 %; tolerance 2 % as above.
  const double gap = 0.01, L = std::hypot(2 * kB, gap);
  const Eigen::Vector3d u(2 * kB / L, 0, gap / L), n(-gap / L, 0, 2 * kB / L), com(0, 0, kH);
  const Eigen::Vector3d plus_pivot(kB, 0, gap), minus_pivot(-kB, 0, 0);
  const double plus_edge = kG * (plus_pivot - com).dot(u) / (com - plus_pivot).dot(n);
  const double minus_edge = kG * (com - minus_pivot).dot(u) / (com - minus_pivot).dot(n);
  const double lean = std::atan(gap / (2 * kB));
  const std::string scene = block_with_base(
      R"({"corner_gaps": [{"corner": [1, 1], "gap": 0.01}, {"corner": [1, -1], "gap": 0.01}]})",
      lean);  // placed at rest on its sloped base
  const Onset toward_plus = ramp_onset("sloped_base_ramp_minus_x", scene, -1.1 * minus_edge);
  const Onset toward_minus = ramp_onset("sloped_base_ramp_plus_x", scene, 1.1 * minus_edge);
  std::cout << "[validation] sloped base (+x corners short by " << gap << " m): uplift toward +x at |a| = "
            << -toward_plus.table_acceleration << " m/s^2 (statics " << plus_edge << ", error "
            << 100 * (-toward_plus.table_acceleration / plus_edge - 1) << " %), toward -x at "
            << toward_minus.table_acceleration << " m/s^2 (statics " << minus_edge << ", error "
            << 100 * (toward_minus.table_acceleration / minus_edge - 1) << " %)\n";
  ASSERT_TRUE(std::isfinite(toward_plus.table_acceleration)) << "no uplift toward +x";
  ASSERT_TRUE(std::isfinite(toward_minus.table_acceleration)) << "no uplift toward -x";
  EXPECT_GT(minus_edge, 1.08 * plus_edge);  // the asymmetry is not within the tolerance
  EXPECT_NEAR(-toward_plus.table_acceleration, plus_edge, 0.02 * plus_edge);
  EXPECT_NEAR(toward_minus.table_acceleration, minus_edge, 0.02 * minus_edge);
  // rock_x is measured from the vertical: at rest it is the lean.
  EXPECT_GT(toward_plus.rock_x, lean + 1e-3);
  EXPECT_LT(toward_minus.rock_x, lean - 1e-3);
}
