// fix rigid/convex against the table plane: a resting block settles to the
// closed-form overlap of the linear contact law, a block sliding on a sine
// table follows Newmark's rigid-plastic reference, and a block released
// tilted with corner contact rocks with Housner's impact times.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>

#include "../reference/housner.h"
#include "../reference/newmark.h"
#include "liggghts_session.h"
#include "run_command.h"
#include "validation_support.h"

namespace fs = std::filesystem;
namespace fv = freestand::validation;

namespace {

const std::string kSetup = fv::convex_preamble(3, 3, -1, 3);

// Writes a scene and a script that prints time, rock_x, slide_x, uplift and
// COM z every `every` steps; runs it; returns the rows.
std::vector<std::vector<double>> run_block(const std::string& name, const std::string& scene,
                                           const std::string& fix_extra,
                                           const std::string& table_line, double dt, double tend,
                                           int every) {
  const fs::path dir = fv::fresh_dir(name);
  std::ofstream(dir / "scene.json") << scene;
  const fs::path out = dir / "out.txt";
  std::ofstream script(dir / "run.in");
  script << kSetup << "timestep " << fv::num(dt) << "\n" << table_line << "\n"
         << "fix bodies all rigid/convex scene " << (dir / "scene.json").string() << " " << fix_extra
         << (table_line.empty() ? "" : " table shake") << "\n"
         << "fix grav all gravity 9.81 vector 0 0 -1\n"
         << "compute rs all rockslide bodies" << (table_line.empty() ? "" : " table shake") << "\n"
         << "variable t equal time\nvariable r equal c_rs[1][1]\nvariable s equal c_rs[1][4]\n"
         << "variable u equal c_rs[1][6]\nvariable z equal z[1]\n"
         << "fix out all print " << every << " \"${t} ${r} ${s} ${u} ${z}\" file " << out.string()
         << " screen no\n"
         << "run " << static_cast<long>(std::llround(tend / dt)) << "\n";
  script.close();
  fv::run_input((dir / "run.in").string(), {});
  return fv::read_rows(out, 5);
}

}  // namespace

TEST(RigidConvex, RestingBlockSettlesToTheLinearLawsOverlap) {
  // 100 kg on a 0.5 x 0.5 m base, k_a = 1e9 N/m^3: overlap m g / (k_a A)
  // = 981 / (1e9 * 0.25) = 3.924e-6 m. The contact is damped (e = 0.1),
  // so after 1 s (about 100 contact periods) the residual oscillation is
  // below 1e-12 m; 1e-3 relative allows for it and round-off.
  const auto rows = run_block("rigid_convex_rest",
      R"({"bodies": [{"name": "b", "shape": "box", "half_extents": [0.25, 0.25, 0.2], "mass": 100,
          "nodes": {"per_edge": 4}}]})",
      "stiffness 1e9 restitution 0.1", "", 1e-5, 1.0, 1000);
  const double settled = rows.back()[4] - 0.2;  // COM height minus half height
  std::cout << "[validation] resting overlap " << -settled << " m (linear law: 3.924e-6 m)\n";
  EXPECT_NEAR(-settled, 9.81 * 100 / (1e9 * 0.25), 1e-3 * 3.924e-6);
}

TEST(RigidConvex, HertzBlockSettlesToTheHertzOverlap) {
  // Hertz per area: p = k_a delta^(3/2) / sqrt(delta_ref). 100 kg on 0.25 m^2,
  // k_a = 1e9 N/m^3, delta_ref = 1e-5 m: delta = (m g sqrt(delta_ref) /
  // (k_a A))^(2/3) = 5.360e-6 m (the linear law would give 3.924e-6 m).
  const auto rows = run_block("rigid_convex_hertz",
      R"({"bodies": [{"name": "b", "shape": "box", "half_extents": [0.25, 0.25, 0.2], "mass": 100,
          "nodes": {"per_edge": 4}}],
          "interfaces": [{"lower": "table", "upper": "b", "law": "hertz",
                          "hertz_reference_overlap": 1e-5, "contact_stiffness": 2.5e8}]})",
      "restitution 0.1", "", 1e-5, 1.0, 1000);
  const double expected = std::pow(9.81 * 100 * std::sqrt(1e-5) / (1e9 * 0.25), 2.0 / 3.0);
  const double settled = 0.2 - rows.back()[4];
  std::cout << "[validation] Hertz resting overlap " << settled << " m (closed form " << expected << " m)\n";
  EXPECT_NEAR(settled, expected, 1e-3 * expected);  // as the linear test: damped to rest
}

