// Recording reader and writer: every input error names file and line or
// column, lost samples stay NaN, table channels are derived correctly
// (checked against closed forms), and CSV and HDF5 round trips are exact.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

#include "freestand/input_error.h"
#include "freestand/series_file.h"
#include "recording.h"
#include "temp_dir.h"

namespace freestand {
namespace {

using test::TempDir;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const char* kBlock =
    R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.1, 0.1, 0.5],
        "mass": 100, "com": [0, 0, 0.5]}], "sampling_hz": 100})";

// Writes NAME.csv and NAME.nominal.json; returns the CSV path.
std::string write_pair(const TempDir& dir, const std::string& csv, const std::string& nominal = kBlock,
                       const std::string& name = "rec") {
  dir.write(name + ".nominal.json", nominal);
  return dir.write(name + ".csv", csv);
}

// The InputError message read_recording(path) throws ("" if none).
std::string error_of(const std::string& path) {
  try {
    read_recording(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_CONTAINS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

TEST(RecordingRead, LostSamplesStayNaN) {
  TempDir dir;
  const Recording r = read_recording(write_pair(
      dir, "t,block.rock_x,block.uplift\n0,0.01,0\n0.01,,0.001\n0.02,nan,NaN\n0.03,-0.02,0.003\n"));
  ASSERT_EQ(r.time.size(), 4u);
  const std::vector<double>& rock = r.body_channel("block", "rock_x");
  EXPECT_EQ(rock[0], 0.01);
  EXPECT_TRUE(std::isnan(rock[1]));
  EXPECT_TRUE(std::isnan(rock[2]));
  EXPECT_EQ(rock[3], -0.02);
  EXPECT_TRUE(std::isnan(r.body_channel("block", "uplift")[2]));
  EXPECT_EQ(r.body_names(), std::vector<std::string>{"block"});
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.table_channel('a', 'x'), nullptr);  // the table did not move
  EXPECT_THROW(r.body_channel("block", "twist"), InputError);
}

TEST(RecordingRead, AcceptsAStemAndCrlf) {
  TempDir dir;
  write_pair(dir, "t,block.rock_x\r\n0,0\r\n0.01,0.5\r\n");
  const Recording r = read_recording(dir / "rec");
  EXPECT_EQ(r.body_channel("block", "rock_x")[1], 0.5);
}

TEST(RecordingRead, MissingTimeColumn) {
  TempDir dir;
  const std::string e = error_of(write_pair(dir, "time,block.rock_x\n0,0\n"));
  EXPECT_CONTAINS(e, "rec.csv:1");
  EXPECT_CONTAINS(e, "no time column 't'");
  EXPECT_CONTAINS(error_of(write_pair(dir, "block.rock_x,t\n0,0\n")), "'t' must come first");
}

TEST(RecordingRead, TimeMustIncrease) {
  TempDir dir;
  const std::string e = error_of(write_pair(dir, "t,block.rock_x\n0,0\n0.01,0\n0.01,0\n"));
  EXPECT_CONTAINS(e, "rec.csv:4");
  EXPECT_CONTAINS(e, "does not increase");
  EXPECT_CONTAINS(error_of(write_pair(dir, "t,block.rock_x\n0,0\n,0\n")), "rec.csv:3");
}

TEST(RecordingRead, WrongColumnCount) {
  TempDir dir;
  const std::string e = error_of(write_pair(dir, "t,block.rock_x\n0,0\n0.01,0,7\n"));
  EXPECT_CONTAINS(e, "rec.csv:3");
  EXPECT_CONTAINS(e, "3 cells, but the header has 2 columns");
}

TEST(RecordingRead, NonNumericCell) {
  TempDir dir;
  const std::string e = error_of(write_pair(dir, "t,block.rock_x,block.uplift\n0,0,0\n0.01,0,abc\n"));
  EXPECT_CONTAINS(e, "rec.csv:3");
  EXPECT_CONTAINS(e, "column 3 ('block.uplift')");
  EXPECT_CONTAINS(e, "'abc'");
  EXPECT_CONTAINS(error_of(write_pair(dir, "t,block.rock_x\n0,inf\n")), "not a finite number");
}

TEST(RecordingRead, BodyInCsvButNotInSidecar) {
  TempDir dir;
  const std::string e = error_of(write_pair(dir, "t,block.rock_x,ghost.rock_x\n0,0,0\n"));
  EXPECT_CONTAINS(e, "'ghost.rock_x' names body 'ghost'");
  EXPECT_CONTAINS(e, "rec.nominal.json");
}

TEST(RecordingRead, SidecarBodyWithoutChannel) {
  TempDir dir;
  const std::string two = R"({"bodies": [{"name": "block"}, {"name": "tower", "supported_by": "block"}]})";
  const std::string e = error_of(write_pair(dir, "t,block.rock_x\n0,0\n", two));
  EXPECT_CONTAINS(e, "rec.nominal.json");
  EXPECT_CONTAINS(e, "body 'tower' has no column");
}

TEST(RecordingRead, MissingOrBrokenSidecar) {
  TempDir dir;
  const std::string csv = dir.write("lonely.csv", "t,block.rock_x\n0,0\n");
  EXPECT_CONTAINS(error_of(csv), "lonely.nominal.json: cannot open");
  EXPECT_CONTAINS(error_of(write_pair(dir, "t,block.rock_x\n0,0\n", "{\"bodies\": [")), "not valid JSON");
  EXPECT_CONTAINS(error_of(write_pair(dir, "t,block.rock_x\n0,0\n", "{\"bodies\": []}")),
                  "'bodies' must be a non-empty list");
}

TEST(RecordingRead, StatedUnitsMustBeSi) {
  TempDir dir;
  const std::string degrees =
      R"({"bodies": [{"name": "block"}], "units": {"block.rock_x": "deg", "t": "s"}})";
  std::string e = error_of(write_pair(dir, "t,block.rock_x\n0,0\n", degrees));
  EXPECT_CONTAINS(e, "'block.rock_x' is stated in 'deg'");
  EXPECT_CONTAINS(e, "radians");
  e = error_of(write_pair(dir, "t,block.uplift\n0,0\n",
                          R"({"bodies": [{"name": "block"}], "units": {"block.uplift": "mm"}})"));
  EXPECT_CONTAINS(e, "expected m");
  e = error_of(write_pair(dir, "t,block.uplift\n0,0\n", R"({"bodies": [{"name": "block"}], "units": "mm"})"));
  EXPECT_CONTAINS(e, "'units' is 'mm'");
  // SI spelled out is accepted.
  EXPECT_EQ(error_of(write_pair(dir, "t,block.uplift\n0,0\n",
                                R"({"bodies": [{"name": "block"}], "units": {"block.uplift": "metres"}})")),
            "");
}

TEST(RecordingRead, RockingAngleBeyondPiMeansDegrees) {
  TempDir dir;
  const std::string e = error_of(write_pair(dir, "t,block.rock_x\n0,0\n0.01,1.5\n0.02,4.2\n"));
  EXPECT_CONTAINS(e, "rec.csv:4");
  EXPECT_CONTAINS(e, "radians");
  // pi itself, rounded up in the last printed digit, is a valid angle.
  EXPECT_EQ(error_of(write_pair(dir, "t,block.rock_x\n0,3.1415927\n")), "");
}

TEST(RecordingRead, UnknownNominalFieldsWarnedOnce) {
  TempDir dir;
  const std::string nominal = R"({"bodies": [{"name": "a", "colour": "red"}, {"name": "b", "colour": "blue"}],
      "operator": "J. Doe", "interfaces": [{"lower": "table", "upper": "a", "glue": true}]})";
  const Recording r = read_recording(write_pair(dir, "t,a.rock_x,b.rock_x\n0,0,0\n", nominal));
  ASSERT_EQ(r.warnings.size(), 3u);
  int colour = 0;
  for (const std::string& w : r.warnings) colour += w.find("'colour'") != std::string::npos;
  EXPECT_EQ(colour, 1);
  EXPECT_CONTAINS(r.warnings[0], "rec.nominal.json");
}

