// Ground-motion reader: every shared record reads as its index.csv says; the
// accepted formats and units; one test per input error, each checking that
// the message names the file (and the line, where one is at fault).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "freestand/ground_motion_reader.h"
#include "freestand/input_error.h"
#include "freestand/table_motion.h"

namespace freestand {
namespace {

namespace fs = std::filesystem;

const std::string kRecords = std::string(FREESTAND_SHARED_DATA) + "/groundmotions";

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) out.push_back(field);
  return out;
}

// "0.1712 (EW)" -> "0.1712"; "m/s^2 (inferred)" -> "m/s^2".
std::string before_parenthesis(const std::string& s) { return s.substr(0, s.find(" (")); }

// Half a unit of the last printed digit of a decimal number ("658.90" -> 0.005).
double half_last_digit(const std::string& printed) {
  const std::size_t dot = printed.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(printed.size() - dot - 1);
  return 0.5 * std::pow(10.0, -decimals);
}

double si_per_unit(const std::string& units) {
  const std::map<std::string, double> f = {{"g", 9.80665}, {"m/s^2", 1.0}, {"cm/s^2", 0.01},
                                           {"mm/s^2", 1e-3}, {"m/s", 1.0}, {"cm/s", 0.01}};
  return f.at(units);
}

struct IndexRow {
  std::string file, quantity, units, dt, npts, peak, component;  // as printed in index.csv
};

std::vector<IndexRow> read_index() {
  std::ifstream in(kRecords + "/index.csv");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_commas(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  std::vector<IndexRow> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = split_commas(line);
    // A quoted field with a comma would shift the columns: fail loudly.
    EXPECT_EQ(f.size(), header.size()) << line;
    if (f.size() != header.size()) continue;
    const std::string peak = f[col.at("peak_abs")];
    const std::size_t paren = peak.find('(');
    rows.push_back({f[col.at("file")], f[col.at("quantity")],
                    before_parenthesis(f[col.at("units")]), f[col.at("dt_s")],
                    f[col.at("npts")], before_parenthesis(peak),
                    paren == std::string::npos ? "" : peak.substr(paren + 1, peak.find(')') - paren - 1)});
  }
  return rows;
}

RecordSource source_for(const IndexRow& row) {
  RecordSource src;
  src.path = kRecords + "/" + row.file;
  src.units = row.units;
  // Michoacan: columns t, NS, EW, V; the index gives the peak of one of them.
  const std::map<std::string, std::string> component_column = {{"NS", "2"}, {"EW", "3"}, {"V", "4"}};
  if (!row.component.empty()) src.column = component_column.at(row.component);
  return src;
}

// Issue requirement: every shared record reads with its index's NPTS, DT and
// peak. Peak: |value| in the file's own units, to half a unit of the printed
// last digit (SI conversion and back adds ~1e-16 relative). DT: AT2 times
// are i DT exactly; column files print times to >= 5 decimals (Michoacan:
// 0.02000, 163.37999), so each step is within 1e-5 s of DT and the mean step
// within 1e-5 / (n - 1) s, plus binary round-off of the printed times.
TEST(GroundMotionReader, EveryIndexedRecordMatchesItsIndex) {
  const std::vector<IndexRow> rows = read_index();
  ASSERT_EQ(rows.size(), 13u);  // the files listed in README.md
  for (const IndexRow& row : rows) {
    SCOPED_TRACE(row.file);
    const GroundRecord r = read_ground_record(source_for(row));
    const std::size_t n = r.t.size();
    EXPECT_EQ(n, std::stoul(row.npts));
    const double dt = std::stod(row.dt);
    EXPECT_NEAR((r.t.back() - r.t.front()) / (n - 1), dt, 1e-5 / (n - 1) + 1e-12);
    for (std::size_t i = 1; i < n; ++i) ASSERT_NEAR(r.t[i] - r.t[i - 1], dt, 1e-5 + 1e-12) << i;
    double peak = 0.0;
    for (double x : r.value) peak = std::max(peak, std::abs(x));
    EXPECT_NEAR(peak / si_per_unit(row.units), std::stod(row.peak), half_last_digit(row.peak));
    EXPECT_EQ(r.is_velocity, row.quantity.rfind("VELOCITY", 0) == 0);
  }
}

