// Energy ledger of fix rigid/convex and pair convex (issue 3, section 4):
// kinetic + potential + elastic + dissipated (normal damping, friction),
// each measured on its own (docs/fix_rigid_convex.md, "Energy ledger"),
// minus its initial value equals the work done by the table, within 1 % of
// the largest of those terms; without a table the total is constant within
// 1 % of the energy dissipated.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <tuple>

#include "run_command.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;
using nlohmann::json;

namespace {

// Columns of the runs' output: time, then f_bodies[1..8] (kinetic, table
// contacts, potential, elastic, normal dissipation, friction dissipation,
// table work, balance), then rock_x and slide_x of body `index`.
struct Ledger {
  double worst = 0;      // largest |KE + PE + E_el + D - (KE + PE + E_el)_0 - W| (J)
  double scale = 0;      // largest of |W|, D, |Delta KE|, |Delta PE|, |Delta E_el| (J)
  double dissipated_normal = 0, dissipated_friction = 0, work = 0;  // at the end (J)
  double peak_kinetic = 0, peak_rock = 0, peak_slide = 0;
  double peak_work = 0;  // largest |W| on the way (J)
};

Ledger run(const std::string& name, const json& scene, const std::string& table, bool pair,
           double dt, double tend, int index) {
  const fs::path dir = fv::fresh_dir(name);
  std::ofstream(dir / "scene.json") << scene.dump(1);
  std::ofstream script(dir / "run.in");
  script << fv::convex_preamble(4, 4, -1, 6) << "timestep " << fv::num(dt) << "\n"
         << table << "\n"
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string()
         << " tangential_damping normal" << (table.empty() ? "" : " table shake") << "\n"
         << (pair ? "pair_style convex pass_weight 1\npair_coeff * *\n" : "")
         << "fix grav all gravity 9.81 vector 0 0 -1\n"
         << "compute rs all rockslide bodies" << (table.empty() ? "" : " table shake") << "\n"
         << "variable t equal time\n";
  std::string line = "${t}";
  for (int k = 1; k <= 8; ++k) {
    script << "variable e" << k << " equal f_bodies[" << k << "]\n";
    line += " ${e" + std::to_string(k) + "}";
  }
  script << "variable r equal c_rs[" << index << "][1]\nvariable s equal c_rs[" << index << "][4]\n"
         << "fix out all print " << std::max(1L, std::lround(1e-3 / dt)) << " \"" << line
         << " ${r} ${s}\" file " << (dir / "out.txt").string() << " screen no\n"
         << "run " << std::lround(tend / dt) << "\n";
  script.close();
  fv::run_input((dir / "run.in").string(), {});
  const auto rows = fv::read_rows(dir / "out.txt", 11);
  Ledger l;
  const auto& first = rows.front();
  for (const auto& row : rows) {
    const double dke = row[1] - first[1], dpe = row[3] - first[3], del = row[4] - first[4];
    // Reference state: the first output (1 ms in; fix print does not print step 0).
    const double d = row[5] + row[6] - first[5] - first[6], w = row[7] - first[7];
    l.worst = std::max(l.worst, std::fabs(dke + dpe + del + d - w));
    l.scale = std::max({l.scale, std::fabs(w), d, std::fabs(dke), std::fabs(dpe), std::fabs(del)});
    l.peak_kinetic = std::max(l.peak_kinetic, row[1]);
    l.peak_work = std::max(l.peak_work, std::fabs(w));
    l.peak_rock = std::max(l.peak_rock, std::fabs(row[9]));
    l.peak_slide = std::max(l.peak_slide, std::fabs(row[10]));
    // The fix's own balance column is the same sum.
    EXPECT_NEAR(row[8] - first[8], dke + dpe + del + d - w, 1e-9 * (1 + l.scale));
  }
  l.dissipated_normal = rows.back()[5] - first[5];
  l.dissipated_friction = rows.back()[6] - first[6];
  l.work = rows.back()[7] - first[7];
  return l;
}

void report(const std::string& what, const Ledger& l) {
  std::cout << "[validation] energy ledger, " << what << ": table work " << l.work
            << " J, normal dissipation " << l.dissipated_normal << " J, friction "
            << l.dissipated_friction << " J, largest term " << l.scale << " J, worst imbalance "
            << l.worst << " J = " << 100 * l.worst / l.scale << " % (peak KE " << l.peak_kinetic
            << " J, rock_x " << l.peak_rock << " rad, slide " << l.peak_slide << " m)\n";
}

// The seed paper's tower (R = 1.55 m, alpha = 13.5 deg, marble), base at z0,
// tilted by `tilt` about its +x base edge (0: upright).
json tower(double z0, double tilt) {
  const double b = 1.55 * std::sin(13.5 * M_PI / 180), h = 1.55 * std::cos(13.5 * M_PI / 180);
  return {{"name", "tower"}, {"shape", "box"}, {"half_extents", {b, b, h}}, {"density", 2700},
          {"position", {b - b * std::cos(tilt), 0.0, z0 + b * std::sin(tilt)}},
          {"orientation", {std::cos(tilt / 2), 0.0, std::sin(tilt / 2), 0.0}},
          {"nodes", {{"layout", "vertices"}}}, {"supported_by", "pedestal"}};
}

// The tower on a marble pedestal (0.91 m, 33 deg: 4.1 t) on the table,
// the stack shifted by x0 along x.
json tower_on_pedestal(double tilt, double x0 = 0.0) {
  const double bp = 0.91 * std::sin(33 * M_PI / 180), hp = 0.91 * std::cos(33 * M_PI / 180);
  json pedestal = {{"name", "pedestal"}, {"shape", "box"}, {"half_extents", {bp, bp, hp}},
                   {"density", 2700}, {"position", {0.0, 0.0, 0.0}}, {"nodes", {{"layout", "vertices"}}}};
  pedestal["position"][0] = x0;
  json upper = tower(2 * hp, tilt);
  upper["position"][0] = upper["position"][0].get<double>() + x0;
  return {{"bodies", {pedestal, upper}},
          {"interfaces", {{{"lower", "table"}, {"upper", "pedestal"}, {"mu", 0.6}, {"restitution", 0.01},
                           {"contact_stiffness", 1e12}},
                          {{"lower", "pedestal"}, {"upper", "tower"}, {"mu", 0.6}, {"restitution", 0.01}}}}};
}

}  // namespace

