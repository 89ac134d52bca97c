// Table pitch and bases that are not flat, in fix rigid/convex
// (docs/validation.md, "Convex bodies: table pitch, uneven and crushed
// bases"): a block on a slowly pitching table slides when tan(pitch) = mu
// and tips when tan(pitch) = b/h (its COM leaves the base), resting with
// the table before; a block with one base corner short rests on the other
// three, tilted by the plane through them, its corners loaded as statics
// says; a block with crushed edges rocks freely as Housner's map for the
// narrower base.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <fstream>
#include <iostream>

#include "../reference/housner.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;

namespace {

constexpr double kG = 9.81;

enum Column { kTime, kPitch, kRockX, kRockY, kTwist, kSlideX, kContacts, kColumns };

// Runs `scene` on a table moved by `motion` (fix shaketable arguments; empty:
// a fixed plane at z = 0) and returns the columns above every `every` steps.
std::vector<std::vector<double>> run_body(const std::string& name, const std::string& scene,
                                          const std::string& motion, double dt, double tend, int every,
                                          const std::string& contact = "stiffness 1e10 restitution 0.1") {
  const fs::path dir = fv::fresh_dir(name);
  std::ofstream(dir / "scene.json") << scene;
  const fs::path out = dir / "out.txt";
  const bool table = !motion.empty();
  std::ofstream script(dir / "run.in");
  script << fv::convex_preamble(4, 4, -2, 4) << "timestep " << fv::num(dt) << "\n"
         << (table ? "fix shake all shaketable " + motion + "\n" : "")
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string()
         << (table ? " table shake " : " plane 0 ") << contact << " tangential_damping normal\n"
         << "fix grav all gravity 9.81 vector 0 0 -1\n"
         << "compute rs all rockslide bodies" << (table ? " table shake" : "") << "\n"
         << "variable t equal time\nvariable p equal " << (table ? "f_shake[11]" : "0") << "\n"
         << "variable rx equal c_rs[1][1]\nvariable ry equal c_rs[1][2]\n"
         << "variable tw equal c_rs[1][3]\nvariable sx equal c_rs[1][4]\nvariable nc equal f_bodies[2]\n"
         << "fix out all print " << every << " \"${t} ${p} ${rx} ${ry} ${tw} ${sx} ${nc}\" file "
         << out.string() << " screen no\nthermo 1000000\n"
         << "run " << std::llround(tend / dt) << "\n";
  script.close();
  fv::run_input((dir / "run.in").string(), {});
  return fv::read_rows(out, kColumns);
}

// Pitch held at 0 for 0.2 s (the block settles), then 0.5 rad/s^2 for 0.4 s,
// after which the table turns on at 0.2 rad/s: a slow ramp of pitch.
const std::string kPitchRamp = "pitch rectangle amplitude 0.5 rad/s^2 width 0.4 start 0.2";
constexpr double kPitchRate = 0.2;  // rad/s after the first 0.6 s

std::string block(double b, double h, double mass, double mu) {
  return R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [)" + fv::num(b) + ", " +
         fv::num(b) + ", " + fv::num(h) + R"(], "mass": )" + fv::num(mass) +
         R"(, "nodes": {"layout": "vertices"}}], "interfaces": [{"lower": "table", "upper": "block", "mu": )" +
         fv::num(mu) + "}]}";
}

// First time `value` reaches `level`, linearly interpolated between rows.
double crossing(const std::vector<std::vector<double>>& rows, int column, double level) {
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (rows[k - 1][column] < level && rows[k][column] >= level)
      return rows[k - 1][kTime] + (rows[k][kTime] - rows[k - 1][kTime]) * (level - rows[k - 1][column]) /
                                      (rows[k][column] - rows[k - 1][column]);
  return NAN;
}

}  // namespace

TEST(ConvexTablePitch, BlockSlidesWhenTheTangentOfThePitchReachesMu) {
  // 0.4 x 0.4 x 0.2 m block, 100 kg, mu = 0.3: it cannot tip (b/h = 2 >
  // mu). Closed form: it stays on the table while tan(pitch) < mu and then
  // slides down the slope at a = g (sin(pitch) - mu cos(pitch)); with the
  // pitch ramping at w, a = g w (cos p* + mu sin p*) tau + O(tau^3) after the
  // onset p* = atan(mu) (the tau^2 term vanishes there), so the slide is
  // s = K tau^3 and the onset follows from the times t1, t2 at which it
  // reaches s1, s2: t* = (t1 - r t2) / (1 - r), r = (s1/s2)^(1/3). Neglected:
  // (w tau)^2 ~ 1e-3 of the cubic, the centripetal w^2 (0.1 m) = 0.004
  // m/s^2 (4e-4 g), the tangential spring's elastic slip (~1e-6 m << s1).
  // Tolerance 1 % of tan(p*).
  const double mu = 0.3;
  const auto rows = run_body("pitch_slide", block(0.2, 0.1, 100, mu), kPitchRamp, 2e-5, 2.1, 5);
  const double s1 = 1e-4, s2 = 1e-3, r = std::cbrt(s1 / s2);
  const double t1 = crossing(rows, kSlideX, s1), t2 = crossing(rows, kSlideX, s2);
  ASSERT_TRUE(std::isfinite(t1) && std::isfinite(t2)) << "the block did not slide down (+x)";
  const double onset = (t1 - r * t2) / (1 - r);
  double pitch = NAN;  // pitch at the onset, from the table's own output
  for (const auto& row : rows)
    if (row[kTime] <= t2) pitch = row[kPitch] - kPitchRate * (row[kTime] - onset);
  std::cout << "[validation] block on a pitching table (mu " << mu << "): slides from pitch " << pitch
            << " rad, tan " << std::tan(pitch) << " (closed form " << mu << ", error "
            << 100 * (std::tan(pitch) / mu - 1) << " %)\n";
  EXPECT_NEAR(std::tan(pitch), mu, 0.01 * mu);
}