// Every record becomes a baseline-corrected table motion that ends at rest.
// Tolerance: node sums of n <~ 1.5e4 terms round by ~n eps ~ 3e-12 of the
// scale PGA T (velocity) or PGA T^2 (displacement); 1e-9 is generous.
TEST(GroundMotionReader, EveryIndexedRecordShapesIntoAMotionEndingAtRest) {
  for (const IndexRow& row : read_index()) {
    SCOPED_TRACE(row.file);
    const GroundRecord r = read_ground_record(source_for(row));
    const std::vector<double> a = r.is_velocity ? differentiate(r.t, r.value) : r.value;
    RecordShaping shaping;
    shaping.baseline_correct = true;
    const auto m = shape_record(r.t, a, shaping);
    const double T = m->duration(), pga = m->peak_acceleration();
    EXPECT_NEAR(T, r.t.back() - r.t.front(), 1e-12 * T);
    EXPECT_NEAR(m->at(T).velocity, 0.0, 1e-9 * pga * T);
    EXPECT_NEAR(m->at(T).displacement, 0.0, 1e-9 * pga * T * T);
  }
}

// Michoacan (SCT 1985): four columns t, NS, EW, V in g, starting at t = 0.02.
// Peaks of NS and V are the file's printed values, exact in g up to the
// conversion round-off (1e-15 relative).
TEST(GroundMotionReader, MichoacanColumnsAndStartTime) {
  RecordSource src;
  src.path = kRecords + "/Michoacan1985_MexicoCity_SCT_NS_EW_V_g_dt0.02.txt";
  src.units = "g";
  const std::map<std::string, double> peaks = {{"2", 0.09953}, {"3", 0.17117}, {"4", 0.03734}};
  for (const auto& [column, peak_g] : peaks) {
    src.column = column;
    const GroundRecord r = read_ground_record(src);
    EXPECT_EQ(r.t.front(), 0.02);
    double peak = 0.0;
    for (double x : r.value) peak = std::max(peak, std::abs(x));
    EXPECT_NEAR(peak, peak_g * 9.80665, 1e-15 * peak) << column;
    EXPECT_NE(r.source.find("(column " + column + ")"), std::string::npos);
  }
}

// ---- formats and units on small files ------------------------------------------

class ReaderFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("freestand_reader_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` to a file `name` in the test's directory; returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  static RecordSource source(const std::string& path, const std::string& units,
                             const std::string& column = "") {
    RecordSource s;
    s.path = path;
    s.units = units;
    s.column = column;
    return s;
  }
  // Expects an InputError whose message starts with `where` (e.g. "path:3:")
  // and contains `what`.
  static void expect_error(const RecordSource& src, const std::string& where,
                           const std::string& what) {
    try {
      read_ground_record(src);
      ADD_FAILURE() << "no InputError for " << src.path;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(where, 0), 0u) << message;
      EXPECT_NE(message.find(what), std::string::npos) << message;
    }
  }

  fs::path dir_;  // scratch directory, removed after the test
};

// Each unit's SI factor, exactly (one multiplication by an exact or
// correctly rounded constant).
TEST_F(ReaderFiles, UnitsConvertToSI) {
  const std::string path = write("r.txt", "0 1\n0.5 -2\n");
  const std::map<std::string, std::pair<double, bool>> expected = {
      {"g", {9.80665, false}}, {"m/s^2", {1.0, false}}, {"cm/s^2", {0.01, false}},
      {"mm/s^2", {0.001, false}}, {"m/s", {1.0, true}}, {"cm/s", {0.01, true}}};
  for (const auto& [units, factor_velocity] : expected) {
    const GroundRecord r = read_ground_record(source(path, units));
    EXPECT_EQ(r.value[0], factor_velocity.first) << units;
    EXPECT_EQ(r.value[1], -2.0 * factor_velocity.first) << units;
    EXPECT_EQ(r.is_velocity, factor_velocity.second) << units;
  }
}

// Leading lines without any number are a header; '#' comments and blank
// lines are skipped anywhere; CRLF line ends and tabs are accepted.
TEST_F(ReaderFiles, ColumnsSkipHeaderCommentsAndBlankLines) {
  const std::string path =
      write("r.dat", "Time [s]\tAcc [g]\r\n# recorded 1999\r\n\r\n0\t+1.5e-1\r\n0.01 2\r\n# end\r\n");
  const GroundRecord r = read_ground_record(source(path, "m/s^2"));
  EXPECT_EQ(r.t, (std::vector<double>{0.0, 0.01}));
  EXPECT_EQ(r.value, (std::vector<double>{0.15, 2.0}));
}