TEST(RecordingRead, ExtraColumnsAreKept) {
  TempDir dir;
  const Recording r = read_recording(
      write_pair(dir, "t,block.rock_x,block.qw,block.x,temperature,block.strain\n0,0,1,0.5,20,1e-6\n"));
  EXPECT_EQ(r.find("block.qw")->values[0], 1.0);  // pose extension: no warning
  EXPECT_EQ(r.find("temperature")->values[0], 20.0);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_CONTAINS(r.warnings[0], "'temperature'");
  EXPECT_CONTAINS(r.warnings[1], "'block.strain'");
}

// ---- table channels ----------------------------------------------------------

std::string table_csv(const std::vector<std::string>& names,
                      const std::vector<std::function<double(double)>>& f, int n, double h) {
  std::string text = "t,block.rock_x";
  for (const std::string& name : names) text += "," + name;
  text += "\n";
  for (int i = 0; i < n; ++i) {
    text += fmt::format("{},0", i * h);
    for (const auto& g : f) text += fmt::format(",{}", g(i * h));
    text += "\n";
  }
  return text;
}

TEST(RecordingTable, AccelerationOnlyIntegratedFromRest) {
  // Constant acceleration: the trapezoid rule integrates the constant and
  // the linear velocity exactly, so v = A t and d = A t^2 / 2 to rounding.
  TempDir dir;
  const double A = 2.0, h = 0.01;
  const Recording r = read_recording(write_pair(dir, table_csv({"table_ax"}, {[&](double) { return A; }}, 101, h)));
  ASSERT_NE(r.table_channel('v', 'x'), nullptr);
  EXPECT_TRUE(r.find("table_vx")->derived);
  EXPECT_FALSE(r.find("table_ax")->derived);
  for (std::size_t i = 0; i < r.time.size(); ++i) {
    const double t = r.time[i];
    EXPECT_NEAR((*r.table_channel('v', 'x'))[i], A * t, 1e-12);
    EXPECT_NEAR((*r.table_channel('d', 'x'))[i], A * t * t / 2, 1e-12);
  }
  EXPECT_EQ(r.table_channel('a', 'y'), nullptr);
}

