// The 1000-block dry-stone wall of inputs/convex (issue 3, section 4, MPI):
// one simulated second of moderate two-axis shaking on two ranks against the
// serial run, and a restart half-way that must continue the two-rank run
// exactly. The table motion is in the wall's plane (x, El Centro NS at PGA
// 0.2 g: the whole wall rides back and forth across the sub-domain boundary
// at x = 0) and out of it (y, El Centro array 9 EW at PGA 0.1 g).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include "run_command.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;

namespace {

constexpr long kStepsPerHalf = 25000;  // 0.5 s at dt = 2e-5 s
constexpr long kDumpEvery = 12500;     // 0.25 s

const std::string kMotion =
    "x record " FREESTAND_SHARED_DATA "/groundmotions/ElCentro1940_NS_g_dt0.02.dat units g pga 0.2 g "
    "skip 1.5 y record " FREESTAND_SHARED_DATA "/groundmotions/ElCentro1940_Array9_EW_cmps2_dt0.005.dat "
    "units cm/s^2 pga 0.1 g skip 1.5";

// Everything after the box (or after read_restart): motion, bodies, contact,
// gravity, and a dump of every body's state every 0.25 s sorted by id.
std::string model(const fs::path& dir, const std::string& dump_name) {
  return "timestep 2e-5\nfix shake all shaketable " + kMotion + "\n" +
         "fix bodies all rigid/convex scene " + (dir / "wall.json").string() +
         " table shake tangential_damping normal\npair_style convex\npair_coeff * *\n"
         "fix grav all gravity 9.81 vector 0 0 -1\n"
         "dump state all custom " + std::to_string(kDumpEvery) + " " + (dir / dump_name).string() +
         ".*.txt id x y z vx vy vz omegax omegay omegaz\n"
         "dump_modify state sort id format \"%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\"\n";
}

// Bodies' states (id x y z v omega) of one dump file.
std::vector<std::vector<double>> dump_rows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  for (int k = 0; k < 9 && std::getline(in, line);) ++k;  // ITEM header lines
  std::vector<std::vector<double>> rows;
  std::vector<double> row(10);
  while (in >> row[0] >> row[1] >> row[2] >> row[3] >> row[4] >> row[5] >> row[6] >> row[7] >> row[8] >> row[9])
    rows.push_back(row);
  return rows;
}

// Largest difference of columns [first, first + 3) between two dumps, relative
// to the largest change of those columns in `a` since `start` (positions) or
// to their largest magnitude (start empty: velocities).
double relative_difference(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
                           const std::vector<std::vector<double>>& start, int first) {
  double difference = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int c = first; c < first + 3; ++c) {
      difference = std::max(difference, std::fabs(a[i][c] - b[i][c]));
      scale = std::max(scale, std::fabs(a[i][c] - (start.empty() ? 0.0 : start[i][c])));
    }
  return difference / scale;
}

}  // namespace

TEST(WallMpi, TwoRanksMatchSerialAndRestartContinuesExactly) {
  const fs::path dir = fv::fresh_dir("wall_mpi");
  ASSERT_EQ(freestand::testing::run_command("python3 " + fv::source_path("inputs/convex/wall.py") +
                                            " wall > " + (dir / "wall.json").string()), 0);
  // Uninterrupted second, writing a restart file half-way.
  std::ofstream(dir / "full.in") << fv::convex_preamble(21, 3, -1, 4) << model(dir, "full")
                                 << "run " << kStepsPerHalf << "\nwrite_restart " << (dir / "half.restart").string()
                                 << "\nrun " << kStepsPerHalf << "\n";
  // Second half again from the restart file.
  std::ofstream(dir / "resumed.in") << "processors * 1 1\nread_restart " << (dir / "half.restart").string()
                                    << "\natom_modify sort 0 0.0\nnewton off\nneighbor 0.05 bin\n"
                                       "neigh_modify delay 0 binsize 1.0\ncommunicate single vel yes\n"
                                    << model(dir, "resumed") << "run " << kStepsPerHalf << "\n";
  auto run = [&](const std::string& launcher, const std::string& script, const std::string& tag) {
    const int status = freestand::testing::run_command(
        "cd " + dir.string() + " && " + launcher + " " FREESTAND_LMP " -in " + script + " -log log." + tag +
        " -screen /dev/null");
    for (long step = 0; step <= 2 * kStepsPerHalf; step += kDumpEvery) {
      const fs::path from = dir / (script.substr(0, script.size() - 3) + "." + std::to_string(step) + ".txt");
      if (fs::exists(from)) fs::rename(from, dir / (tag + "." + std::to_string(step) + ".txt"));
    }
    return status;
  };
  ASSERT_EQ(run("", "full.in", "serial"), 0);
  ASSERT_EQ(run(freestand::testing::mpirun(2), "full.in", "np2"), 0);
  ASSERT_EQ(run(freestand::testing::mpirun(2), "resumed.in", "resumed"), 0);

  const auto start = dump_rows(dir / "serial.0.txt");
  ASSERT_EQ(start.size(), 1000u);
  double worst = 0;
  for (long step = kDumpEvery; step <= 2 * kStepsPerHalf; step += kDumpEvery) {
    const std::string at = "." + std::to_string(step) + ".txt";
    const auto serial = dump_rows(dir / ("serial" + at)), np2 = dump_rows(dir / ("np2" + at));
    ASSERT_EQ(serial.size(), 1000u);
    ASSERT_EQ(np2.size(), 1000u);
    const double position = relative_difference(serial, np2, start, 1);
    const double velocity = relative_difference(serial, np2, {}, 4);
    const double spin = relative_difference(serial, np2, {}, 7);
    std::cout << "[validation] wall, t = " << step * 2e-5 << " s: np2 vs serial, relative difference of "
              << "positions " << position << ", velocities " << velocity << ", angular velocities " << spin
              << "\n";
    worst = std::max({worst, position, velocity, spin});
  }
  // Bodies that changed sub-domain (crossed x = 0) at some dump.
  int crossed = 0;
  const auto end = dump_rows(dir / ("serial." + std::to_string(2 * kStepsPerHalf) + ".txt"));
  for (std::size_t i = 0; i < start.size(); ++i) crossed += (start[i][1] < 0) != (end[i][1] < 0);
  std::cout << "[validation] wall: " << crossed << " bodies on the other rank's side at 1 s than at 0 s\n";
  // Issue 3 asks for 1e-6 relative over one simulated second. Pair forces
  // are summed per body in partner-tag order (pair_convex.cpp), so the
  // two-rank run does the serial arithmetic: identical, not just close.
  EXPECT_EQ(worst, 0.0);
  EXPECT_GT(crossed, 0);

  // The resumed run must equal the uninterrupted one exactly (restart files
  // store doubles exactly; the atoms' order on a rank after read_restart does
  // not change the sums, as above).
  const std::string at_end = "." + std::to_string(2 * kStepsPerHalf) + ".txt";
  const auto np2 = dump_rows(dir / ("np2" + at_end)), resumed = dump_rows(dir / ("resumed" + at_end));
  ASSERT_EQ(resumed.size(), np2.size());
  for (std::size_t i = 0; i < np2.size(); ++i)
    for (int c = 0; c < 10; ++c) ASSERT_EQ(resumed[i][c], np2[i][c]) << "body " << i << " column " << c;
}