TEST(RigidConvex, SlidingOnSineTableMatchesNewmark) {
  // Squat 0.5 x 0.5 x 0.4 m block (b/h = 1.25 >> mu: it cannot rock), mu = 0.2,
  // table a = 0.4 g sin(2 pi 2 t) for 2 s. Reference: rigid-plastic Newmark
  // integration. Tolerance 1 % of the peak slide (issue 3). What separates
  // the two is the contact's compliance (the elastic tangential spring before
  // each slip, the normal spring): it must shrink as the contact stiffens,
  // like 1/sqrt(k) for the spring's stick-slip lag.
  const double g = 9.81, A = 0.4 * 9.80665, f = 2.0;
  auto ag = [&](double t) { return t < 2.0 ? A * std::sin(2 * M_PI * f * t) : 0.0; };
  const auto ref = freestand::reference::newmark_sliding(ag, 0.2, 0.2, g, 3.0, 1e-3, 1e-6);
  double peak = 0;
  for (double u : ref.u) peak = std::max(peak, std::fabs(u));
  std::vector<double> errors;
  for (const char* stiffness : {"1e10", "1e11"}) {
    const auto rows = run_block(std::string("rigid_convex_slide_") + stiffness,
        R"({"bodies": [{"name": "b", "shape": "box", "half_extents": [0.25, 0.25, 0.2], "mass": 200,
            "nodes": {"per_edge": 2}}],
            "interfaces": [{"lower": "table", "upper": "b", "mu": 0.2}]})",
        std::string("stiffness ") + stiffness + " restitution 0.1",
        "fix shake all shaketable x sine amplitude 0.4 g frequency 2 duration 2", 2e-5, 3.0, 50);
    double worst = 0;
    for (const auto& row : rows)
      worst = std::max(worst, std::fabs(row[2] - fv::interpolate(ref.t, ref.u, row[0])));
    std::cout << "[validation] convex sliding, k_a " << stiffness << " N/m^3: peak " << peak
              << " m, largest error " << worst << " m (" << 100 * worst / peak << " % of the peak)\n";
    EXPECT_LT(worst, 0.01 * peak);
    errors.push_back(worst);
  }
  EXPECT_GT(peak, 0.01);
  EXPECT_LT(errors[1], 0.5 * errors[0]);  // converges toward Newmark as the contact stiffens
}

TEST(RigidConvex, RestartContinuesIdentically) {
  // write_restart, read_restart and the same fix again: the continued run
  // must match the uninterrupted one exactly (same arithmetic on the same
  // state; restart files store doubles exactly).
  const fs::path dir = fv::fresh_dir("rigid_convex_restart");
  const std::string scene = fv::source_path("inputs/convex/free_rocking_block.json");
  const std::string restart = (dir / "state.restart").string();
  const std::string body = "fix bodies all rigid/convex scene " + scene + "\n"
                           "fix grav all gravity 9.81 vector 0 0 -1\n"
                           "compute rs all rockslide bodies\n"
                           "thermo_style custom step c_rs[1][1] f_bodies[1]\nthermo 1000\n";
  double rock_uninterrupted, energy_uninterrupted;
  {
    freestand::testing::LiggghtsSession session;
    session.commands(kSetup + "timestep 2e-5\n" + body);
    session.commands("run 20000\nwrite_restart " + restart + "\nrun 20000");
    rock_uninterrupted = session.equal("c_rs[1][1]");
    energy_uninterrupted = session.equal("f_bodies[1]");
  }
  freestand::testing::LiggghtsSession session;
  session.commands("read_restart " + restart + "\natom_modify sort 0 0.0\nneighbor 0.01 bin\n"
                   "neigh_modify delay 0 binsize 0.5\ntimestep 2e-5\n" + body + "run 20000");
  std::cout << "[validation] restart: rock_x " << session.equal("c_rs[1][1]") << " vs "
            << rock_uninterrupted << "\n";
  EXPECT_EQ(session.equal("c_rs[1][1]"), rock_uninterrupted);
  EXPECT_EQ(session.equal("f_bodies[1]"), energy_uninterrupted);
  EXPECT_GT(energy_uninterrupted, 0.1);  // it is rocking, not at rest
}