TEST(RecordingTable, DisplacementOnlyDifferentiated) {
  // d = sin(w t): second-order differences err by at most w^3 h^2 / 3 in v
  // (one-sided ends). Differentiating that v again errs by O(w^4 h^2)
  // inside, but at the first and last two samples the differences meet
  // the sample-to-sample change of v's own end error, O(w^3 h^2) / h =
  // O(w^3 h) (0.75 w^3 h here, as numpy.gradient(edge_order=2) also gives).
  // w h = 2 pi / 1000; the bounds are 2-3 times those estimates.
  TempDir dir;
  const double w = 2 * M_PI, h = 0.001;
  const Recording r = read_recording(
      write_pair(dir, table_csv({"table_dy"}, {[&](double t) { return std::sin(w * t); }}, 1001, h)));
  double v_error = 0, a_inside = 0, a_ends = 0;
  const std::size_t n = r.time.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double t = r.time[i];
    v_error = std::max(v_error, std::fabs((*r.table_channel('v', 'y'))[i] - w * std::cos(w * t)));
    const double a_error = std::fabs((*r.table_channel('a', 'y'))[i] + w * w * std::sin(w * t));
    double& worst = (i < 2 || i + 2 >= n) ? a_ends : a_inside;
    worst = std::max(worst, a_error);
  }
  EXPECT_LT(v_error, 3 * w * w * w * h * h / 3);
  EXPECT_LT(a_inside, 3 * w * w * w * w * h * h);
  EXPECT_LT(a_ends, 2 * w * w * w * h);
  EXPECT_GT(a_inside, 0.0);  // derived, not copied
}

