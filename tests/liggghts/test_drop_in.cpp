// freestand-lmp is a drop-in for Debian's liggghts binary: the same stock
// input gives byte-identical dumps and thermo output, serial and under mpirun.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "run_command.h"

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Thermo rows of a log: the lines between "Step ..." and "Loop time". Timing
// lines differ between any two runs of the same binary, so they are left out.
std::string thermo_rows(const std::string& log) {
  std::istringstream in(log);
  std::string line, rows;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("Step ", 0) == 0 || line.find(" Step ") != std::string::npos) inside = true;
    if (line.rfind("Loop time", 0) == 0) inside = false;
    if (inside) rows += line + "\n";
  }
  return rows;
}

// Runs `launcher binary` on the stock pour in its own directory.
fs::path run_pour(const std::string& name, const std::string& launcher) {
  const fs::path dir = fs::absolute(fs::path("drop_in") / name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command = launcher + " -in " FREESTAND_SOURCE_DIR
                              "/tests/liggghts/data/stock_pour.in -var out " + dir.string() +
                              " -log " + (dir / "log.txt").string() +
                              " -screen " + (dir / "screen.txt").string();
  const int status = freestand::testing::run_command(command);
  EXPECT_EQ(status, 0) << command;
  return dir;
}

void expect_identical(const fs::path& a, const fs::path& b) {
  const std::string dump_a = read_file(a / "pour.dump"), dump_b = read_file(b / "pour.dump");
  ASSERT_FALSE(dump_a.empty());
  EXPECT_EQ(dump_a, dump_b) << "dumps differ: " << a << " vs " << b;
  const std::string rows_a = thermo_rows(read_file(a / "log.txt"));
  ASSERT_NE(rows_a.find("5000"), std::string::npos) << "the run did not reach step 5000";
  EXPECT_EQ(rows_a, thermo_rows(read_file(b / "log.txt")));
}

}  // namespace

TEST(DropIn, StockInputGivesByteIdenticalOutputSerial) {
  expect_identical(run_pour("stock", "liggghts"), run_pour("freestand", FREESTAND_LMP));
}

TEST(DropIn, StockInputGivesByteIdenticalOutputUnderMpirun) {
  const std::string mpirun = freestand::testing::mpirun(2);
  expect_identical(run_pour("stock_np2", mpirun + " liggghts"),
                   run_pour("freestand_np2", mpirun + " " FREESTAND_LMP));
}

TEST(DropIn, HelpListsFreestandStylesWithStockOnes) {
  const std::string out = freestand::testing::capture_command(FREESTAND_LMP " -h");
  EXPECT_NE(out.find("shaketable (freestand)"), std::string::npos) << out;
  EXPECT_NE(out.find("rockslide (freestand)"), std::string::npos);
  EXPECT_NE(out.find("multisphere"), std::string::npos);  // a stock fix
  EXPECT_NE(out.find("gran"), std::string::npos);         // a stock pair style
}