TEST(ConvexEnergy, BlockRockingAndSlidingOnSineTable) {
  // 0.4 x 0.4 x 1.0 m, 400 kg (b/h = 0.4), mu 0.45, corner contact: rocks
  // under 0.5 g at 2.5 Hz for 3 s, then 1 s of free motion, and slides a
  // little at its impacts. dt = 2e-6 s: the ledger's error is O(dt), from
  // the dashpot switching on at each corner impact (1.3 % at 1e-5 s).
  const json scene = {
      {"bodies", {{{"name", "block"}, {"shape", "box"}, {"half_extents", {0.2, 0.2, 0.5}}, {"mass", 400},
                   {"nodes", {{"layout", "vertices"}}}}}},
      {"interfaces", {{{"lower", "table"}, {"upper", "block"}, {"mu", 0.45}, {"restitution", 0.1}}}}};
  const Ledger l = run("convex_energy_block", scene,
                       "fix shake all shaketable x sine amplitude 0.5 g frequency 2.5 duration 3", false,
                       2e-6, 4.0, 1);
  report("block rocking and sliding on a sine table (0.5 g, 2.5 Hz, 3 s + 1 s)", l);
  EXPECT_LT(l.worst, 0.01 * l.scale);
  EXPECT_GT(l.peak_rock, 0.01);       // it rocked
  EXPECT_GT(l.peak_slide, 5e-4);      // and slid
  EXPECT_GT(l.dissipated_normal, 0.0);
  EXPECT_GT(l.dissipated_friction, 0.0);
}

TEST(ConvexEnergy, TowerRockingOnPedestalOnSineTable) {
  const Ledger l = run("convex_energy_tower_table", tower_on_pedestal(0.0),
                       "fix shake all shaketable x sine amplitude 0.4 g frequency 1 duration 3", true,
                       2e-6, 3.0, 2);
  report("tower rocking on a pedestal (pair convex) on a sine table (0.4 g, 1 Hz, 3 s)", l);
  EXPECT_LT(l.worst, 0.01 * l.scale);
  EXPECT_GT(l.peak_rock, 0.01);
}

