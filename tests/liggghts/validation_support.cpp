#include "validation_support.h"

#include <chrono>
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


}  // namespace freestand::validation
