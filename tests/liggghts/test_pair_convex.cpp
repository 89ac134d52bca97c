// pair_style convex: a tower rocking on a pedestal that cannot move (10^7 kg,
// stiff support) must rock as the same tower on the table (issue 3: within 1 %).

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "run_command.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;
using nlohmann::json;

namespace {

// The seed paper's tower: R = 1.55 m, alpha = 13.5 deg, marble; released
// from rest tilted by alpha/2 about its +x base edge, whose base is at z0.
json tower(double z0) {
  const double b = 1.55 * std::sin(13.5 * M_PI / 180), h = 1.55 * std::cos(13.5 * M_PI / 180);
  const double theta = 0.5 * std::atan(b / h);
  return {{"name", "tower"}, {"shape", "box"}, {"half_extents", {b, b, h}}, {"density", 2700},
          {"position", {b - b * std::cos(theta), 0.0, z0 + b * std::sin(theta)}},
          {"orientation", {std::cos(theta / 2), 0.0, std::sin(theta / 2), 0.0}},
          {"nodes", {{"layout", "vertices"}}}};
}

// The tower on a pedestal that cannot move: 1e7 kg on a stiff support (it
// sinks 1e-6 m under its own weight); the stack is shifted by x0.
json tower_on_pedestal(double x0) {
  const double bp = 0.91 * std::sin(33 * M_PI / 180), hp = 0.91 * std::cos(33 * M_PI / 180);
  json pedestal = {{"name", "pedestal"}, {"shape", "box"}, {"half_extents", {bp, bp, hp}},
                   {"mass", 1e7}, {"position", {x0, 0.0, 0.0}}, {"nodes", {{"layout", "vertices"}}}};
  json upper = tower(2 * hp);
  upper["supported_by"] = "pedestal";
  upper["position"][0] = upper["position"][0].get<double>() + x0;
  return {{"bodies", {pedestal, upper}},
          {"interfaces", {{{"lower", "table"}, {"upper", "pedestal"}, {"mu", 0.6}, {"restitution", 0.01},
                           {"contact_stiffness", 1e14}},
                          {{"lower", "pedestal"}, {"upper", "tower"}, {"mu", 0.6}, {"restitution", 0.01}}}}};
}

// Writes a scene and a script printing (time, rock_x of body `index`) every
// 1e-3 s for `steps` steps of 2e-6 s; returns the script's path.
fs::path write_run(const fs::path& dir, const json& scene, int index, long steps) {
  std::ofstream(dir / "scene.json") << scene.dump(1);
  std::ofstream script(dir / "run.in");
  script << fv::convex_preamble(4, 4, -1, 6) << "timestep 2e-6\n"
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string()
         << " tangential_damping normal\n"
         // Corner nodes against a face are seen by one of the two passes only:
         // full weight, so a corner is as stiff on the pedestal as on the table.
         << "pair_style convex pass_weight 1\npair_coeff * *\n"
            "fix grav all gravity 9.81 vector 0 0 -1\ncompute rs all rockslide bodies\n"
            "variable t equal time\nvariable r equal c_rs["
         << index << "][1]\nfix out all print 500 \"${t} ${r}\" file " << (dir / "out.txt").string()
         << " screen no\nrun " << steps << "\n";
  return dir / "run.in";
}

// Runs a scene in-process for 5 s; returns (time, rock_x of body `index`).
std::vector<std::vector<double>> rock(const std::string& name, const json& scene, int index) {
  const fs::path dir = fv::fresh_dir(name);
  fv::run_input(write_run(dir, scene, index, 2500000).string(), {});
  return fv::read_rows(dir / "out.txt", 2);
}

}  // namespace

TEST(PairConvex, TowerOnHeavyPedestalRocksAsOnTheTable) {
  const json interface_table = {{"lower", "table"}, {"upper", "tower"}, {"mu", 0.6}, {"restitution", 0.01}};
  const auto on_table = rock("pair_convex_table", {{"bodies", {tower(0.0)}}, {"interfaces", {interface_table}}}, 1);

  const json scene = tower_on_pedestal(0.0);
  const auto on_pedestal = rock("pair_convex_pedestal", scene, 2);

  ASSERT_EQ(on_table.size(), on_pedestal.size());
  double peak = 0, worst = 0;
  for (std::size_t k = 0; k < on_table.size(); ++k) {
    peak = std::max(peak, std::fabs(on_table[k][1]));
    worst = std::max(worst, std::fabs(on_table[k][1] - on_pedestal[k][1]));
  }
  std::cout << "[validation] tower on a 1e7 kg pedestal vs on the table, 5 s of free rocking: "
            << "largest rock_x difference " << worst << " rad = " << 100 * worst / peak
            << " % of the peak " << peak << " rad\n";
  // Issue 3: within 1 %. The remaining difference is the pedestal's own
  // compliance (it sinks and tilts by ~1e-6) and round-off.
  EXPECT_LT(worst, 0.01 * peak);
  EXPECT_GT(peak, 0.1);  // it rocked
}

TEST(PairConvex, StackSplitOverTwoRanksMatchesSerial) {
  // The stack shifted so that the pedestal (x = -0.05) and the tower (x ~ +0.01)
  // live on different ranks of `processors 2 1 1`; the tower rocks across the
  // boundary. Both ranks compute the pair with the lower tag first and keep
  // identical history copies, so the result must equal the serial run bit for bit.
  const fs::path dir = fv::fresh_dir("pair_convex_mpi");
  const fs::path script = write_run(dir, tower_on_pedestal(-0.05), 2, 500000);
  auto run = [&](const std::string& launcher, const std::string& copy) {
    const int status = freestand::testing::run_command(
        launcher + " " FREESTAND_LMP " -in " + script.string() + " -log none -screen /dev/null");
    fs::rename(dir / "out.txt", dir / copy);
    return status;
  };
  ASSERT_EQ(run("", "serial.txt"), 0);
  ASSERT_EQ(run(freestand::testing::mpirun(2), "np2.txt"), 0);
  const auto serial = fv::read_rows(dir / "serial.txt", 2), np2 = fv::read_rows(dir / "np2.txt", 2);
  ASSERT_EQ(serial.size(), np2.size());
  for (std::size_t k = 0; k < serial.size(); ++k) ASSERT_EQ(serial[k][1], np2[k][1]) << "row " << k;
}
