// The free-rocking block of inputs/convex/free_rocking.in in MuJoCo (Debian
// libmujoco-dev 2.2.2), for bench/time_to_accuracy.sh only: a 0.25 x 0.25 x
// 1.0 m, 100 kg box (uniform inertia, free joint) on a plane, released at rest
// tilted theta0 = alpha/2 about its +x base edge, which touches the plane.
// Steps it with the time step and solver options given on the command line,
// samples rock_x = atan2(e3.x, e3.z) (e3: the body's z axis in the world, as
// compute rockslide), and writes "time rock_x" rows to --out. Prints the wall
// time of the stepping loop alone (model compilation and output excluded).

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr double kHalfWidth = 0.125, kHalfDepth = 0.125, kHalfHeight = 0.5;  // m
constexpr double kMass = 100.0;                                               // kg

struct Settings {
  double dt = 0.002;  // MuJoCo's default time step (s)
  double t_end = 2.6;
  double sample = 5e-4;  // sampling interval of rock_x (s)
  // MJCF attribute values, passed through as text: MuJoCo's parser checks them.
  std::string integrator = "Euler", cone = "pyramidal", solver = "Newton";
  std::string solref = "0.02 1", solimp = "0.9 0.95 0.001 0.5 2";
  std::string friction = "0.6", condim = "3", impratio = "1";
  std::string iterations = "100", tolerance = "1e-8", noslip_iterations = "0";
  std::string refsafe = "enable";
  std::string out;
  bool print_xml = false;
};

// The model, MuJoCo's defaults where Settings keep theirs. The body frame is
// at the box centre; the +x base edge lies on the plane z = 0.
std::string model_xml(const Settings& s) {
  const double theta0 = 0.5 * std::atan2(kHalfWidth, kHalfHeight);
  const double c = std::cos(theta0), sn = std::sin(theta0);
  // Centre = edge point (b, 0, 0) + R_y(theta0) (-b, 0, h).
  const double x = kHalfWidth - kHalfWidth * c + kHalfHeight * sn;
  const double z = kHalfWidth * sn + kHalfHeight * c;
  return fmt::format(
      R"(<mujoco model="free_rocking">
  <option timestep="{dt:.17g}" gravity="0 0 -9.81" integrator="{integ}" cone="{cone}"
          solver="{solver}" iterations="{iter}" tolerance="{tol}"
          noslip_iterations="{noslip}" impratio="{imp}">
    <flag refsafe="{refsafe}"/>
  </option>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" condim="{condim}" friction="{mu} 0.005 0.0001"
          solref="{solref}" solimp="{solimp}"/>
    <body name="block" pos="{x:.17g} 0 {z:.17g}" quat="{qw:.17g} 0 {qy:.17g} 0">
      <freejoint/>
      <geom type="box" size="{b} {d} {h}" mass="{m}" condim="{condim}"
            friction="{mu} 0.005 0.0001" solref="{solref}" solimp="{solimp}"/>
    </body>
  </worldbody>
</mujoco>
)",
      fmt::arg("dt", s.dt), fmt::arg("integ", s.integrator), fmt::arg("cone", s.cone),
      fmt::arg("solver", s.solver), fmt::arg("iter", s.iterations), fmt::arg("tol", s.tolerance),
      fmt::arg("noslip", s.noslip_iterations), fmt::arg("imp", s.impratio),
      fmt::arg("refsafe", s.refsafe), fmt::arg("condim", s.condim), fmt::arg("mu", s.friction),
      fmt::arg("solref", s.solref), fmt::arg("solimp", s.solimp), fmt::arg("x", x),
      fmt::arg("z", z), fmt::arg("qw", std::cos(0.5 * theta0)),
      fmt::arg("qy", std::sin(0.5 * theta0)), fmt::arg("b", kHalfWidth),
      fmt::arg("d", kHalfDepth), fmt::arg("h", kHalfHeight), fmt::arg("m", kMass));
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Compiles the MJCF text through MuJoCo's in-memory file system.
ModelPtr compile(const std::string& xml) {
  auto vfs = std::make_unique<mjVFS>();  // ~2 MB: not on the stack
  mj_defaultVFS(vfs.get());
  const char* name = "free_rocking.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("cannot create the in-memory model file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name)], xml.data(), xml.size());
  char error[1000] = "";
  ModelPtr model(mj_loadXML(name, vfs.get(), error, sizeof error));
  mj_deleteVFS(vfs.get());
  if (!model) throw std::runtime_error(fmt::format("MuJoCo rejected the model: {}", error));
  return model;
}

