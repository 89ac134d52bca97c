// fix rockslide/hdf5 end to end: h5py opens the file, the table series are
// exactly fix shaketable's motion at the stored times, a failed run leaves
// an existing file untouched, and an mpirun -np 2 run agrees with serial.

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "freestand/shake_table.h"
#include "run_command.h"

namespace fs = std::filesystem;

namespace {

const std::string kInputs = FREESTAND_SOURCE_DIR "/inputs/shake_table";
const std::string kRecord = FREESTAND_SHARED_DATA "/groundmotions/DUZCE_BOL090.AT2";

// Runs the sliding example for `tend` s (through the 11 s peak of the record).
int run_example(const fs::path& out, const std::string& launcher, double tend) {
  const std::string command = "cd " + kInputs + " && " + launcher + " " FREESTAND_LMP
                              " -in duzce_sliding.in -var motion \"x record " + kRecord +
                              " units g\" -var tend " + std::to_string(tend) + " -var out " +
                              out.string() + " -log none -screen /dev/null";
  return freestand::testing::run_command(command);
}

std::vector<double> read_series(const fs::path& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return {};
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  std::vector<double> values;
  if (d >= 0) {
    const hid_t space = H5Dget_space(d);
    values.resize(H5Sget_simple_extent_npoints(space));
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Sclose(space);
    H5Dclose(d);
  }
  H5Fclose(f);
  return values;
}

class RockSlideHdf5 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test in its own process, in parallel: one folder each.
    dir_ = fs::absolute("rockslide_hdf5_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    serial_status_ = run_example(dir_ / "serial.h5", "", 11.5);
  }
  static void TearDownTestSuite() {
    if (!::testing::UnitTest::GetInstance()->Failed()) fs::remove_all(dir_);
  }
  static fs::path dir_;
  static int serial_status_;
};
fs::path RockSlideHdf5::dir_;
int RockSlideHdf5::serial_status_ = -1;

}  // namespace

TEST_F(RockSlideHdf5, FileIsCompleteAndH5pyOpensIt) {
  ASSERT_EQ(serial_status_, 0);
  EXPECT_TRUE(fs::exists(dir_ / "serial.h5"));
  EXPECT_FALSE(fs::exists(dir_ / "serial.h5.part"));
  const std::string out = freestand::testing::capture_command(
      "/usr/bin/python3 -c \"import h5py; f = h5py.File('" + (dir_ / "serial.h5").string() +
      "', 'r'); print(sorted(f['/bodies/block'].keys()), f['/time'].shape[0], "
      "f['/bodies/block/slide_x'].attrs['units'])\"");
  EXPECT_NE(out.find("'rock_x', 'rock_y', 'slide_x', 'slide_y', 'twist', 'uplift'"),
            std::string::npos) << out;
  // 11.5 s at 1 kHz plus the sample at the start of the run.
  EXPECT_NE(out.find("11501"), std::string::npos) << out;
}

TEST_F(RockSlideHdf5, TableSeriesAreTheRecordAtTheStoredTimes) {
  ASSERT_EQ(serial_status_, 0);
  const auto t = read_series(dir_ / "serial.h5", "/time");
  const auto ax = read_series(dir_ / "serial.h5", "/table/ax");
  const auto dx = read_series(dir_ / "serial.h5", "/table/dx");
  ASSERT_EQ(t.size(), ax.size());
  freestand::ShakeTableSpec spec = freestand::parse_shake_table_args({"x", "record", kRecord, "units", "g"});
  const freestand::ShakeTable table(spec);
  // The example settles 0.2 s before the record starts (tsettle).
  double worst = 0, peak = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const freestand::TableState s = table.at(t[i] - 0.2);
    worst = std::max({worst, std::fabs(s.acceleration.x() - ax[i]), std::fabs(s.displacement.x() - dx[i])});
    peak = std::max(peak, std::fabs(s.acceleration.x()));
  }
  // Same closed form, times differing only by round-off of step counting (1e-12 s):
  // 1e-9 of the peak acceleration bounds that.
  EXPECT_LT(worst, 1e-9 * peak);
  EXPECT_GT(peak, 0.8 * 9.80665);  // the 0.82 g peak at 11 s was played
}

TEST_F(RockSlideHdf5, BlockSlidesAndFailedRunKeepsExistingFile) {
  ASSERT_EQ(serial_status_, 0);
  const auto slide = read_series(dir_ / "serial.h5", "/bodies/block/slide_x");
  double peak = 0;
  for (double s : slide) peak = std::max(peak, std::fabs(s));
  EXPECT_GT(peak, 0.01) << "mu = 0.2 under a 0.82 g record must slide";

  // A run that dies (here: an input error after results started) must not
  // replace the file that was there.
  const fs::path kept = dir_ / "kept.h5";
  std::ofstream(kept) << "an older result";
  // The example followed by a bad command, through a wrapper script.
  const fs::path wrapper = dir_ / "dies.in";
  std::ofstream(wrapper) << "include " << kInputs << "/duzce_sliding.in\nthis_is_not_a_command\n";
  const int status = freestand::testing::run_command(
      "cd " + kInputs + " && " FREESTAND_LMP " -in " + wrapper.string() + " -var motion \"x record " +
      kRecord + " units g\" -var tend 0.1 -var out " + kept.string() + " -log none -screen /dev/null");
  EXPECT_NE(status, 0);
  std::ifstream in(kept);
  std::stringstream content;
  content << in.rdbuf();
  EXPECT_EQ(content.str(), "an older result");
  EXPECT_TRUE(fs::exists(dir_ / "kept.h5.part"));
}

TEST_F(RockSlideHdf5, MpirunTwoProcessesAgreesWithSerial) {
  ASSERT_EQ(serial_status_, 0);
  ASSERT_EQ(run_example(dir_ / "np2.h5", freestand::testing::mpirun(2), 11.5), 0);
  for (const char* name : {"/bodies/block/slide_x", "/bodies/block/rock_x", "/bodies/block/uplift"}) {
    const auto a = read_series(dir_ / "serial.h5", name), b = read_series(dir_ / "np2.h5", name);
    ASSERT_EQ(a.size(), b.size()) << name;
    double worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(a[i] - b[i]));
    std::cout << name << ": largest |np2 - serial| = " << worst << "\n";
    // Serial and parallel runs sum the same contact forces in a different
    // order. Horizontal motion agrees to ~1e-8; the vertical chatter of the
    // stiff 1 mm corner contacts amplifies round-off to ~2e-5 m in uplift.
    // Bound: a tenth of the sensor noise of ../shared/recording-format.md
    // (5e-4 m, 5e-4 rad), so the difference is invisible against any recording.
    EXPECT_LT(worst, 5e-5) << name;
  }
}
