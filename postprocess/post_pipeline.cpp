#include "post_pipeline.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "results.h"
#include "vtk_series.h"

namespace freestand {

namespace fs = std::filesystem;

namespace {

// The bodies' shapes from the scenario stored in the results.
std::vector<SeriesBody> series_bodies(const Results& results) {
  if (!results.scenario.is_object())
    throw InputError(results.path + ": no scenario attribute: the body shapes for ParaView are unknown");
  const Scene scene = parse_scene(results.scenario, results.path + ": scenario");
  std::vector<SeriesBody> bodies;
  for (const BodyResults& b : results.bodies) {
    const auto spec = std::find_if(scene.bodies.begin(), scene.bodies.end(),
                                   [&](const BodySpec& s) { return s.name == b.name; });
    if (spec == scene.bodies.end())
      throw InputError(fmt::format("{}: body '{}' is not in the scenario", results.path, b.name));
    bodies.push_back({b.name, spec->geometry, spec->com});
  }
  return bodies;
}

SeriesHistory history_of(const Results& results) {
  SeriesHistory h;
  h.time = results.time;
  for (const char* axis : {"x", "y", "z"}) {
    const auto it = results.table.find(std::string("d") + axis);
    std::vector<double>& d = axis[0] == 'x' ? h.table_dx : axis[0] == 'y' ? h.table_dy : h.table_dz;
    if (it != results.table.end()) d = it->second;
  }
  for (const BodyResults& b : results.bodies) {
    BodyHistory body;
    body.x = b.at("x"), body.y = b.at("y"), body.z = b.at("z");
    body.qw = b.at("qw"), body.qx = b.at("qx"), body.qy = b.at("qy"), body.qz = b.at("qz");
    const auto& names = channel_names();
    for (std::size_t k = 0; k < names.size(); ++k) body.channels[k] = b.at(names[k]);
    if (b.has("vx")) {
      body.vx = b.at("vx"), body.vy = b.at("vy"), body.vz = b.at("vz");
      body.wx = b.at("wx"), body.wy = b.at("wy"), body.wz = b.at("wz");
    }
    h.bodies.push_back(std::move(body));
  }
  return h;
}

void print_summary(const Results& results) {
  fmt::print("  {:<12} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "peak |.|", "rock_x", "rock_y", "twist",
             "slide_x", "slide_y", "uplift");
  for (const BodyResults& b : results.bodies) {
    fmt::print("  {:<12}", b.name);
    for (const std::string& channel : channel_names()) {
      double peak = 0;
      for (double v : b.at(channel)) peak = std::max(peak, std::fabs(v));
      fmt::print(" {:>10.4g}", peak);
    }
    fmt::print("\n");
  }
  fmt::print("  (rad, m; at {} s)\n", results.time.back());
}

}  // namespace

void postprocess(const std::string& results_path, const PostOptions& options) {
  const Results results = read_results(results_path);
  const fs::path dir = fs::path(results_path).parent_path();
  print_summary(results);
  if (options.csv) {
    const std::string stem = (dir / "channels").string();
    write_recording(stem, results_as_recording(results));
    fmt::print("  channels (recording format): {}.csv\n", stem);
  }
  if (options.vtk) {
    VtkSeriesOptions vtk;
    const double dt = results.time.size() > 1 ? results.time[1] - results.time[0] : 1.0;
    vtk.stride = std::max(1, static_cast<int>(std::lround(1.0 / (options.vtk_rate * dt))));
    vtk.table_top_z = results.scenario.value("table_height", 0.0);
    const std::string pvd =
        write_vtk_series((dir / "paraview").string(), series_bodies(results), history_of(results), vtk);
    fmt::print("  ParaView: {} (docs/paraview.md)\n", pvd);
  }
}

}  // namespace freestand