TEST(RecordingTable, NoisyDisplacementIsCutWhereItsStatedNoiseOvertakesIt) {
  // Three tones (1, 2.5 and 4 Hz, 1 m/s^2 each) in 0.5 mm of noise at 200 Hz for 10 s: twice
  // differentiated as recorded (central differences over 2 h) that noise alone is 0.5e-3
  // sqrt(6) / (4 0.005^2) = 12 m/s^2 rms.
  // Kept only where the travel exceeds the stated noise (signal::cut_noise: about the tones,
  // 1 Hz wide each), what is left of the noise is about 2 sigma^2 dt (2 pi)^4 f^4 B over the
  // kept band B = 3 Hz near f = 4 Hz: 0.03 m/s^2 rms; the bound allows 3 times it. One cut-off
  // below the last tone would lose the tones above it (1 m/s^2 rms of a 1.5 m/s^2 record).
  // A lost sample stays lost.
  TempDir dir;
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0, 5e-4);
  const auto tones = [](double t, int derivative) {
    double sum = 0;
    for (double f : {1.0, 2.5, 4.0}) sum += std::sin(2 * M_PI * f * t) * (derivative ? 1 : -1 / std::pow(2 * M_PI * f, 2));
    return sum;
  };
  std::string csv = table_csv({"table_dx"}, {[&](double t) { return tones(t, 0) + noise(random); }}, 2001, 0.005);
  csv.replace(csv.find("\n5,0,") + 5, csv.find('\n', csv.find("\n5,0,") + 1) - csv.find("\n5,0,") - 5, "nan");
  const std::string stated = R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.1, 0.1, 0.5],
        "mass": 100, "com": [0, 0, 0.5]}], "sampling_hz": 200, "sensor_noise": {"angle": 5e-4, "length": 5e-4}})";
  const Recording r = read_recording(write_pair(dir, csv, stated));
  const std::vector<double>& a = *r.table_channel('a', 'x');
  double sum = 0;
  int count = 0;
  for (std::size_t i = 10; i + 10 < a.size(); ++i)
    if (i != 1000) sum += std::pow(a[i] - tones(r.time[i], 2), 2), ++count;
  EXPECT_LT(std::sqrt(sum / count), 0.1);
  EXPECT_TRUE(std::isnan(a[1000]) && std::isnan((*r.table_channel('v', 'x'))[1000]));
  ASSERT_EQ(r.warnings.size(), 2u);  // the cut, and the lost sample a replay bridges
  EXPECT_CONTAINS(r.warnings[0], "table_ax differentiated twice from table_dx where the travel exceeds its stated noise");
  EXPECT_CONTAINS(r.warnings[1], "table_ax: 1 samples lost");
  // The noise not stated: differentiated as recorded, and said so.
  const Recording unstated = read_recording(write_pair(dir, csv, kBlock, "unstated"));
  ASSERT_EQ(unstated.warnings.size(), 2u);
  EXPECT_CONTAINS(unstated.warnings[0], "as recorded (no sensor_noise.length stated)");
}

TEST(RecordingTable, VelocityWithLostSampleBridgesTheGap) {
  // v = 3 t: its derivative 3 and its trapezoid integral 1.5 t^2 are exact,
  // also across the lost sample, which stays NaN in every derived channel.
  TempDir dir;
  std::string csv = table_csv({"table_vz"}, {[](double t) { return 3 * t; }}, 11, 0.1);
  csv.replace(csv.find("0.5,0,1.5"), 9, "0.5,0,nan");
  const Recording r = read_recording(write_pair(dir, csv));
  for (std::size_t i = 0; i < r.time.size(); ++i) {
    const double a = (*r.table_channel('a', 'z'))[i], d = (*r.table_channel('d', 'z'))[i];
    if (i == 5) {
      EXPECT_TRUE(std::isnan(a) && std::isnan(d));
      continue;
    }
    EXPECT_NEAR(a, 3.0, 1e-9);
    EXPECT_NEAR(d, 1.5 * r.time[i] * r.time[i], 1e-12);
  }
}

