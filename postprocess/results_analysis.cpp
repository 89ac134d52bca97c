#include "results_analysis.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"

namespace freestand {

namespace {

using analysis::BodyGeometry;
using analysis::BodyMotion;

// The base it rocks on: from the COM to the base faces' extreme x and y
// (the nearer edge on each side, so the smaller slenderness counts), and the
// COM height above the base.
BodyGeometry base_geometry(const BodySpec& body) {
  Eigen::AlignedBox3d base;
  for (const FaceRef& f : body.geometry.base_faces()) {
    const ConvexShape& piece = body.geometry.pieces()[f.piece];
    for (int v : piece.faces()[f.face].loop) base.extend(piece.vertices()[v]);
  }
  BodyGeometry g;
  if (base.isEmpty()) return g;
  g.half_width_x = std::min(base.max().x() - body.com.x(), body.com.x() - base.min().x());
  g.half_width_y = std::min(base.max().y() - body.com.y(), body.com.y() - base.min().y());
  g.com_height = body.com.z() - base.min().z();
  return g;
}

const BodySpec* find_body(const Scene& scene, const std::string& name) {
  for (const BodySpec& b : scene.bodies)
    if (b.name == name) return &b;
  return nullptr;
}

std::vector<Eigen::Vector3d> vectors(const BodyResults& b, const char* x, const char* y, const char* z) {
  const Series &a = b.at(x), &c = b.at(y), &d = b.at(z);
  std::vector<Eigen::Vector3d> out(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) out[k] = {a[k], c[k], d[k]};
  return out;
}

std::vector<Eigen::Quaterniond> orientations(const BodyResults& b) {
  const Series &w = b.at("qw"), &x = b.at("qx"), &y = b.at("qy"), &z = b.at("qz");
  std::vector<Eigen::Quaterniond> out(w.size());
  for (std::size_t k = 0; k < w.size(); ++k) out[k] = Eigen::Quaterniond(w[k], x[k], y[k], z[k]);
  return out;
}

// Velocity and vertical displacement of the point a body slides against:
// the table, or the top-face centre of the body below.
void support_motion(const Results& results, const Scene& scene, const BodySpec& body,
                    std::vector<Eigen::Vector3d>& velocity, std::vector<double>& uplift) {
  const std::size_t n = results.time.size();
  velocity.assign(n, Eigen::Vector3d::Zero());
  uplift.assign(n, 0.0);
  if (body.supported_by == "table") {
    if (results.table.empty()) return;
    for (std::size_t k = 0; k < n; ++k) {
      velocity[k] = {results.table.at("vx")[k], results.table.at("vy")[k], results.table.at("vz")[k]};
      uplift[k] = results.table.at("dz")[k] - results.table.at("dz")[0];
    }
    return;
  }
  const BodySpec* below = find_body(scene, body.supported_by);
  const BodyResults& b = results.body(body.supported_by);
  const auto com = vectors(b, "x", "y", "z"), v = vectors(b, "vx", "vy", "vz"), w = vectors(b, "wx", "wy", "wz");
  const auto q = orientations(b);
  const Eigen::Vector3d top(0, 0, below->height);
  double z0 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d r = q[k] * (top - below->com);
    velocity[k] = v[k] + w[k].cross(r);
    const double z = com[k].z() + r.z();
    if (k == 0) z0 = z;
    uplift[k] = z - z0;
  }
}

}  // namespace

analysis::AnalysisParameters parameters_for(const nlohmann::json& nominal) {
  analysis::AnalysisParameters p;
  if (nominal.is_object() && nominal.contains("sensor_noise")) {
    const auto& noise = nominal["sensor_noise"];
    p.angle_noise = noise.value("angle", p.angle_noise);
    p.length_noise = noise.value("length", p.length_noise);
  }
  return p;
}

std::vector<AnalysedBody> analyse_results(const Results& results, const analysis::AnalysisParameters& parameters) {
  if (!results.scenario.is_object())
    throw InputError(results.path + ": no scenario attribute: the bodies' geometry is unknown");
  const Scene scene = parse_scene(results.scenario, results.path + ": scenario");
  std::vector<AnalysedBody> out;
  for (const BodySpec& spec : scene.bodies) {
    const BodyResults& b = results.body(spec.name);
    AnalysedBody a{spec.name, spec.supported_by, {}, base_geometry(spec), {}};
    a.motion.time = results.time;
    const auto& names = channel_names();
    for (std::size_t c = 0; c < names.size(); ++c) a.motion.channels[c] = b.at(names[c]);
    if (b.has("vx")) {
      std::vector<Eigen::Vector3d> support_velocity;
      support_motion(results, scene, spec, support_velocity, a.motion.support_uplift);
      a.motion.rates = analysis::channel_rates(orientations(b), vectors(b, "wx", "wy", "wz"),
                                               vectors(b, "vx", "vy", "vz"), support_velocity, spec.com);
    }
    a.summary = analysis::analyse_motion(a.motion, a.geometry, parameters);
    out.push_back(std::move(a));
  }
  return out;
}

std::vector<AnalysedBody> analyse_recording(const Recording& recording) {
  // Geometry from the nominal when it parses as a scene (shapes stated).
  Scene scene;
  bool shapes = true;
  try {
    scene = parse_scene(recording.nominal, recording.path + ": nominal");
  } catch (const InputError&) {
    shapes = false;
  }
  const analysis::AnalysisParameters parameters = parameters_for(recording.nominal);
  std::vector<AnalysedBody> out;
  for (const std::string& name : recording.body_names()) {
    AnalysedBody a;
    a.name = name;
    a.supported_by = "table";
    if (const BodySpec* spec = shapes ? find_body(scene, name) : nullptr) {
      a.geometry = base_geometry(*spec);
      a.supported_by = spec->supported_by;
    }
    a.motion.time = recording.time;
    const auto& names = channel_names();
    for (std::size_t c = 0; c < names.size(); ++c)
      if (const RecordingChannel* ch = recording.find(name + "." + names[c])) a.motion.channels[c] = ch->values;
    a.summary = analysis::analyse_motion(a.motion, a.geometry, parameters);
    out.push_back(std::move(a));
  }
  return out;
}

}  // namespace freestand
