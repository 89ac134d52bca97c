#include "shooting.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "results_analysis.h"
#include "signal_tools.h"

namespace freestand {

namespace {

using nlohmann::json;

// The cut times: `margin` before each motion episode that follows a rest of at least
// `min_rest` on the base, keeping every piece at least `min_segment` long and with a
// motion episode of its own (a piece of rest alone has no events to compare: a cut before
// the first episode would leave the fit set empty and hold out the whole motion).
std::vector<double> cut_times(const AnalysedBody& body, const analysis::AnalysisParameters& p,
                              const ShootingOptions& o, double start, double end) {
  std::vector<double> cuts;
  const auto& modes = body.summary.modes;
  bool moved = false;  // the piece that the next cut would end holds a motion episode
  for (std::size_t i = 0; i + 1 < modes.size(); ++i) {
    const analysis::ModeSegment& rest = modes[i];
    if (rest.mode != analysis::Mode::rest && rest.mode != analysis::Mode::lost) moved = true;
    if (!moved || rest.mode != analysis::Mode::rest || modes[i + 1].mode == analysis::Mode::lost) continue;
    const double cut = modes[i + 1].start - o.margin;
    if (modes[i + 1].start - rest.start < o.min_rest || cut < rest.start) continue;
    if (cut - (cuts.empty() ? start : cuts.back()) < o.min_segment || end - cut < o.min_segment) continue;
    const signal::IndexRange r = signal::index_range(body.motion.time, rest.start, cut);
    const double tilt = std::hypot(signal::finite_mean(body.motion.channels[analysis::kRockX], r),
                                   signal::finite_mean(body.motion.channels[analysis::kRockY], r));
    if (!(tilt <= o.max_tilt_sds * p.angle_noise)) continue;  // not resting on its base
    cuts.push_back(cut);
    moved = false;
  }
  return cuts;
}

// The samples of `r` in [from, to), with the body channels that are stated from the start
// (slide, twist, uplift) re-zeroed at `from`.
Recording piece(const Recording& r, const std::string& body, double from, double to) {
  Recording out;
  out.path = fmt::format("{}@{:.2f}s", r.path, from), out.nominal = r.nominal, out.warnings = r.warnings;
  const signal::IndexRange range = signal::index_range(r.time, from, to);
  out.time.assign(r.time.begin() + range.first, r.time.begin() + range.last);
  for (const RecordingChannel& c : r.channels) {
    RecordingChannel cut{c.name, {c.values.begin() + range.first, c.values.begin() + range.last}, c.derived};
    for (const char* relative : {".slide_x", ".slide_y", ".twist", ".uplift"})
      if (c.name == body + relative && !cut.values.empty())
        for (double& v : cut.values) v -= c.values[range.first];
    out.channels.push_back(std::move(cut));
  }
  return out;
}

// The nominal body at rest where the recording shows it at `at`: moved by the slide, turned by
// the twist about the vertical through its base centre; no velocity or spin.
void place_at_rest(json& body, const Recording& r, const std::string& name, double at) {
  const auto value = [&](const char* channel) {
    const RecordingChannel* c = r.find(name + "." + channel);
    return c ? signal::interpolate(r.time, c->values, at) : 0.0;
  };
  std::vector<double> p = body.value("position", std::vector<double>{0, 0, 0});
  p[0] += value("slide_x"), p[1] += value("slide_y");
  const auto q = body.value("orientation", std::vector<double>{1, 0, 0, 0});
  const Eigen::Quaterniond turned =
      Eigen::Quaterniond(Eigen::AngleAxisd(value("twist"), Eigen::Vector3d::UnitZ())) * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  body["position"] = p;
  body["orientation"] = {turned.w(), turned.x(), turned.y(), turned.z()};
  body.erase("velocity"), body.erase("omega");
}

}  // namespace

std::vector<Recording> shooting_segments(const Recording& recording, const ShootingOptions& options) {
  const std::vector<AnalysedBody> bodies = analyse_recording(recording);
  if (bodies.size() != 1 || recording.time.size() < 2) return {recording};
  const AnalysedBody& body = bodies.front();
  const double start = recording.time.front(), end = recording.time.back();
  std::vector<double> cuts = cut_times(body, parameters_for(recording.nominal), options, start, end);
  if (cuts.empty()) return {recording};
  cuts.insert(cuts.begin(), start);
  std::vector<Recording> out;
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    const double to = i + 1 < cuts.size() ? cuts[i + 1] : end + 1;  // the last piece keeps the last sample
    Recording p = piece(recording, body.name, cuts[i], to);
    if (i > 0)
      for (json& b : p.nominal["bodies"])
        if (b.value("name", "") == body.name) place_at_rest(b, recording, body.name, cuts[i]);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace freestand