TEST(RecordingTable, LostAccelerationIsReplayedAcrossAShortGapAndRefusedAcrossALongOne) {
  // A 2 Hz sine of 1 m/s^2 at 200 Hz with 8 samples lost about its crest (the bridge's worst
  // place), the bridge spanning T = 0.045 s: a chord misses a sine by at most its amplitude
  // times 1 - cos(omega T / 2) <= (pi f T)^2 / 2 = 0.040, the bound kLongestTableBridge's
  // comment states. Read, the samples stay lost and the reader says a replay bridges them.
  // A gap of 0.06 s is refused, naming the time: the replay would invent the table's motion.
  TempDir dir;
  const auto sine = [](double t) { return std::sin(2 * M_PI * 2 * t); };
  const auto with_gap = [&](int first, int last) {  // samples first..last lost (t = k / 200)
    std::string csv = "t,block.rock_x,table_ax\n";
    for (int k = 0; k < 800; ++k)
      csv += fmt::format("{},0,{}\n", k * 0.005, k >= first && k <= last ? "" : fmt::format("{}", sine(k * 0.005)));
    return csv;
  };
  const std::string nominal = R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.1, 0.1, 0.5],
        "mass": 100, "com": [0, 0, 0.5]}], "sampling_hz": 200})";
  const Recording r = read_recording(write_pair(dir, with_gap(22, 29), nominal));  // the crest at k = 25
  EXPECT_TRUE(std::isnan((*r.table_channel('a', 'x'))[25]));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_CONTAINS(r.warnings[0], "table_ax: 8 samples lost, the longest run spanning 0.045 s from t = 0.11 s");
  const std::vector<double> replayed = replayed_table_acceleration(r, 'x');
  double worst = 0;
  for (int k = 22; k <= 29; ++k) worst = std::max(worst, std::abs(replayed[k] - sine(k * 0.005)));
  EXPECT_LE(worst, std::pow(M_PI * 2 * 0.045, 2) / 2);
  EXPECT_GT(worst, 0.02);  // the crest's chord: 1 - cos at the nearest samples, not a copy of the truth
  EXPECT_EQ(replayed[21], sine(21 * 0.005));
  const Recording long_gap = read_recording(write_pair(dir, with_gap(100, 110), nominal, "long"));
  try {
    replayed_table_acceleration(long_gap, 'x');
    ADD_FAILURE() << "a 0.06 s gap was replayed";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "long.csv: table acceleration along x lost for 0.06 s from t = 0.5 s");
  }
}

TEST(RecordingTable, AccelerationAndDisplacementGiveVelocityFromAcceleration) {
  TempDir dir;
  const Recording r = read_recording(write_pair(
      dir, table_csv({"table_ax", "table_dx"}, {[](double) { return 1.0; }, [](double) { return 7.0; }}, 5, 0.5)));
  EXPECT_NEAR(r.table_channel('v', 'x')->back(), 2.0, 1e-12);  // integral of a, not derivative of d
  EXPECT_EQ(r.table_channel('d', 'x')->back(), 7.0);            // as measured
  EXPECT_CONTAINS(error_of(write_pair(dir, table_csv({"table_dx"}, {[](double) { return 1.0; }}, 2, 0.5))),
                  "fewer than 3 valid samples");
}

// ---- writing and round trips ---------------------------------------------------

Recording sample_recording() {
  Recording r;
  r.nominal = nlohmann::json::parse(kBlock);
  r.time = {0.0, 0.005, 0.01, 0.015};
  r.channels = {{"table_ax", {0.1, -1e-17, 3.0, kNaN}},
                {"block.rock_x", {0.0, 1.0 / 3.0, kNaN, -M_PI}},
                {"block.uplift", {kNaN, 2e-300, 1e300, 0.0}}};
  return r;
}

void expect_same_channels(const Recording& written, const Recording& read) {
  EXPECT_EQ(read.time, written.time);
  EXPECT_EQ(read.nominal, written.nominal);
  for (const RecordingChannel& c : written.channels) {
    const RecordingChannel* back = read.find(c.name);
    ASSERT_NE(back, nullptr) << c.name;
    EXPECT_FALSE(back->derived);
    for (std::size_t i = 0; i < c.values.size(); ++i) {
      if (std::isnan(c.values[i])) EXPECT_TRUE(std::isnan(back->values[i])) << c.name << " " << i;
      else EXPECT_EQ(back->values[i], c.values[i]) << c.name << " " << i;  // bit-exact
    }
  }
}