TEST(ConvexEnergy, BlockOnAPitchingAndRollingTable) {
  // 0.4 m cube, 100 kg, standing 0.5 m from the table's pivot, on a table
  // that pitches (2 Hz) and rolls (2.5 Hz) by about 0.05 rad: the table
  // lifts and tilts it, so the table's work is mostly the rotation's (the
  // plane's velocity at each node includes omega x r). The records are 8 and
  // 5 rad/s^2 sines for 1 s, baseline-corrected so the table ends level;
  // 0.2 s of rest follow. Same 1 % criterion as above; without the omega x r
  // term the work would miss the potential energy the tilt gives the block
  // (m g 0.5 m 0.05 rad ~ 25 J).
  const fs::path dir = fv::fresh_dir("convex_energy_pitch_records");
  for (const auto& [name, amplitude, frequency] : {std::tuple{"pitch.txt", 8.0, 2.0}, std::tuple{"roll.txt", 5.0, 2.5}}) {
    std::ofstream record(dir / name);
    record.precision(17);
    for (int i = 0; i <= 200; ++i) record << i / 200.0 << " " << amplitude * std::sin(2 * M_PI * frequency * i / 200.0) << "\n";
  }
  const json scene = {
      {"bodies", {{{"name", "block"}, {"shape", "box"}, {"half_extents", {0.2, 0.2, 0.2}}, {"mass", 100},
                   {"position", {0.5, 0.0, 0.0}}, {"nodes", {{"layout", "vertices"}}}}}},
      {"interfaces", {{{"lower", "table"}, {"upper", "block"}, {"mu", 0.6}, {"restitution", 0.1}}}}};
  const std::string table = "fix shake all shaketable pitch record " + (dir / "pitch.txt").string() +
                            " units rad/s^2 baseline yes roll record " + (dir / "roll.txt").string() +
                            " units rad/s^2 baseline yes";
  const Ledger l = run("convex_energy_pitch", scene, table, false, 1e-5, 1.2, 1);
  report("block on a pitching and rolling table (0.5 m from the pivot, 1 s + 0.2 s)", l);
  EXPECT_LT(l.worst, 0.01 * l.scale);
  std::cout << "[validation] energy ledger, pitching table: largest |table work| on the way " << l.peak_work << " J\n";
  EXPECT_GT(l.peak_work, 10.0);  // the table did work on it (and took it back as it levelled)
}

TEST(ConvexEnergy, FreeRockingConservesTheTotal) {
  // No table motion: the total is constant within 1 % of what is dissipated.
  const Ledger block = run("convex_energy_free_block",
                           json::parse(std::ifstream(fv::source_path("inputs/convex/free_rocking_block.json"))),
                           "", false, 2e-6, 3.0, 1);
  report("free rocking block (inputs/convex/free_rocking_block.json, 3 s)", block);
  std::cout << "[validation] energy ledger, free rocking block: worst imbalance "
            << 100 * block.worst / (block.dissipated_normal + block.dissipated_friction)
            << " % of the energy dissipated\n";
  EXPECT_EQ(block.work, 0.0);
  EXPECT_LT(block.worst, 0.01 * (block.dissipated_normal + block.dissipated_friction));
  const Ledger tower = run("convex_energy_free_tower", tower_on_pedestal(0.5 * 13.5 * M_PI / 180), "", true,
                           2e-6, 3.0, 2);
  report("free rocking tower on a pedestal (pair convex, released from alpha/2, 3 s)", tower);
  std::cout << "[validation] energy ledger, free rocking tower on a pedestal: worst imbalance "
            << 100 * tower.worst / (tower.dissipated_normal + tower.dissipated_friction)
            << " % of the energy dissipated\n";
  EXPECT_EQ(tower.work, 0.0);
  EXPECT_LT(tower.worst, 0.01 * (tower.dissipated_normal + tower.dissipated_friction));
}

TEST(ConvexEnergy, LedgerOfAPairSplitOverTwoRanksMatchesSerial) {
  // The rocking stack shifted so that the pedestal and the tower live on
  // different ranks of `processors * 1 1`: each rank counts half of the pair's
  // contacts, and the ledger must equal the serial one (to round-off: the
  // sums are taken in another order).
  run("convex_energy_split", tower_on_pedestal(0.5 * 13.5 * M_PI / 180, -0.05), "", true, 2e-6, 1.0, 2);
  const fs::path dir = fs::current_path() / "validation" / "convex_energy_split";
  fs::rename(dir / "out.txt", dir / "serial.txt");
  ASSERT_EQ(freestand::testing::run_command(freestand::testing::mpirun(2) + " " FREESTAND_LMP " -in " +
                                            (dir / "run.in").string() + " -log none -screen /dev/null"),
            0);
  const auto serial = fv::read_rows(dir / "serial.txt", 11), np2 = fv::read_rows(dir / "out.txt", 11);
  ASSERT_EQ(serial.size(), np2.size());
  double worst = 0;
  for (std::size_t k = 0; k < serial.size(); ++k)
    for (int c = 3; c <= 8; ++c)
      worst = std::max(worst, std::fabs(serial[k][c] - np2[k][c]) / (1.0 + std::fabs(serial[k][c])));
  std::cout << "[validation] energy ledger, stack split over two ranks: largest relative difference "
               "from serial in f_bodies[3..8] "
            << worst << " (pair elastic " << serial.back()[4] << " J, normal dissipation "
            << serial.back()[5] << " J)\n";
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(serial.back()[5], 10.0);  // the tower has had its first impacts
}
