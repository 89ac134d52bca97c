// fix shaketable inside LIGGGHTS: its outputs are the closed-form motion at
// the simulation time, a restart keeps the phase, and bad input stops the
// run with a message naming the file and line or the keyword.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "liggghts_session.h"
#include "run_command.h"

namespace fs = std::filesystem;
using freestand::testing::LiggghtsSession;

namespace {

const char* kBox = R"(
atom_style granular
atom_modify map array sort 0 0.0
boundary f f f
newton off
communicate single vel yes
units si
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
timestep 0.001
)";

}  // namespace

TEST(FixShakeTable, OutputsAreClosedFormSineAtSimulationTime) {
  LiggghtsSession session;
  session.commands(kBox);
  session.commands("fix shake all shaketable x sine amplitude 0.5 g frequency 2.0 start 0.1");
  session.commands("run 1234");
  // Motion time: 1.234 s since the fix was defined minus the 0.1 s delay.
  const double t = 1.234 - 0.1, A = 0.5 * 9.80665, w = 2 * M_PI * 2.0;
  // The analytic sine is evaluated in closed form: only round-off differs.
  EXPECT_NEAR(session.equal("f_shake[1]"), A * std::sin(w * t), 1e-9);
  EXPECT_NEAR(session.equal("f_shake[4]"), A / w * (1 - std::cos(w * t)), 1e-9);
  EXPECT_NEAR(session.equal("f_shake[7]"), A / w * (t - std::sin(w * t) / w), 1e-9);
  EXPECT_EQ(session.equal("f_shake[2]"), 0.0);  // y axis not named: at rest
}

TEST(FixShakeTable, RestAtZeroBeforeStart) {
  LiggghtsSession session;
  session.commands(kBox);
  session.commands("fix shake all shaketable x sine amplitude 1 m/s^2 frequency 1 start 5");
  session.commands("run 100");
  EXPECT_EQ(session.equal("f_shake[1]"), 0.0);
  EXPECT_EQ(session.equal("f_shake[7]"), 0.0);
}

TEST(FixShakeTable, RestartContinuesTheRecordWhereItStopped) {
  const fs::path restart = fs::absolute("shaketable_restart.bin");
  double before;
  {
    LiggghtsSession session;
    session.commands(kBox);
    session.commands("fix shake all shaketable x sine amplitude 1 m/s^2 frequency 1.5 start 0.2");
    session.commands("run 700");
    before = session.equal("f_shake[7]");
    session.commands("write_restart " + restart.string());
  }
  LiggghtsSession session;
  session.commands("read_restart " + restart.string());
  session.commands("atom_modify sort 0 0.0");
  session.commands("timestep 0.001");
  // Defined again after read_restart, without `start`: the saved start wins.
  session.commands("fix shake all shaketable x sine amplitude 1 m/s^2 frequency 1.5");
  session.commands("run 0");
  EXPECT_NEAR(session.equal("f_shake[7]"), before, 1e-12);
}

namespace {

// Runs freestand-lmp on a script with a bad fix shaketable; returns its output.
std::string run_bad(const std::string& name, const std::string& fix_line, int* status) {
  const fs::path dir = fs::absolute("bad_input");
  fs::create_directories(dir);
  const fs::path script = dir / (name + ".in");
  std::ofstream(script) << kBox << fix_line << "\nrun 10\n";
  return freestand::testing::capture_command(std::string(FREESTAND_LMP) + " -in " +
                                                 script.string() + " -log none",
                                             status);
}

}  // namespace

TEST(FixShakeTable, BadRecordStopsBeforeTheRunNamingFileAndLine) {
  const fs::path record = fs::absolute("bad_input/broken.txt");
  fs::create_directories(record.parent_path());
  std::ofstream(record) << "0.00 0.1\n0.01 0.2\n0.02 abc\n0.03 0.4\n";
  int status = 0;
  const std::string out =
      run_bad("broken", "fix shake all shaketable x record " + record.string() + " units g", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("ERROR"), std::string::npos) << out;
  EXPECT_NE(out.find("broken.txt:3"), std::string::npos) << out;
  EXPECT_EQ(out.find("Setting up run"), std::string::npos) << "must stop before the run";
}

TEST(FixShakeTable, MissingUnitsAreAnErrorNotAGuess) {
  int status = 0;
  const std::string out = run_bad("nounits",
      "fix shake all shaketable x record " FREESTAND_SHARED_DATA
      "/groundmotions/DUZCE_BOL090.AT2", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("units"), std::string::npos) << out;
}

TEST(FixShakeTable, VelocityRecordNeedsDifferentiateRequest) {
  int status = 0;
  const std::string out = run_bad("velocity",
      "fix shake all shaketable x record " FREESTAND_SHARED_DATA
      "/groundmotions/RSN1063_Northridge1994_Rinaldi228_VELOCITY_cmps_dt0.01.txt units cm/s",
      &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("differentiate yes"), std::string::npos) << out;
}

TEST(FixShakeTable, UnknownKeywordIsNamed) {
  int status = 0;
  const std::string out =
      run_bad("keyword", "fix shake all shaketable x sine amplitude 1 g frequency 1 wobble 3", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("wobble"), std::string::npos) << out;
}