TEST(RecordingWrite, CsvRoundTripIsExact) {
  TempDir dir;
  const Recording written = sample_recording();
  write_recording(dir / "out", written);
  const Recording read = read_recording(dir / "out.csv");
  expect_same_channels(written, read);
  EXPECT_TRUE(read.find("table_vx")->derived);
  // Derived channels are not written back: a second round trip is unchanged.
  write_recording(dir / "again", read);
  expect_same_channels(written, read_recording(dir / "again.csv"));
  std::ifstream csv(dir / "again.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "t,table_ax,block.rock_x,block.uplift");
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    EXPECT_NE(entry.path().extension(), ".part");
}

TEST(RecordingWrite, Hdf5RoundTripIsExact) {
  TempDir dir;
  const Recording written = sample_recording();
  write_recording(dir / "out", written, true);
  expect_same_channels(written, read_recording(dir / "out.h5"));
  expect_same_channels(written, read_recording(dir / "out"));
}

TEST(RecordingWrite, RefusesInconsistentRecordingsAndUnwritablePlaces) {
  TempDir dir;
  Recording r = sample_recording();
  r.channels[1].values.pop_back();
  EXPECT_THROW(write_recording(dir / "short", r), InputError);
  EXPECT_THROW(write_recording(dir / "no/such/dir/out", sample_recording()), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "short.csv"));
}

// ---- HDF5 input errors -------------------------------------------------------------

TEST(RecordingHdf5, TruncatedOrCorruptFile) {
  TempDir dir;
  write_recording(dir / "whole", sample_recording(), true);
  const auto size = std::filesystem::file_size(dir / "whole.h5");
  std::filesystem::copy_file(dir / "whole.h5", dir / "cut.h5");
  std::filesystem::resize_file(dir / "cut.h5", size / 2);
  EXPECT_CONTAINS(error_of(dir / "cut.h5"), "cut.h5: not a readable HDF5 file");
  EXPECT_CONTAINS(error_of(dir.write("junk.h5", "t,block.rock_x\n0,0\n")), "junk.h5: not a readable HDF5");
  EXPECT_CONTAINS(error_of(dir / "absent.h5"), "cannot open");
}

// An HDF5 recording with the given rock_x unit, time and nominal.
std::string hdf5_recording(const TempDir& dir, const std::string& name, const std::string& rock_unit,
                           const std::vector<double>& t, const std::string& nominal = kBlock) {
  SeriesFile file(dir / name);
  file.add_series("/channels/t", "s");
  file.add_series("/channels/block.rock_x", rock_unit);
  if (!nominal.empty()) file.set_attribute("/", "nominal", nominal);
  for (double time : t) file.append({time, 0.0});
  file.commit();
  return dir / name;
}

TEST(RecordingHdf5, ErrorsNameTheDatasetOrSample) {
  TempDir dir;
  std::string e = error_of(hdf5_recording(dir, "deg.h5", "deg", {0, 1}));
  EXPECT_CONTAINS(e, "/channels/block.rock_x");
  EXPECT_CONTAINS(e, "radians");
  e = error_of(hdf5_recording(dir, "back.h5", "rad", {0, 1, 0.5}));
  EXPECT_CONTAINS(e, "back.h5: sample 2");
  EXPECT_CONTAINS(error_of(hdf5_recording(dir, "bare.h5", "rad", {0, 1}, "")), "/nominal");
}

TEST(RecordingHdf5, ReadsWhatH5pyWrites) {
  // h5py writes the attribute as a variable-length string, unlike SeriesFile.
  TempDir dir;
  const std::string path = dir / "py.h5";
  const std::string script = fmt::format(
      "import h5py, numpy as np\n"
      "with h5py.File('{}', 'w') as f:\n"
      "    f['channels/t'] = np.arange(4) / 100.0\n"
      "    f['channels/block.rock_x'] = np.array([0.0, 0.01, np.nan, 0.03])\n"
      "    f.attrs['nominal'] = '{}'\n",
      path, R"({"bodies": [{"name": "block"}]})");
  ASSERT_EQ(std::system(("/usr/bin/python3 " + dir.write("make.py", script)).c_str()), 0);
  const Recording r = read_recording(path);
  EXPECT_EQ(r.time[3], 0.03);
  EXPECT_TRUE(std::isnan(r.body_channel("block", "rock_x")[2]));
}

}  // namespace
}  // namespace freestand