TEST_F(ReaderFiles, CsvByNameOrNumber) {
  const std::string path = write("r.csv", "time,\"ns\", ew\n0,1,10\n0.1,2,20\n0.2,3,30\n");
  EXPECT_EQ(read_ground_record(source(path, "m/s^2")).value, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(read_ground_record(source(path, "m/s^2", "ew")).value,
            (std::vector<double>{10, 20, 30}));
  EXPECT_EQ(read_ground_record(source(path, "m/s^2", "ns")).value,
            (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(read_ground_record(source(path, "m/s^2", "3")).value,
            (std::vector<double>{10, 20, 30}));
}

// The old PEER variant with the numbers first on line 4, and NGA spacing.
TEST_F(ReaderFiles, At2LineFourVariants) {
  const std::string old = write("old.AT2", "a\nb\nc\n    3    .50000    NPTS, DT\n 1 2\n 3\n");
  const GroundRecord r = read_ground_record(source(old, "m/s^2"));
  EXPECT_EQ(r.t, (std::vector<double>{0.0, 0.5, 1.0}));
  EXPECT_EQ(r.value, (std::vector<double>{1, 2, 3}));
  const std::string nga = write("nga.at2", "a\nb\nc\nNPTS=    2,DT=   0.0200 SEC\n1 2\n");
  EXPECT_EQ(read_ground_record(source(nga, "m/s^2")).t, (std::vector<double>{0.0, 0.02}));
}

// ---- one test per error --------------------------------------------------------

TEST_F(ReaderFiles, MissingFile) {
  const std::string path = (dir_ / "nope.AT2").string();
  expect_error(source(path, "g"), path + ": ", "cannot open");
}

TEST_F(ReaderFiles, UnknownUnit) {
  const std::string path = write("r.txt", "0 1\n1 2\n");
  expect_error(source(path, "gal"), path + ": ", "unknown units 'gal'");
  expect_error(source(path, ""), path + ": ", "unknown units ''");  // units are required
}

TEST_F(ReaderFiles, NonNumericToken) {
  const std::string path = write("r.txt", "0 1\n0.01 2\n0.02 abc\n");
  expect_error(source(path, "g"), path + ":3: ", "non-numeric token 'abc'");
  // Text mixed with numbers is data, not a header: an error too.
  const std::string mixed = write("m.txt", "DT= 0.01\n0 1\n");
  expect_error(source(mixed, "g"), mixed + ":1: ", "non-numeric token 'DT='");
  const std::string at2 = write("r.AT2", "a\nb\nc\nNPTS= 3, DT= .01 SEC\n1 2\n3.0D+00\n");
  expect_error(source(at2, "g"), at2 + ":6: ", "non-numeric token '3.0D+00'");
}

TEST_F(ReaderFiles, At2FewerValuesThanNpts) {
  const std::string path = write("r.AT2", "a\nb\nc\nNPTS= 4, DT= .01 SEC\n1 2\n3\n");
  expect_error(source(path, "g"), path + ":4: ", "NPTS= 4 but the file holds 3 values");
}

TEST_F(ReaderFiles, At2MoreValuesThanNpts) {
  const std::string path = write("r.AT2", "a\nb\nc\nNPTS= 2, DT= .01 SEC\n1\n2\n3\n");
  expect_error(source(path, "g"), path + ":7: ", "more values than NPTS= 2");
}

// An AT2 file has no time column, so DT cannot contradict the data; an
// invalid or missing DT is still an error.
TEST_F(ReaderFiles, At2InvalidOrMissingDt) {
  const std::string zero = write("z.AT2", "a\nb\nc\nNPTS= 2, DT= 0.0 SEC\n1 2\n");
  expect_error(source(zero, "g"), zero + ":4: ", "DT= 0 is not > 0");
  const std::string none = write("n.AT2", "a\nb\nc\nNPTS= 2\n1 2\n");
  expect_error(source(none, "g"), none + ":4: ", "expected 'NPTS=");
  const std::string frac = write("f.AT2", "a\nb\nc\nNPTS= 2.5, DT= 0.1 SEC\n1 2\n");
  expect_error(source(frac, "g"), frac + ":4: ", "not a positive whole number");
  const std::string short_header = write("s.AT2", "a\nb\n");
  expect_error(source(short_header, "g"), short_header + ":2: ", "header ends before line 4");
}

// The header's stated units must agree with the units given.
TEST_F(ReaderFiles, At2HeaderUnitsDisagree) {
  const std::string path =
      write("r.AT2", "a\nb\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 2, DT= .01 SEC\n1 2\n");
  expect_error(source(path, "m/s^2"), path + ":3: ", "header states units g");
}

TEST_F(ReaderFiles, NonIncreasingTime) {
  const std::string path = write("r.txt", "0 1\n0.01 2\n0.01 3\n");
  expect_error(source(path, "g"), path + ":3: ", "time 0.01 does not increase (line 2");
  const std::string back = write("b.csv", "t,a\n0,1\n0.02,2\n0.01,3\n");
  expect_error(source(back, "g"), back + ":4: ", "does not increase");
}

TEST_F(ReaderFiles, NanOrInf) {
  const std::string path = write("r.txt", "0 1\n0.01 nan\n");
  expect_error(source(path, "g"), path + ":2: ", "'nan' is not a finite number");
  const std::string inf = write("i.AT2", "a\nb\nc\nNPTS= 2, DT= .01 SEC\n1 -inf\n");
  expect_error(source(inf, "g"), inf + ":5: ", "'-inf' is not a finite number");
  const std::string huge = write("h.txt", "0 1\n0.01 1e999\n");
  expect_error(source(huge, "g"), huge + ":2: ", "'1e999' is not a finite number");
}

// No line is at fault in an empty record; the message names the file.
TEST_F(ReaderFiles, EmptyRecord) {
  const std::string blank = write("e.txt", "");
  expect_error(source(blank, "g"), blank + ": ", "empty record");
  const std::string header_only = write("h.txt", "time accel\n# nothing\n");
  expect_error(source(header_only, "g"), header_only + ": ", "empty record");
  const std::string csv = write("h.csv", "time,accel\n");
  expect_error(source(csv, "g"), csv + ": ", "empty record");
  const std::string one = write("o.txt", "0 1\n");
  expect_error(source(one, "g"), one + ":1: ", "only one sample");
}

TEST_F(ReaderFiles, MissingColumn) {
  const std::string path = write("r.txt", "0 1\n0.01 2\n");
  expect_error(source(path, "g", "3"), path + ":1: ", "no column 3");
  const std::string ragged = write("g.txt", "0 1 5\n0.01 2\n");
  expect_error(source(ragged, "g", "3"), ragged + ":2: ", "no column 3");
  const std::string uneven = write("u.txt", "0 1 5\n0.01 2\n");
  expect_error(source(uneven, "g"), uneven + ":2: ", "2 columns, but line 1 has 3");
  const std::string csv = write("r.csv", "time,ns\n0,1\n1,2\n");
  expect_error(source(csv, "g", "ew"), csv + ":1: ", "no column 'ew'");
  const std::string short_row = write("s.csv", "time,ns\n0,1\n1\n");
  expect_error(source(short_row, "g"), short_row + ":3: ", "1 fields, but the header (line 1) has 2");
  expect_error(source(path, "g", "1"), path + ": ", "column 1 is time");
}

TEST_F(ReaderFiles, CsvWithoutHeader) {
  const std::string path = write("r.csv", "0,1\n1,2\n");
  expect_error(source(path, "g"), path + ":1: ", "expected a CSV header");
}

// ---- differentiate --------------------------------------------------------------

// Three-point formulas are exact for quadratics, also on uneven steps and at
// the one-sided ends: v = 3 + 2 t - 5 t^2 -> a = 2 - 10 t, to round-off
// (|v| ~ 1e2, steps ~0.1: cancellation ~ eps |v| / h ~ 1e-13).
TEST(Differentiate, ExactForQuadraticsOnUnevenSteps) {
  const std::vector<double> t = {0.0, 0.1, 0.25, 0.3, 0.6, 0.65, 1.0, 1.4};
  std::vector<double> v;
  for (double x : t) v.push_back(3 + 2 * x - 5 * x * x);
  const std::vector<double> a = differentiate(t, v);
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(a[i], 2 - 10 * t[i], 1e-12) << i;
}

TEST(Differentiate, NeedsThreeSamples) {
  EXPECT_THROW(differentiate({0.0, 1.0}, {0.0, 1.0}), InputError);
}

}  // namespace
}  // namespace freestand