TEST(ConvexTablePitch, BlockRestsWithTheTableUntilItsCentreOfMassLeavesTheBase) {
  // 0.2 x 0.2 x 0.6 m block, 100 kg, mu = 0.8 > b/h: it cannot slide first.
  // Statics: it rests on its four corners while its COM is over the base,
  // tan(pitch) < b/h, and tips about the downhill edge when tan(pitch) =
  // b/h = 1/3 (the uphill corners' force, hence their contact, drops to
  // zero: the contact count goes from 4 to 2, exactly, linear law). Before,
  // it turns with the table: rock_x = pitch up to its elastic tilt (moment
  // m g h sin p over 4 k_node b^2 = 4e6 N m/rad: < 2.5e-5 rad) and does not
  // slide relative to the table (elastic slip ~1e-6 m). Tolerances: 1 % of
  // the tipping tangent; 1e-4 rad and 1e-4 m at rest.
  const double b = 0.1, h = 0.3;
  const auto rows = run_body("pitch_tip", block(b, h, 100, 0.8), kPitchRamp, 2e-5, 2.1, 5);
  double tip = NAN, lean = 0, slip = 0;
  for (const auto& row : rows) {
    if (row[kTime] < 0.3) continue;
    if (row[kContacts] < 3.5) {
      tip = row[kPitch];
      EXPECT_EQ(row[kContacts], 2.0) << "the uphill edge lifts as a whole";
      break;
    }
    lean = std::max(lean, std::fabs(row[kRockX] - row[kPitch]));
    slip = std::max(slip, std::fabs(row[kSlideX]));
  }
  std::cout << "[validation] block on a pitching table (b/h " << b / h << "): tips at pitch " << tip
            << " rad, tan " << std::tan(tip) << " (statics " << b / h << ", error "
            << 100 * (std::tan(tip) * h / b - 1) << " %); before, |rock_x - pitch| <= " << lean
            << " rad, |slide| <= " << slip << " m\n";
  ASSERT_TRUE(std::isfinite(tip)) << "it did not tip";
  EXPECT_NEAR(std::tan(tip), b / h, 0.01 * b / h);
  EXPECT_LT(lean, 1e-4);
  EXPECT_LT(slip, 1e-4);
}