TEST(RigidConvex, MpirunTwoProcessesMatchesSerial) {
  // The free-rocking example on two ranks (the domain is split at x = 0,
  // which the block's bounding sphere straddles): table contact is computed
  // by the rank that owns the body, so the arithmetic is the serial one and
  // the outputs must be identical.
  const fs::path dir = fv::fresh_dir("rigid_convex_mpi");
  auto run = [&](const std::string& launcher, const std::string& out) {
    const std::string command = "cd " + fv::source_path("inputs/convex") + " && " + launcher + " " +
                                FREESTAND_LMP " -in free_rocking.in -var tend 1.0 -var out " +
                                (dir / out).string() + " -log none -screen /dev/null";
    return freestand::testing::run_command(command);
  };
  ASSERT_EQ(run("", "serial.txt"), 0);
  ASSERT_EQ(run(freestand::testing::mpirun(2), "np2.txt"), 0);
  const auto serial = fv::read_rows(dir / "serial.txt", 2), np2 = fv::read_rows(dir / "np2.txt", 2);
  ASSERT_EQ(serial.size(), np2.size());
  ASSERT_GT(serial.size(), 1000u);
  for (std::size_t k = 0; k < serial.size(); ++k) ASSERT_EQ(serial[k][1], np2[k][1]) << "row " << k;
}

TEST(RigidConvex, ToppledBlockComesToRestOnItsSide) {
  // The free-rocking block (0.25 x 0.25 x 1.0 m, 100 kg, corner nodes)
  // released at rest tilted 0.5 rad about its +x base edge, past its
  // slenderness alpha = 0.245 rad: it topples and must end lying on its +x
  // face, held by that face's corners (not fall through the table pivoting
  // on its base rim). At rest the face's four corners share the weight
  // equally: the COM sits at the half thickness 0.125 m minus the linear
  // law's overlap m g / (k_a A_face) = 981 / (1e10 * 0.25) = 3.924e-7 m, and
  // the block is flat: rock_x = pi/2. Tolerances: 1 % of that overlap
  // (residual ringing of the damped contact after 2 s and round-off of
  // z ~ 1e-16 m) and 1e-6 rad.
  const double theta = 0.5, b = 0.125;
  const std::string scene = R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.125, 0.125, 0.5],
      "mass": 100, "nodes": {"layout": "vertices"}, "position": [)" +
                            fv::num(b - b * std::cos(theta)) + ", 0, " + fv::num(b * std::sin(theta)) +
                            R"(], "orientation": [)" + fv::num(std::cos(theta / 2)) + ", 0, " +
                            fv::num(std::sin(theta / 2)) + R"(, 0]}]})";
  const auto rows = run_block("rigid_convex_toppled", scene, "", "", 2e-5, 3.0, 1000);
  const auto& last = rows.back();
  const double overlap = 100 * 9.81 / (1e10 * 0.25);
  std::cout.precision(10);
  std::cout << "[validation] toppled block at rest: rock_x " << last[1] << " rad, COM z " << last[4]
            << " m (closed form " << b - overlap << " m)\n";
  EXPECT_NEAR(last[1], M_PI / 2, 1e-6);
  EXPECT_NEAR(last[4], b - overlap, 0.01 * overlap);
}
