#include "post_pipeline.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "events_file.h"
#include "results.h"
#include "results_analysis.h"
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

// Per sample, each body's resultant contact forces (table, other bodies) at a
// point of their line of action, when the results have them; the other body
// of a body-on-body resultant is the one it stands on (-2: several or unknown).
std::vector<std::vector<ContactVector>> contact_vectors(const Results& results) {
  std::vector<std::vector<ContactVector>> out;
  if (results.bodies.empty() || !results.bodies.front().has("table_fx")) return out;
  out.resize(results.time.size());
  for (std::size_t b = 0; b < results.bodies.size(); ++b) {
    const BodyResults& body = results.bodies[b];
    for (const char* kind : {"table", "bodies"}) {
      const std::string f = std::string(kind) + "_f", p = std::string(kind) + "_p";
      const Series &fx = body.at(f + "x"), &fy = body.at(f + "y"), &fz = body.at(f + "z");
      const Series &px = body.at(p + "x"), &py = body.at(p + "y"), &pz = body.at(p + "z");
      for (std::size_t k = 0; k < results.time.size(); ++k)
        if (fx[k] != 0.0 || fy[k] != 0.0 || fz[k] != 0.0)
          out[k].push_back({{px[k], py[k], pz[k]}, {fx[k], fy[k], fz[k]}, static_cast<int>(b),
                            kind[0] == 't' ? -1 : -2});
    }
  }
  return out;
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
  h.contacts = contact_vectors(results);
  return h;
}

// Seconds spent in each mode, largest first: "rock 12.3 s, rest 40.1 s".
std::string mode_times(const analysis::MotionSummary& s) {
  std::map<std::string, double> seconds;
  for (const analysis::ModeSegment& m : s.modes) seconds[analysis::mode_name(m.mode)] += m.end - m.start;
  std::vector<std::pair<double, std::string>> sorted;
  for (const auto& [mode, t] : seconds) sorted.emplace_back(-t, mode);
  std::sort(sorted.begin(), sorted.end());
  std::string out;
  for (const auto& [t, mode] : sorted) out += fmt::format("{}{} {:.1f} s", out.empty() ? "" : ", ", mode, -t);
  return out;
}

void print_summary(const Results& results, const std::vector<AnalysedBody>& bodies) {
  fmt::print("  {:<12} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "peak |.|", "rock_x", "rock_y", "twist",
             "slide_x", "slide_y", "uplift");
  for (const AnalysedBody& b : bodies) {
    fmt::print("  {:<12}", b.name);
    for (const analysis::Peak& p : b.summary.peaks) fmt::print(" {:>10.4g}", p.magnitude());
    fmt::print("\n  {:<12}", "  residual");
    for (double r : b.summary.residual.mean) fmt::print(" {:>10.3g}", r);
    fmt::print("\n");
  }
  fmt::print("  (rad, m; {:.2f} s simulated; residual = mean over the last 10 %)\n", results.time.back());
  for (const AnalysedBody& b : bodies) {
    const analysis::MotionSummary& s = b.summary;
    fmt::print("  {}: {}\n", b.name, mode_times(s));
    if (s.overturn.overturned) fmt::print("    OVERTURNED at {:.2f} s ({})\n", s.overturn.time, s.overturn.criterion);
    for (int axis = 0; axis < 2; ++axis) {
      const analysis::RockingImpacts& r = s.impacts[axis];
      if (r.impacts.empty()) continue;
      fmt::print("    {} impacts in {}: median omega ratio {:.3f} (Housner {:.3f})\n", r.impacts.size(),
                 axis == 0 ? "rock_x" : "rock_y", r.median_ratio, r.housner_ratio);
    }
    if (!s.slips.empty()) fmt::print("    {} slip events\n", s.slips.size());
  }
}

}  // namespace

void postprocess(const std::string& results_path, const PostOptions& options) {
  const Results results = read_results(results_path);
  const fs::path dir = fs::path(results_path).parent_path();
  const std::vector<AnalysedBody> bodies = analyse_results(results);
  write_events(results_path, bodies);
  print_summary(results, bodies);
  fmt::print("  events (impacts, slips, modes, peaks): {} /events\n", results_path);
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