TEST(ConvexBase, OneShortCornerRestsOnTheOtherThreeTiltedByTheirPlane) {
  // 0.4 x 0.4 x 0.6 m block, 200 kg, COM stated at (-0.04, 0.04, 0.3),
  // corner (-b, +b) short by g = 1 mm, on a fixed plane. The COM lies over
  // the triangle of that corner and its two neighbours, so the block tips
  // onto the short corner and rests on A (b, b, 0), B (-b, b, g), C (-b, -b,
  // 0), the fourth corner lifted: 3 contacts. Tilt: the plane through A, B,
  // C is z = alpha x + beta y, alpha = -g/2b, beta = g/2b, and the block
  // rests with it level: rock_x = atan(alpha), rock_y = atan(beta). Statics:
  // the three corner forces F_i balance the weight about the COM (3x3, world
  // lever arms in the tilted pose); each corner sinks F_i / k_node (k_node =
  // k_a b^2 = 4e8 N/m), which tilts the plane by ~4e-6 rad more. The test
  // asks the measured tilt to match the plane with those sinkings to 1 % of
  // their effect: the corner forces follow statics to 1 % (measured 4e-5).
  const double b = 0.2, g = 1e-3, k_node = 1e10 * b * b, mass = 200;
  const std::string scene = R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.2, 0.2, 0.3],
      "mass": 200, "com": [-0.04, 0.04, 0.3], "nodes": {"layout": "vertices"},
      "base": {"corner_gaps": [{"corner": [-1, 1], "gap": 0.001}]}}],
      "interfaces": [{"lower": "table", "upper": "block", "mu": 0.8}]})";
  const auto rows = run_body("short_corner", scene, "", 2e-5, 0.5, 100);
  const auto& rest = rows.back();
  const Eigen::Vector3d A(b, b, 0), B(-b, b, g), C(-b, -b, 0), com(-0.04, 0.04, 0.3);
  auto tilt_of = [](const Eigen::Vector3d& a, const Eigen::Vector3d& bb, const Eigen::Vector3d& c) {
    const Eigen::Vector3d m = (bb - a).cross(c - a).normalized();  // into the body (z > 0)
    return Eigen::Vector2d(std::atan(-m.x() / m.z()), std::atan(-m.y() / m.z()));
  };
  const Eigen::Vector2d rigid = tilt_of(A, B, C);
  // Statics in the rigid resting pose (supports level, world lever arms).
  const Eigen::Quaterniond pose =
      Eigen::Quaterniond::FromTwoVectors((B - A).cross(C - A).normalized(), Eigen::Vector3d::UnitZ());
  Eigen::Matrix3d equations;
  const Eigen::Vector3d c = pose * com;
  int k = 0;
  for (const Eigen::Vector3d& s : {A, B, C}) {
    const Eigen::Vector3d p = pose * s;
    equations.col(k++) = Eigen::Vector3d(1.0, p.x() - c.x(), p.y() - c.y());
  }
  const Eigen::Vector3d force = equations.partialPivLu().solve(Eigen::Vector3d(mass * kG, 0, 0));
  const Eigen::Vector3d up(0, 0, 1);
  const Eigen::Vector2d compliant = tilt_of(A + force[0] / k_node * up, B + force[1] / k_node * up,
                                            C + force[2] / k_node * up);
  const Eigen::Vector2d measured(rest[kRockX], rest[kRockY]);
  std::cout << "[validation] block with one corner short by " << g << " m: rests on " << rest[kContacts]
            << " corners; rock_x, rock_y " << measured.transpose() << " rad (plane through the three "
            << rigid.transpose() << ", with the statics corner forces " << force.transpose()
            << " N and their sinking " << compliant.transpose() << "; difference from that "
            << (measured - compliant).norm() << " rad, compliance effect " << (compliant - rigid).norm()
            << " rad); twist " << rest[kTwist] << " rad\n";
  EXPECT_EQ(rest[kContacts], 3.0);
  EXPECT_GT(force.minCoeff(), 0.0);  // the COM is inside the triangle: all three press
  EXPECT_LT((measured - compliant).norm(), 0.01 * (compliant - rigid).norm());
}

TEST(ConvexBase, CrushedEdgesRockAsHousnersMapForTheNarrowerBase) {
  // A 0.3 x 0.3 x 1.0 m block, 100 kg, edges crushed by d = 0.025 m: its
  // pivots are at b' = b - d = 0.125 m while its inertia is the full
  // block's. Released at rest at half its (reduced) slenderness about the +x
  // pivot, it rocks as Housner's map and period for alpha' = atan(b'/h) and
  // I_O = m ((b^2 + h^2)/3 + R'^2) (tests/reference/housner.h). Contact set
  // to Housner's assumptions as in test_convex_rocking.cpp (corner nodes,
  // k_a = 1e10, restitution 0.01, tangential dashpot); there the flat block
  // is within 0.25 % at this dt. Tolerance 1 % (issue 3).
  const double b = 0.15, d = 0.025, h = 0.5;
  freestand::reference::HousnerBlock reduced{b - d, h};
  reduced.gyration2 = (b * b + h * h) / 3;
  const double theta0 = 0.5 * reduced.alpha(), pivot = b - d;
  const std::string scene = R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.15, 0.15, 0.5],
      "mass": 100, "nodes": {"layout": "vertices"}, "base": {"edge_inset": 0.025},
      "position": [)" + fv::num(pivot * (1 - std::cos(theta0))) + ", 0, " + fv::num(pivot * std::sin(theta0)) +
                            R"(], "orientation": [)" + fv::num(std::cos(theta0 / 2)) + ", 0, " +
                            fv::num(std::sin(theta0 / 2)) + R"(, 0]}],
      "interfaces": [{"lower": "table", "upper": "block", "mu": 0.6}]})";
  const auto rows = run_body("crushed_edges_rocking", scene, "", 4e-6, 2.75, 5, "stiffness 1e10 restitution 0.01");
  const fv::HousnerErrors errors = fv::housner_errors(fv::column(rows, kTime), fv::column(rows, kRockX), reduced, 5,
                                                      0.02 * reduced.alpha());
  ASSERT_EQ(errors.amplitude.size(), 5u);
  double worst = std::fabs(errors.first_impact);
  std::cout << "[validation] block with edges crushed by " << d << " m, free rocking (e' = " << reduced.e()
            << ", the rectangle of width 2b' would have " << freestand::reference::HousnerBlock{b - d, h}.e()
            << "): theta_n error %";
  for (double e : errors.amplitude) {
    std::cout << " " << 100 * e;
    worst = std::max(worst, std::fabs(e));
  }
  std::cout << "; half-cycle error %";
  for (double e : errors.half_cycle) {
    std::cout << " " << 100 * e;
    worst = std::max(worst, std::fabs(e));
  }
  std::cout << "; first impact " << 100 * errors.first_impact << " %\n";
  EXPECT_LT(worst, 0.01);
}