struct Record {
  std::vector<double> t, rock_x;
  double loop_seconds = 0.0;
};

// From the state itself (qpos at d.time): xmat lags a step behind mj_step.
double rock_x(const mjData& d) {
  const mjtNum* q = d.qpos + 3;  // free joint: position, then quaternion w x y z
  const double e3x = 2 * (q[1] * q[3] + q[0] * q[2]);
  const double e3z = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
  return std::atan2(e3x, e3z);
}

Record simulate(const mjModel& m, mjData& d, const Settings& s) {
  const long steps = std::lround(s.t_end / s.dt);
  const long every = std::max(1L, std::lround(s.sample / s.dt));
  Record rec;
  rec.t.reserve(steps / every + 2);
  rec.rock_x.reserve(steps / every + 2);
  rec.t.push_back(d.time);
  rec.rock_x.push_back(rock_x(d));
  const auto start = std::chrono::steady_clock::now();
  for (long k = 1; k <= steps; ++k) {
    mj_step(&m, &d);
    if (k % every == 0) {
      rec.t.push_back(d.time);
      rec.rock_x.push_back(rock_x(d));
    }
  }
  rec.loop_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return rec;
}

void write_atomically(const std::string& path, const Record& rec, const Settings& s) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + tmp);
  fmt::print(f, "# MuJoCo {} free rocking, dt {} s: time (s), rock_x (rad)\n", mj_versionString(),
             s.dt);
  for (std::size_t i = 0; i < rec.t.size(); ++i)
    fmt::print(f, "{:.9g} {:.12g}\n", rec.t[i], rec.rock_x[i]);
  if (std::fclose(f) != 0 || std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot write " + path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Free rocking of a 0.25 x 0.25 x 1.0 m block in MuJoCo"};
  Settings s;
  app.add_option("--dt", s.dt, "time step (s)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--tend", s.t_end, "simulated time (s)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--sample", s.sample, "sampling interval of rock_x (s)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--integrator", s.integrator, "Euler, RK4, implicit")->capture_default_str();
  app.add_option("--cone", s.cone, "pyramidal, elliptic")->capture_default_str();
  app.add_option("--solver", s.solver, "Newton, CG, PGS")->capture_default_str();
  app.add_option("--iterations", s.iterations, "solver iterations")->capture_default_str();
  app.add_option("--tolerance", s.tolerance, "solver tolerance")->capture_default_str();
  app.add_option("--noslip", s.noslip_iterations, "noslip iterations")->capture_default_str();
  app.add_option("--impratio", s.impratio, "friction-to-normal impedance ratio")
      ->capture_default_str();
  app.add_option("--solref", s.solref, "contact solref: 'timeconst dampratio' or '-k -b'")
      ->capture_default_str();
  app.add_option("--solimp", s.solimp, "contact solimp: 'dmin dmax width midpoint power'")
      ->capture_default_str();
  app.add_option("--friction", s.friction, "sliding friction coefficient")->capture_default_str();
  app.add_option("--condim", s.condim, "contact dimensionality (1, 3, 4, 6)")
      ->capture_default_str();
  app.add_option("--refsafe", s.refsafe, "enable: timeconst >= 2 dt; disable")
      ->capture_default_str();
  app.add_option("--out", s.out, "output file: time, rock_x rows");
  app.add_flag("--print-xml", s.print_xml, "print the model and exit");
  CLI11_PARSE(app, argc, argv);
  try {
    const std::string xml = model_xml(s);
    if (s.print_xml) {
      fmt::print("{}", xml);
      return 0;
    }
    if (s.out.empty()) throw std::runtime_error("--out is required");
    const ModelPtr model = compile(xml);
    const DataPtr data(mj_makeData(model.get()));
    const Record rec = simulate(*model, *data, s);
    write_atomically(s.out, rec, s);
    fmt::print("loop_seconds {:.6f} steps {} contacts_at_end {}\n", rec.loop_seconds,
               std::lround(s.t_end / s.dt), data->ncon);
  } catch (const std::exception& error) {
    fmt::print(stderr, "mujoco_free_rocking: {}\n", error.what());
    return 1;
  }
  return 0;
}
