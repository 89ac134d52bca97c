#include "validation_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "input.h"
#include "lammps.h"
#include "liggghts_session.h"
#include "run_command.h"

namespace fs = std::filesystem;

namespace freestand::validation {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::absolute(fs::path("validation") / name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string convex_preamble(double half_x, double half_y, double z_lo, double z_hi) {
  return "atom_style sphere\natom_modify map array sort 0 0.0\nboundary f f f\n"
         "processors * 1 1\nnewton off\ncommunicate single vel yes\nunits si\n"
         "region domain block " + num(-half_x) + " " + num(half_x) + " " + num(-half_y) + " " +
         num(half_y) + " " + num(z_lo) + " " + num(z_hi) + " units box\ncreate_box 1 domain\n"
         "neighbor 0.05 bin\nneigh_modify delay 0 binsize 1.0\n";
}

std::string source_path(const std::string& relative) {
  return (fs::path(FREESTAND_SOURCE_DIR) / relative).string();
}

std::string make_clump(const fs::path& dir, const std::string& name, const BlockClump& b) {
  const std::string prefix = (dir / name).string();
  std::ostringstream command;
  command.precision(17);
  command << "python3 " << source_path("inputs/free_rocking/gen_block_clump.py") << " --W "
          << b.width << " --D " << b.depth << " --H " << b.height << " --mass " << b.mass
          << " --nz " << b.nz << " --ntop " << b.ntop << " --rbase " << b.rbase << " --rside "
          << b.rside << " --prefix " << prefix;
  int status = 0;
  const std::string out = freestand::testing::capture_command(command.str(), &status);
  if (status != 0) throw std::runtime_error("clump generation failed: " + command.str() + "\n" + out);
  return prefix;
}

void run_input(const std::string& script, const Variables& variables) {
  freestand::testing::LiggghtsSession session;
  for (const auto& [name, value] : variables)
    session.commands("variable " + name + " index \"" + value + "\"");
  // Input::file(name) runs a whole script as -in would (an `include` sent
  // through one() would only be queued).
  session.lmp()->input->file(script.c_str());
}

std::vector<std::vector<double>> read_rows(const fs::path& file, std::size_t columns) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    double value;
    while (fields >> value) row.push_back(value);
    if (row.size() < columns)
      throw std::runtime_error(file.string() + ": short line '" + line + "'");
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<double> column(const std::vector<std::vector<double>>& rows, std::size_t index) {
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(row.at(index));
  return out;
}

std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

double wall_seconds() {
  using clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

RockingCycles rocking_cycles(const std::vector<double>& t, const std::vector<double>& theta,
                             double hysteresis) {
  RockingCycles out;
  const std::size_t n = t.size();
  // Sign of the current half-cycle, set once |theta| exceeds the hysteresis.
  int sign = 0;
  double last_crossing = NAN;
  std::vector<std::size_t> starts;  // first sample index of each half-cycle after an impact
  for (std::size_t k = 1; k < n; ++k) {
    if ((theta[k - 1] > 0) != (theta[k] > 0)) {
      // Linear interpolation of the zero crossing.
      last_crossing = t[k - 1] + (t[k] - t[k - 1]) * theta[k - 1] / (theta[k - 1] - theta[k]);
    }
    if (std::fabs(theta[k]) > hysteresis) {
      const int s = theta[k] > 0 ? 1 : -1;
      if (sign != 0 && s != sign && !std::isnan(last_crossing)) {
        out.impacts.push_back(last_crossing);
        starts.push_back(k);
      }
      sign = s;
    }
  }
  // Amplitude between consecutive impacts.
  for (std::size_t i = 0; i + 1 < out.impacts.size(); ++i) {
    std::size_t best = starts[i];
    for (std::size_t k = starts[i]; k < n && t[k] < out.impacts[i + 1]; ++k)
      if (std::fabs(theta[k]) > std::fabs(theta[best])) best = k;
    double peak = std::fabs(theta[best]);
    if (best > 0 && best + 1 < n) {
      // Vertex of the parabola through three equally spaced samples.
      const double a = std::fabs(theta[best - 1]), b = peak, c = std::fabs(theta[best + 1]);
      const double curvature = a - 2 * b + c;
      if (curvature < 0) peak = b - (a - c) * (a - c) / (8 * curvature);
    }
    out.amplitudes.push_back(peak);
  }
  return out;
}

long first_rate_above(const std::vector<double>& t, const std::vector<double>& value,
                      std::size_t window, double direction, double threshold, std::size_t first) {
  for (std::size_t k = std::max(first, window); k < t.size(); ++k) {
    const double rate = (value[k] - value[k - window]) / (t[k] - t[k - window]);
    if (direction * rate > threshold) return static_cast<long>(k);
  }
  return -1;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xi) {
  if (xi <= x.front()) return y.front();
  if (xi >= x.back()) return y.back();
  const std::size_t hi = std::lower_bound(x.begin(), x.end(), xi) - x.begin();
  const double f = (xi - x[hi - 1]) / (x[hi] - x[hi - 1]);
  return y[hi - 1] + f * (y[hi] - y[hi - 1]);
}

}  // namespace freestand::validation
