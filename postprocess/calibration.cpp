#include "calibration.h"

#include "signal_tools.h"

#include <fmt/format.h>
#include <stdlib.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <nlopt.hpp>
#include <unsupported/Eigen/NonLinearOptimization>
#include <thread>

#include "atomic_file.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "liggghts_runner.h"
#include "scenario.h"

namespace freestand {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// A failed simulation gives every residual this many times the largest
// residual of a model that ran (at least 1), so the optimiser moves away.
const double kFailedResidual = 10.0;

// Levenberg-Marquardt: the trust region is measured in the scaled
// coordinates (every parameter spans [0, 1]), and the first step may move the
// point by half its norm (MINPACK's `factor`; its default 100 makes the first
// step a plain Gauss-Newton one, which the strongly nonlinear residuals of a
// start far from the fit do not support; 0.5 was not tuned against other values).
const double kLevenbergMarquardtFactor = 0.5;
// It stops when a step lowers the objective by less than 1e-4 of it (for a
// chi-square near n ~ 300, 0.03: far below the change of 1 that one standard
// error makes).
const double kLevenbergMarquardtFtol = 1e-4;

// Default bounds and start of the parameters calibrate knows. Bounds are wide
// on purpose: the data, not the defaults, should decide.
const CalibrationParameter kKnownParameters[] = {
    {"stiffness", 1e6, 1e11, 1e9, true},       // N/m^3 per area
    {"restitution", 0.02, 0.95, 0.3, false},   // flat face-on impact
    {"mu", 0.02, 1.5, 0.5, false},
    {"mu_s", 0.02, 1.5, 0.5, false},
    {"mu_k", 0.02, 1.5, 0.5, false},
    {"friction_decay", 0.0, 50.0, 5.0, false},  // s/m
    {"table_height", -0.01, 0.01, 0.0, false},  // m
};

// y at `at` by linear interpolation, held at the end values outside the samples.
double linear_interpolate(const std::vector<double>& t, const std::vector<double>& y, double at) {
  return signal::interpolate(t, y, std::clamp(at, t.front(), t.back()));
}

// A body's pose at time `at`: centre linearly, orientation by slerp.
struct Pose {
  Eigen::Vector3d centre;
  Eigen::Quaterniond orientation;
  bool valid = false;
};
Pose pose_at(const Recording& r, const std::string& body, std::size_t k) {
  Pose p;
  double v[7];
  const char* keys[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  for (int i = 0; i < 7; ++i) v[i] = r.body_channel(body, keys[i])[k];
  p.centre = {v[0], v[1], v[2]};
  p.orientation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
  p.valid = std::all_of(v, v + 7, [](double x) { return std::isfinite(x); });
  if (p.valid) p.orientation.normalize();
  return p;
}
Pose pose_at_time(const Recording& r, const std::string& body, double at) {
  const std::vector<double>& t = r.time;
  const std::size_t i = std::min<std::size_t>(std::upper_bound(t.begin(), t.end(), at) - t.begin(), t.size() - 1);
  if (i == 0 || at >= t.back()) return pose_at(r, body, i);
  const Pose a = pose_at(r, body, i - 1), b = pose_at(r, body, i);
  const double w = (at - t[i - 1]) / (t[i] - t[i - 1]);
  Pose p;
  p.valid = a.valid && b.valid;
  if (p.valid) {
    p.centre = a.centre + w * (b.centre - a.centre);
    p.orientation = a.orientation.slerp(w, b.orientation);
  }
  return p;
}

bool has_pose(const Recording& r, const std::string& body) { return r.find(body + ".qw") != nullptr; }

// Indices of at most `count` samples spread evenly over the record.
std::vector<std::size_t> spread_samples(std::size_t size, std::size_t count) {
  std::vector<std::size_t> k;
  const std::size_t n = std::min(size, count);
  for (std::size_t i = 0; i < n; ++i) k.push_back(n == 1 ? 0 : i * (size - 1) / (n - 1));
  return k;
}

// Free rocking reduced to its impacts: an impact is a change of sign of the
// rock angle confirmed by the angle passing `hysteresis` on the other side
// (so noise near zero does not count). Both features are read from local
// least-squares fits rather than single samples, so that they resolve below
// the sampling step and measurement noise does not bias them: the impact time
// is the zero of a line through the 2 + 2 samples around the crossing, the
// amplitude of a half-cycle the vertex of a parabola through the 5 samples
// around its largest |angle| (the largest noisy sample overestimates it by
// about one noise deviation).
struct RockingFeatures {
  std::vector<double> impact_times, amplitudes;  // amplitudes[i]: half-cycle after impact i
  std::vector<double> impact_rates;              // |d angle/dt| at impact i (rad/s)
};
RockingFeatures rocking_features(const std::vector<double>& t, const std::vector<double>& angle, double hysteresis) {
  std::vector<std::size_t> crossings, peaks;  // sample after each confirmed crossing; largest |angle| after it
  int side = 0;
  std::size_t crossing = 0, peak = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double a = angle[k];
    if (!std::isfinite(a)) continue;
    if (k > 0 && std::isfinite(angle[k - 1]) && (a > 0) != (angle[k - 1] > 0)) crossing = k;
    const int now = a > hysteresis ? 1 : a < -hysteresis ? -1 : 0;
    if (now != 0 && side != 0 && now != side) {
      if (!crossings.empty()) peaks.push_back(peak);
      crossings.push_back(crossing);
      peak = k;
    }
    if (now != 0) side = now;
    if (!crossings.empty() && std::abs(a) > std::abs(angle[peak])) peak = k;
  }
  if (!crossings.empty()) peaks.push_back(peak);
  RockingFeatures f;
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < crossings.size(); ++i) {
    const std::size_t c = crossings[i], m = peaks[i];
    const signal::LocalFit line = signal::local_fit(t, angle, {c >= 2 ? c - 2 : 0, std::min(c + 2, n)}, t[c], 1, 0.0);
    if (!line.valid || line.slope == 0.0 || c == 0) continue;  // a crossing at lost samples: not timed
    f.impact_times.push_back(t[c] - line.value / line.slope);
    f.impact_rates.push_back(std::abs(line.slope));
    const signal::LocalFit top = signal::local_fit(t, angle, {m >= 2 ? m - 2 : 0, std::min(m + 3, n)}, t[m], 2, 0.0);
    double amplitude = std::abs(angle[m]);
    if (top.valid && top.curvature * top.value < 0.0) {  // a maximum of |angle|
      const double shift = -top.slope / top.curvature;   // vertex relative to t[m]
      if (std::abs(shift) <= t[std::min(m + 1, n - 1)] - t[m > 0 ? m - 1 : 0])  // within the 5 samples
        amplitude = std::abs(top.value + 0.5 * top.slope * shift);
    }
    f.amplitudes.push_back(amplitude);
  }
  return f;
}

// The rock channel of a body that moves most in the recording.
std::string rocking_channel(const Recording& r, const std::string& body) {
  double best = -1.0;
  std::string channel;
  for (const char* c : {"rock_x", "rock_y"}) {
    double range = 0.0;
    for (double v : r.body_channel(body, c)) if (std::isfinite(v)) range = std::max(range, std::abs(v));
    if (range > best) best = range, channel = c;
  }
  return channel;
}

double peak_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) if (std::isfinite(x)) m = std::max(m, std::abs(x));
  return m;
}

const int kMaxImpacts = 10;          // impacts compared per recording: later ones are small and noisy
const std::size_t kHistorySamples = 100;  // samples compared per channel of a history

// The measurement noise a recording's nominal states (sensor_noise: standard
// deviations of the angles and lengths), 0 where it states none.
struct SensorNoise {
  double angle = 0.0, length = 0.0;
};
SensorNoise sensor_noise(const Recording& r) {
  const json noise = r.nominal.value("sensor_noise", json::object());
  return {noise.value("angle", 0.0), noise.value("length", 0.0)};
}

// An impact is compared only while the recorded half-cycle after it reaches
// this many times the detection hysteresis: nearer the threshold, noise or a
// slightly different simulation makes or misses a half-cycle, and every later
// impact would be compared with the wrong one.
const double kComparedAmplitude = 2.0;

// Residuals are divided by the measurement noise of the feature when the
// recording states its sensor noise sigma (a least-squares fit is then a
// maximum-likelihood one): a crossing time fitted to 4 samples has the noise
// of their mean, sigma / 2, over the angular velocity; a 5-sample parabola's
// vertex sqrt(17/35) sigma = 0.70 sigma. Without stated noise, by the time of
// the first impact and by the peak angle.
void rocking_residuals(const Recording& rec, const Recording& sim, const std::string& body,
                       std::vector<double>& out) {
  const std::string channel = rocking_channel(rec, body);
  const std::vector<double>& angle = rec.body_channel(body, channel);
  const double amplitude = peak_abs(angle), hysteresis = 0.05 * amplitude;
  const RockingFeatures recorded = rocking_features(rec.time, angle, hysteresis);
  if (recorded.impact_times.empty())
    throw InputError(fmt::format("{}: body '{}' does not rock ({} never changes sign by more than {:.3g} rad): "
                                 "no impacts to compare", rec.path, body, channel, hysteresis));
  const RockingFeatures simulated = rocking_features(sim.time, sim.body_channel(body, channel), hysteresis);
  const double noise = sensor_noise(rec).angle;
  const double time_scale = recorded.impact_times.front() - rec.time.front();
  for (std::size_t i = 0; i < std::min<std::size_t>(recorded.impact_times.size(), kMaxImpacts); ++i) {
    if (i > 0 && recorded.amplitudes[i] < kComparedAmplitude * hysteresis) break;
    const bool happened = i < simulated.impact_times.size();
    out.push_back(((happened ? simulated.impact_times[i] : rec.time.back()) - recorded.impact_times[i]) /
                  (noise > 0 ? 0.5 * noise / recorded.impact_rates[i] : time_scale));
    out.push_back(((happened ? simulated.amplitudes[i] : 0.0) - recorded.amplitudes[i]) /
                  (noise > 0 ? std::sqrt(17.0 / 35.0) * noise : amplitude));
  }
}

// With stated sensor noise every sample is compared, divided by the noise;
// without, 100 samples spread over the record, divided by the channel's peak.
void history_residuals(const Recording& rec, const Recording& sim, const std::string& body,
                       std::vector<double>& out) {
  const SensorNoise noise = sensor_noise(rec);
  const bool weighted = noise.angle > 0 && noise.length > 0;
  const std::vector<std::size_t> samples =
      spread_samples(rec.time.size(), weighted ? rec.time.size() : kHistorySamples);
  int compared = 0;
  for (const char* channel : {"slide_x", "slide_y", "uplift", "rock_x", "rock_y", "twist"}) {
    const std::vector<double>& recorded = rec.body_channel(body, channel);
    const double peak = peak_abs(recorded);
    const bool length = channel[0] == 's' || channel[0] == 'u';
    // Below 2 mm or 20 mrad a channel is mostly measurement noise: dividing by
    // its peak would make noise the largest residuals.
    if (peak < (length ? 2e-3 : 2e-2)) continue;
    const double scale = weighted ? (length ? noise.length : noise.angle) : peak;
    const std::vector<double>& simulated = sim.body_channel(body, channel);
    for (std::size_t k : samples) {
      // A lost recorded sample compares with nothing; a simulation that
      // went non-finite (it blew up) is as bad as one that failed.
      const double s = linear_interpolate(sim.time, simulated, rec.time[k]);
      out.push_back(!std::isfinite(recorded[k]) ? 0.0
                    : std::isfinite(s)          ? (s - recorded[k]) / scale
                                                : kFailedResidual * peak / scale);
    }
    ++compared;
  }
  if (compared == 0)
    throw InputError(fmt::format("{}: body '{}' neither slides, lifts (2 mm), rocks nor twists (20 mrad): "
                                 "nothing to compare", rec.path, body));
}

void trajectory_residuals(const Recording& rec, const Recording& sim, const std::string& body,
                          std::vector<double>& out) {
  const double size = body_size(rec, body);
  for (std::size_t k = 0; k < rec.time.size(); ++k) {
    const Pose r = pose_at(rec, body, k), s = pose_at_time(sim, body, rec.time[k]);
    Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
    if (r.valid && !s.valid) e.setConstant(kFailedResidual);
    if (r.valid && s.valid) {
      const Eigen::AngleAxisd turn(s.orientation.conjugate() * r.orientation);
      e.head<3>() = (s.centre - r.centre) / size;
      e.tail<3>() = 0.5 * turn.angle() * turn.axis();  // a face centre moves by angle x size/2
    }
    for (int i = 0; i < 6; ++i) out.push_back(e[i]);
  }
}

// A symmetry-blind face label: which signed body axis points down.
int down_face(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d down = q.conjugate() * Eigen::Vector3d(0, 0, -1);
  int axis;
  down.cwiseAbs().maxCoeff(&axis);
  return 2 * axis + (down[axis] < 0);
}

// First time after which the pose stays within 2 % of `size` and 2 degrees
// of the final pose.
double rest_time(const std::vector<double>& t, const std::vector<Pose>& poses, double size) {
  const Pose& last = poses.back();
  for (std::size_t k = poses.size(); k-- > 0;) {
    if (!poses[k].valid) continue;
    const double moved = (poses[k].centre - last.centre).norm();
    const double turned = poses[k].orientation.angularDistance(last.orientation);
    if (moved > 0.02 * size || turned > 2.0 * M_PI / 180.0) return t[std::min(k + 1, t.size() - 1)];
  }
  return t.front();
}

std::string make_temporary_directory() {
  std::string pattern = (fs::temp_directory_path() / "freestand_calibrate_XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw InputError("cannot create a temporary directory for the calibration runs");
  return pattern;
}

// Scaled coordinate u in [0, 1] <-> parameter value.
double to_value(const CalibrationParameter& p, double u) {
  return p.log_scale ? std::exp(std::log(p.lower) + u * (std::log(p.upper) - std::log(p.lower)))
                     : p.lower + u * (p.upper - p.lower);
}
double to_scaled(const CalibrationParameter& p, double value) {
  return p.log_scale ? (std::log(value) - std::log(p.lower)) / (std::log(p.upper) - std::log(p.lower))
                     : (value - p.lower) / (p.upper - p.lower);
}
// d(value or log value)/du: converts a scaled standard error to SI (or to log).
double scale_span(const CalibrationParameter& p) {
  return p.log_scale ? std::log(p.upper) - std::log(p.lower) : p.upper - p.lower;
}

ParameterEstimate estimate(const CalibrationParameter& p, double value, double standard_error, double quantile) {
  ParameterEstimate e{p, value, standard_error, kNaN, kNaN};
  if (std::isfinite(standard_error)) {
    e.lower95 = p.log_scale ? value * std::exp(-quantile * standard_error) : value - quantile * standard_error;
    e.upper95 = p.log_scale ? value * std::exp(quantile * standard_error) : value + quantile * standard_error;
  }
  return e;
}

double sum_of_squares(const std::vector<double>& r) {
  double s = 0.0;
  for (double x : r) s += x * x;
  return s;
}

}  // namespace

void simulate_each(const std::vector<json>& models, const std::vector<const Recording*>& recordings,
                   const std::string& directory, int jobs,
                   const std::function<void(std::size_t, Recording&&, std::exception_ptr)>& done) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr done_failed;  // the first exception `done` threw (an escaped one would end the process)
  std::mutex done_lock;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < models.size();) {
      const std::string dir = (fs::path(directory) / fmt::format("run_{}", i)).string();
      Recording simulated;
      std::exception_ptr failure;
      std::error_code ignored;
      // A failed run is run once more, from a clean directory: a model's own error (a LIGGGHTS
      // ERROR) fails again, but a run lost to its process (a signal, MPI's start-up, the file
      // system) must not decide a fit or a diagnosis. The second failure is the one passed on.
      for (int attempt = 0; attempt < 2; ++attempt) {
        fs::remove_all(dir, ignored);
        try {
          simulated = simulate_recording(models[i], *recordings[i], dir);
          failure = nullptr;
          break;
        } catch (...) {
          failure = std::current_exception();
        }
      }
      fs::remove_all(dir, ignored);
      try {
        done(i, std::move(simulated), failure);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(done_lock);
        if (!done_failed) done_failed = std::current_exception();
        next = models.size();  // no more runs: their results would go nowhere
      }
    }
  };
  std::vector<std::thread> threads;
  for (int k = 0; k < std::max(1, jobs); ++k) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  if (done_failed) std::rethrow_exception(done_failed);
}

namespace {

// Runs (model, recording) pairs `jobs` at a time; a failed run leaves its exception in `failures`.
std::vector<Recording> simulate_parallel(const std::vector<json>& models, const std::vector<const Recording*>& recordings,
                                         const std::string& directory, int jobs,
                                         std::vector<std::exception_ptr>* failures) {
  std::vector<Recording> out(models.size());
  failures->assign(models.size(), nullptr);
  simulate_each(models, recordings, directory, jobs, [&](std::size_t i, Recording&& simulated, std::exception_ptr f) {
    out[i] = std::move(simulated);
    (*failures)[i] = f;
  });
  return out;
}

// Evaluates parameter points on all recordings: residual vectors per point,
// and per (point, recording) the residual count and sum of squares.
class Evaluator {
 public:
  Evaluator(const json& model, const std::vector<Recording>& recordings, const CalibrationOptions& options,
            std::string directory)
      : recordings_(recordings), options_(options), directory_(std::move(directory)) {
    for (const Recording& r : recordings) {
      kinds_.push_back(classify_recording(r));
      bases_.push_back(recording_scenario(model, r, "table_motion.csv"));
      step_shares_.push_back(step_share(bases_.back()));
    }
  }

  struct Point {
    std::vector<double> residuals;
    std::vector<double> recording_rms;
  };

  std::vector<Point> evaluate(const std::vector<std::vector<double>>& scaled_points) {
    std::vector<json> models;
    std::vector<const Recording*> runs;
    for (const auto& u : scaled_points) {
      std::vector<double> values;
      for (std::size_t i = 0; i < u.size(); ++i) values.push_back(to_value(options_.parameters[i], u[i]));
      for (std::size_t r = 0; r < recordings_.size(); ++r) {
        models.push_back(bases_[r]);
        apply_parameters(models.back(), options_.parameters, values);
        keep_step_share(models.back(), step_shares_[r]);  // a stiffer point is not refused at the model's step
        runs.push_back(&recordings_[r]);
      }
    }
    const std::string batch = (fs::path(directory_) / fmt::format("batch_{}", batches_++)).string();
    std::vector<std::exception_ptr> failures;
    const std::vector<Recording> simulated = simulate_parallel(models, runs, batch, options_.jobs, &failures);
    std::vector<Point> points(scaled_points.size());
    for (std::size_t p = 0, j = 0; p < points.size(); ++p) {
      for (std::size_t r = 0; r < recordings_.size(); ++r, ++j) {
        std::vector<double> residuals;
        if (!failures[j]) residuals = calibration_residuals(kinds_[r], recordings_[r], simulated[j]);
        else residuals = failed_residuals(r), ++failed_runs;
        if (residual_counts_.size() <= r) residual_counts_.push_back(residuals.size()), largest_.push_back(1.0);
        if (!failures[j])
          for (double x : residuals) largest_[r] = std::max(largest_[r], std::abs(x));
        points[p].recording_rms.push_back(std::sqrt(sum_of_squares(residuals) / residuals.size()));
        points[p].residuals.insert(points[p].residuals.end(), residuals.begin(), residuals.end());
      }
    }
    return points;
  }

  RecordingKind kind(std::size_t r) const { return kinds_[r]; }
  std::size_t residual_count(std::size_t r) const { return residual_counts_.at(r); }
  int failed_runs = 0;

 private:
  // A failed run's residuals: as many as recording r's run gave, each far beyond any that ran
  // (the optimiser keeps away). Before any run of r did, there is nothing to compare with.
  std::vector<double> failed_residuals(std::size_t r) const {
    if (r >= residual_counts_.size())
      throw InputError(fmt::format("{}: the simulation with the starting values failed", recordings_[r].path));
    return std::vector<double>(residual_counts_[r], kFailedResidual * largest_[r]);
  }

  const std::vector<Recording>& recordings_;
  const CalibrationOptions& options_;
  std::string directory_;
  std::vector<RecordingKind> kinds_;
  std::vector<json> bases_;
  std::vector<double> step_shares_;  // per recording: the model's step over its critical step (scenario.h)
  std::vector<std::size_t> residual_counts_;
  std::vector<double> largest_;  // per recording: the largest |residual| of a model that ran (at least 1)
  int batches_ = 0;
};

// Residuals per sample (or per impact) of a recording kind: the lag at which
// a residual meets its neighbour in time.
std::size_t residuals_per_sample(RecordingKind kind) {
  return kind == RecordingKind::kRocking ? 2 : kind == RecordingKind::kTrajectory ? 6 : 1;
}

// Residuals of neighbouring samples are correlated when the model misses
// something systematic (a phase drift, a missed bounce): n such residuals
// carry the information of fewer independent ones. For an AR(1) sequence
// with lag-one correlation rho the variance of a mean grows by
// (1 + rho) / (1 - rho); this factor, from the residuals r[first, last) at the
// fit (rho clamped to [0, 0.99]), inflates their share of the covariance.
// White measurement noise gives rho near 0 and no inflation.
double serial_inflation(const std::vector<double>& r, std::size_t first, std::size_t last, std::size_t lag) {
  double products = 0.0, squares = 0.0;
  for (std::size_t k = first; k < last; ++k) {
    squares += r[k] * r[k];
    if (k + lag < last) products += r[k] * r[k + lag];
  }
  const double rho = squares > 0 ? std::clamp(products / squares, 0.0, 0.99) : 0.0;
  return (1.0 + rho) / (1.0 - rho);
}

// cov = s^2 (J^T J)^-1 (sum_r f_r J_r^T J_r) (J^T J)^-1, J_r the rows of
// recording r and f_r its serial inflation (the sandwich form of a
// least-squares covariance with residual variance s^2 f_r per recording);
// all f_r = 1 gives the plain Gauss-Newton s^2 (J^T J)^-1. Pseudo-inverse:
// a parameter the data do not feel makes `rank` < columns.
Eigen::MatrixXd sandwich_covariance(const Eigen::MatrixXd& J, const std::vector<double>& inflation,
                                    const Evaluator& evaluator, double variance, long* rank) {
  const Eigen::MatrixXd normal = J.transpose() * J;
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  for (std::size_t r = 0, first = 0; r < inflation.size(); first += evaluator.residual_count(r++)) {
    const auto rows = J.middleRows(first, evaluator.residual_count(r));
    meat += inflation[r] * rows.transpose() * rows;
  }
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> decomposition(normal);
  *rank = decomposition.rank();
  const Eigen::MatrixXd inverse = decomposition.pseudoInverse();
  return variance * inverse * meat * inverse;
}

nlopt::algorithm nlopt_algorithm(const std::string& name) {
  if (name == "bobyqa") return nlopt::LN_BOBYQA;
  if (name == "sbplx") return nlopt::LN_SBPLX;
  if (name == "neldermead") return nlopt::LN_NELDERMEAD;
  throw InputError(fmt::format("calibration: unknown algorithm '{}' (lm, bobyqa, sbplx, neldermead)", name));
}

// Two-sided 97.5 % quantile of Student's t with `dof` degrees of freedom.
double t_quantile_975(int dof) {
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228};
  if (dof < 1) return kNaN;
  return dof <= 10 ? table[dof - 1] : dof <= 30 ? 2.042 + (2.228 - 2.042) * (30 - dof) / 20.0 : 1.96;
}


// The evaluations of one fit: every point evaluated (by the optimiser or for
// a Jacobian) counts against the budget, goes to the progress callback, and
// becomes the best point when it lowers the objective.
class Search {
 public:
  Search(Evaluator& evaluator, const CalibrationOptions& options) : evaluator_(evaluator), options_(options) {}

  std::vector<Evaluator::Point> evaluate(const std::vector<std::vector<double>>& points) {
    std::vector<Evaluator::Point> evaluated = evaluator_.evaluate(points);
    for (std::size_t p = 0; p < points.size(); ++p) {
      const double ssr = sum_of_squares(evaluated[p].residuals);
      if (evaluations++ == 0) start = evaluated[p];
      if (ssr < best_objective) best_objective = ssr, best = evaluated[p], best_u = points[p];
      if (options_.progress) options_.progress(evaluations, ssr);
    }
    return evaluated;
  }

  // One point; the last one is remembered (Levenberg-Marquardt asks for its
  // start again after the caller evaluated it to learn the residual count).
  const Evaluator::Point& evaluate(const std::vector<double>& u) {
    if (u != last_u_) last_ = evaluate(std::vector<std::vector<double>>{u}).front(), last_u_ = u;
    return last_;
  }

  // d residuals / d scaled parameters by central differences, step
  // kJacobianStep, the stencil clamped to [0, 1] (one-sided at a bound): 2 evaluations per parameter,
  // simulated together. The last one is remembered: the covariance at the
  // point where Levenberg-Marquardt stopped reuses it.
  const Eigen::MatrixXd& jacobian(const std::vector<double>& u) {
    if (u == jacobian_u_) return jacobian_;
    std::vector<std::vector<double>> stencil;
    for (std::size_t i = 0; i < u.size(); ++i)
      for (int sign : {1, -1}) {
        stencil.push_back(u);
        stencil.back()[i] = std::clamp(u[i] + sign * kJacobianStep, 0.0, 1.0);
      }
    const std::vector<Evaluator::Point> evaluated = evaluate(stencil);
    const std::size_t rows = evaluated.front().residuals.size();
    jacobian_.resize(rows, u.size());
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double span = stencil[2 * i][i] - stencil[2 * i + 1][i];
      for (std::size_t k = 0; k < rows; ++k)
        jacobian_(k, i) = (evaluated[2 * i].residuals[k] - evaluated[2 * i + 1].residuals[k]) / span;
    }
    jacobian_u_ = u;
    return jacobian_;
  }

  // Evaluations one Jacobian costs.
  int jacobian_cost() const { return 2 * static_cast<int>(options_.parameters.size()); }

  int evaluations = 0;
  Evaluator::Point start, best;
  double best_objective = std::numeric_limits<double>::infinity();
  std::vector<double> best_u;

  // 2 % of each scaled range: large enough to step over the event noise of
  // the residuals (impacts resolved at the time step).
  static constexpr double kJacobianStep = 0.02;

 private:
  Evaluator& evaluator_;
  const CalibrationOptions& options_;
  std::vector<double> last_u_, jacobian_u_;
  Evaluator::Point last_;
  Eigen::MatrixXd jacobian_;
};

// NLopt's derivative-free minimisers on the sum of squares.
void minimise_derivative_free(Search& search, const std::vector<double>& u0, const CalibrationOptions& options) {
  auto objective = [&](const std::vector<double>& u) { return sum_of_squares(search.evaluate(u).residuals); };
  const std::size_t n = u0.size();
  nlopt::opt opt(nlopt_algorithm(options.algorithm), n);
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_min_objective(
      [](const std::vector<double>& u, std::vector<double>&, void* data) {
        return (*static_cast<decltype(objective)*>(data))(u);
      },
      &objective);
  opt.set_xtol_abs(options.tolerance);
  // A trust region that shrank along a narrow curved valley (stiffness
  // against restitution in free rocking) stops short of the minimum:
  // restart from the best point with a fresh region while evaluations remain
  // and a restart still improves the objective.
  double step = 0.15, previous = 0.0;  // first a seventh of each scaled range: a move that events can feel
  std::vector<double> u = u0;
  do {
    previous = search.best_objective;
    opt.set_maxeval(options.max_evaluations - search.evaluations);
    opt.set_initial_step(step);
    double minimum = 0.0;
    try {
      opt.optimize(u, minimum);
    } catch (const nlopt::roundoff_limited&) {  // converged as far as the objective resolves: keep the best
    }
    u = search.best_u;
    step = 0.05;
  } while (search.evaluations < options.max_evaluations && search.best_objective < previous);
}

// The residual vector at P(x), P the projection onto the box [0, 1]^n, for
// Eigen's Levenberg-Marquardt (which knows no bounds; the caller projects
// each accepted point back into the box). Its Jacobian is the
// finite-difference one at P(x), with the column of a parameter at a bound
// that the gradient pushes outward set to zero: that bound is active, and
// the step leaves the parameter on it. Refuses (returns -1, ending the
// minimisation) an evaluation that would exceed the budget.
class ProjectedResiduals {
 public:
  ProjectedResiduals(Search& search, int budget, Eigen::Index count)
      : search_(search), budget_(budget), count_(count) {}
  Eigen::Index values() const { return count_; }

  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& residuals) const {
    if (search_.evaluations + 1 > budget_) return -1;
    residuals = as_vector(search_.evaluate(project(x)).residuals);
    return 0;
  }

  // Returns the evaluations spent (Eigen adds them to its count).
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& jacobian) const {
    if (search_.evaluations + search_.jacobian_cost() > budget_) return -1;
    const std::vector<double> u = project(x);
    jacobian = search_.jacobian(u);
    const Eigen::VectorXd gradient = jacobian.transpose() * as_vector(search_.evaluate(u).residuals);
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if ((u[i] <= 0.0 && gradient[i] > 0.0) || (u[i] >= 1.0 && gradient[i] < 0.0)) jacobian.col(i).setZero();
    return search_.jacobian_cost();
  }

  static std::vector<double> project(const Eigen::VectorXd& x) {
    std::vector<double> u(x.size());
    for (Eigen::Index i = 0; i < x.size(); ++i) u[i] = std::clamp(x[i], 0.0, 1.0);
    return u;
  }

 private:
  static Eigen::VectorXd as_vector(const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  Search& search_;
  int budget_;
  Eigen::Index count_;
};

// Levenberg-Marquardt on the residual vector (docs/calibration.md): Eigen's
// port of MINPACK's lmder with the parallel finite-difference Jacobian,
// each accepted point projected into the box (a projected Levenberg-
// Marquardt iteration).
void minimise_levenberg_marquardt(Search& search, const std::vector<double>& u0, const CalibrationOptions& options) {
  const Eigen::Index count = static_cast<Eigen::Index>(search.evaluate(u0).residuals.size());
  ProjectedResiduals residuals(search, options.max_evaluations, count);
  Eigen::LevenbergMarquardt<ProjectedResiduals> lm(residuals);
  lm.parameters.maxfev = options.max_evaluations;
  lm.parameters.factor = kLevenbergMarquardtFactor;
  lm.parameters.xtol = options.tolerance;
  lm.parameters.ftol = kLevenbergMarquardtFtol;
  lm.useExternalScaling = true;
  lm.diag = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(u0.size()));
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(u0.data(), static_cast<Eigen::Index>(u0.size()));
  Eigen::LevenbergMarquardtSpace::Status status = lm.minimizeInit(x);
  while (status == Eigen::LevenbergMarquardtSpace::NotStarted || status == Eigen::LevenbergMarquardtSpace::Running) {
    status = lm.minimizeOneStep(x);
    const std::vector<double> u = ProjectedResiduals::project(x);
    x = Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
  }
}

}  // namespace

CalibrationParameter parse_calibration_parameter(const std::string& spec) {
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const std::size_t colon = spec.find(':', start);
    parts.push_back(spec.substr(start, colon == std::string::npos ? colon : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  const auto known = std::find_if(std::begin(kKnownParameters), std::end(kKnownParameters),
                                  [&](const CalibrationParameter& p) { return p.name == parts[0]; });
  if (known == std::end(kKnownParameters))
    throw InputError(fmt::format("--fit '{}': unknown parameter '{}' (stiffness, restitution, mu, mu_s, mu_k, "
                                 "friction_decay, table_height)", spec, parts[0]));
  CalibrationParameter p = *known;
  if (parts.size() == 2 || parts.size() > 4)
    throw InputError(fmt::format("--fit '{}': expected NAME, NAME:LOWER:UPPER or NAME:LOWER:UPPER:START", spec));
  try {
    if (parts.size() >= 3) p.lower = std::stod(parts[1]), p.upper = std::stod(parts[2]);
    p.start = parts.size() == 4 ? std::stod(parts[3]) : p.log_scale ? std::sqrt(p.lower * p.upper)
                                                                    : parts.size() >= 3 ? 0.5 * (p.lower + p.upper)
                                                                                        : p.start;
  } catch (const std::exception&) {
    throw InputError(fmt::format("--fit '{}': bounds and start must be numbers", spec));
  }
  if (!(p.lower < p.upper) || (p.log_scale && !(p.lower > 0)) || !(p.start >= p.lower && p.start <= p.upper))
    throw InputError(fmt::format("--fit '{}': need LOWER < UPPER (> 0 for {}) and START within them", spec, p.name));
  return p;
}

void apply_parameters(json& document, const std::vector<CalibrationParameter>& parameters,
                      const std::vector<double>& values) {
  json* interfaces = document.contains("interfaces") && !document["interfaces"].empty() ? &document["interfaces"]
                                                                                         : nullptr;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const std::string& name = parameters[i].name;
    const double value = values[i];
    if (name == "table_height") {
      document["table_height"] = value;
    } else if (name == "stiffness") {
      document["contact"]["stiffness"] = value;
      if (interfaces) for (json& f : *interfaces) f.erase("contact_stiffness");
    } else if (!interfaces) {
      if (name == "mu_s" || name == "mu_k")
        throw InputError(fmt::format("calibration: {} is set on interfaces, and the scenario has none "
                                     "(fit mu, or state the interfaces)", name));
      document["contact"][name] = value;
    } else {
      for (json& f : *interfaces) {
        if ((name == "mu_s" || name == "mu_k") && f.contains("mu")) {
          f["mu_s"] = f["mu_k"] = f["mu"];
          f.erase("mu");
        }
        if (name == "mu") f.erase("mu_s"), f.erase("mu_k");
        f[name] = value;
      }
    }
  }
  if (interfaces)
    for (json& f : *interfaces)
      if (f.contains("mu_s") && f.contains("mu_k") && f["mu_k"].get<double>() > f["mu_s"].get<double>())
        f["mu_k"] = f["mu_s"];
}

const char* kind_name(RecordingKind kind) {
  switch (kind) {
    case RecordingKind::kRocking: return "free rocking";
    case RecordingKind::kHistory: return "histories";
    case RecordingKind::kTrajectory: return "launched";
  }
  return "";
}

RecordingKind classify_recording(const Recording& r) {
  for (char axis : {'x', 'y', 'z'})
    if (r.table_channel('a', axis)) return RecordingKind::kHistory;
  for (const json& body : r.nominal.at("bodies"))
    for (const char* key : {"velocity", "omega"})
      if (body.contains(key))
        for (const json& v : body[key])
          if (v.get<double>() != 0.0) {
            if (!has_pose(r, body.at("name").get<std::string>()))
              throw InputError(fmt::format("{}: body '{}' is launched (initial {}) but the recording has no pose "
                                           "columns to compare its trajectory with", r.path,
                                           body.at("name").get<std::string>(), key));
            return RecordingKind::kTrajectory;
          }
  // Released at rest on a fixed table: free rocking if it rocks (20 mrad, the
  // history threshold), else (dropped face-on, or at rest) its histories.
  for (const std::string& body : r.body_names())
    if (peak_abs(r.body_channel(body, rocking_channel(r, body))) >= 2e-2) return RecordingKind::kRocking;
  return RecordingKind::kHistory;
}

json recording_scenario(const json& model, const Recording& recording, const std::string& table_file) {
  json doc = model;
  doc.erase("table_motion");
  doc.erase("duration");
  for (const char* key : kNominalModelKeys)
    if (recording.nominal.contains(key)) doc[key] = recording.nominal[key];
  const double length = recording.time.back() - recording.time.front();
  doc["simulation"]["duration"] = length;
  doc["simulation"]["output_rate"] = (recording.time.size() - 1) / length;
  for (char axis : {'x', 'y', 'z'})
    if (recording.table_channel('a', axis))
      doc["table_motion"][std::string(1, axis)] = {
          {"record", table_file}, {"format", "csv"}, {"column", std::string("a") + axis}, {"units", "m/s^2"}};
  return doc;
}

Recording run_scenario_document(const json& document, const std::string& directory) {
  fs::create_directories(directory);
  Scenario scenario;
  scenario.path = (fs::path(directory) / "scenario.json").string();
  scenario.document = document;
  const RunFiles files;
  const GeneratedRun run = generate_run(scenario, files);
  write_file_atomically((fs::path(directory) / files.scenario).string(), document.dump(2) + "\n");
  write_file_atomically((fs::path(directory) / files.scene).string(), run.scene.dump(2) + "\n");
  write_file_atomically((fs::path(directory) / files.script).string(), run.script);
  const LiggghtsOutcome outcome =
      run_liggghts({default_liggghts_executable(), directory, files.script, "log.liggghts", 1}, [](long, long) {});
  if (outcome.status != 0)
    throw InputError(fmt::format("{}: simulation failed: {}", scenario.path, outcome.error));
  return results_as_recording(read_results((fs::path(directory) / files.results).string()));
}

std::string table_acceleration_csv(const Recording& recording) {
  std::string table = "t";
  std::vector<std::vector<double>> columns;
  for (char axis : {'x', 'y', 'z'})
    if (recording.table_channel('a', axis))
      table += std::string(",a") + axis, columns.push_back(replayed_table_acceleration(recording, axis));
  if (columns.empty()) return "";
  table += "\n";
  for (std::size_t k = 0; k < recording.time.size(); ++k) {
    table += fmt::format("{:.17g}", recording.time[k] - recording.time.front());
    for (const auto& c : columns) table += fmt::format(",{:.17g}", c[k]);
    table += "\n";
  }
  return table;
}

Recording simulate_recording(const json& model, const Recording& recording, const std::string& directory) {
  fs::create_directories(directory);
  if (model.contains("table_motion"))
    write_file_atomically((fs::path(directory) / "table_motion.csv").string(), table_acceleration_csv(recording));
  Recording simulated = run_scenario_document(model, directory);
  for (double& t : simulated.time) t += recording.time.front();
  return simulated;
}

std::vector<double> calibration_residuals(RecordingKind kind, const Recording& recorded, const Recording& simulated) {
  std::vector<double> out;
  for (const std::string& body : recorded.body_names()) {
    if (kind == RecordingKind::kRocking) rocking_residuals(recorded, simulated, body, out);
    else if (kind == RecordingKind::kHistory) history_residuals(recorded, simulated, body, out);
    else if (has_pose(recorded, body)) trajectory_residuals(recorded, simulated, body, out);
  }
  return out;
}

double body_size(const Recording& r, const std::string& body) {
  json scene = json::object();
  for (const char* key : {"bodies", "interfaces", "gravity"})
    if (r.nominal.contains(key)) scene[key] = r.nominal[key];
  for (const BodySpec& b : parse_scene(scene, r.path + " (nominal)").bodies)
    if (b.name == body) return std::cbrt(b.geometry.volume());
  throw InputError(fmt::format("{}: no body '{}' in the nominal", r.path, body));
}

TrajectoryErrors trajectory_errors(const Recording& recorded, const Recording& simulated, const std::string& body,
                                   double size) {
  TrajectoryErrors e;
  std::vector<Pose> rec, sim;
  int count = 0;
  for (std::size_t k = 0; k < recorded.time.size(); ++k) {
    rec.push_back(pose_at(recorded, body, k));
    sim.push_back(pose_at_time(simulated, body, recorded.time[k]));
    if (!rec.back().valid || !sim.back().valid) continue;
    e.mean_position += (sim.back().centre - rec.back().centre).norm() / size;
    ++count;
  }
  e.mean_position /= std::max(count, 1);
  std::size_t last = rec.size() - 1;
  while (last > 0 && !(rec[last].valid && sim[last].valid)) --last;
  e.final_position = (sim[last].centre - rec[last].centre).norm() / size;
  e.final_rotation = sim[last].orientation.angularDistance(rec[last].orientation);
  e.same_rest_face = down_face(sim[last].orientation) == down_face(rec[last].orientation);
  e.rest_time_recorded = rest_time(recorded.time, rec, size);
  e.rest_time_simulated = rest_time(recorded.time, sim, size);
  return e;
}

std::vector<Recording> simulate_recordings(const std::vector<json>& models, const std::vector<const Recording*>& recordings,
                                           const std::string& directory, int jobs,
                                           std::vector<std::exception_ptr>* failures) {
  std::vector<std::exception_ptr> own;
  std::vector<Recording> out = simulate_parallel(models, recordings, directory, jobs, failures ? failures : &own);
  for (const std::exception_ptr& f : own) if (f) std::rethrow_exception(f);
  return out;
}

CalibrationResult calibrate(const json& model, const std::vector<Recording>& recordings,
                            const CalibrationOptions& options) {
  const std::vector<CalibrationParameter>& params = options.parameters;
  if (params.empty()) throw InputError("calibration: no parameters to fit");
  if (recordings.empty()) throw InputError("calibration: no recordings");
  const bool own_directory = options.work_directory.empty();
  const std::string directory = own_directory ? make_temporary_directory() : options.work_directory;
  Evaluator evaluator(model, recordings, options, directory);
  Search search(evaluator, options);
  const std::size_t n = params.size();

  std::vector<double> u0;
  for (const CalibrationParameter& p : params) u0.push_back(to_scaled(p, p.start));
  if (options.algorithm == "lm") minimise_levenberg_marquardt(search, u0, options);
  else minimise_derivative_free(search, u0, options);
  // The fit is the best point of the search; the Jacobian stencil around it
  // does not move it (the covariance needs the residuals where J was taken).
  const Evaluator::Point best = search.best;
  const std::vector<double> best_u = search.best_u;
  CalibrationResult result;
  result.objective_start = sum_of_squares(search.start.residuals);
  result.objective = sum_of_squares(best.residuals);
  result.residual_count = static_cast<int>(best.residuals.size());
  for (std::size_t r = 0; r < recordings.size(); ++r)
    result.recordings.push_back(
        {recordings[r].path, evaluator.kind(r), search.start.recording_rms[r], best.recording_rms[r]});

  // Gauss-Newton covariance in the scaled coordinates, inflated for residuals
  // correlated in time (serial_inflation).
  std::vector<double> standard_error(n, kNaN);
  const int dof = result.residual_count - static_cast<int>(n);
  if (options.uncertainty && dof > 0) {
    const Eigen::MatrixXd J = search.jacobian(best_u);
    std::vector<double> inflation;
    for (std::size_t r = 0, first = 0; r < recordings.size(); first += evaluator.residual_count(r++)) {
      inflation.push_back(serial_inflation(best.residuals, first, first + evaluator.residual_count(r),
                                           residuals_per_sample(evaluator.kind(r))));
      result.recordings[r].variance_inflation = inflation.back();
    }
    long rank = 0;
    const Eigen::MatrixXd covariance = sandwich_covariance(J, inflation, evaluator, result.objective / dof, &rank);
    const Eigen::VectorXd d = covariance.diagonal().cwiseSqrt();
    result.correlation = covariance.cwiseQuotient(d * d.transpose());
    for (std::size_t i = 0; i < n; ++i)
      standard_error[i] = rank == static_cast<long>(n) ? d[i] * scale_span(params[i])
                                                       : std::numeric_limits<double>::infinity();
  }
  result.evaluations = search.evaluations;
  result.failed_runs = evaluator.failed_runs;
  std::vector<double> values;
  for (std::size_t i = 0; i < n; ++i) {
    values.push_back(to_value(params[i], best_u[i]));
    result.estimates.push_back(estimate(params[i], values.back(), standard_error[i], t_quantile_975(dof)));
  }
  result.model = model;
  // Friction of a model without interfaces: on the first recording's ones
  // (contact has no mu_s, mu_k).
  if (!model.contains("interfaces") && recordings.front().nominal.contains("interfaces"))
    result.model["interfaces"] = recordings.front().nominal["interfaces"];
  apply_parameters(result.model, params, values);
  if (own_directory) {
    std::error_code ignored;
    fs::remove_all(directory, ignored);
  }
  return result;
}

CalibrationResult average_calibrations(const std::vector<CalibrationResult>& fits, const json& model) {
  if (fits.empty()) throw InputError("calibration: nothing to average");
  CalibrationResult average;
  std::vector<CalibrationParameter> params;
  std::vector<double> values;
  const int count = static_cast<int>(fits.size());
  for (std::size_t i = 0; i < fits.front().estimates.size(); ++i) {
    const CalibrationParameter& p = fits.front().estimates[i].parameter;
    double sum = 0.0, squares = 0.0;
    for (const CalibrationResult& f : fits) {
      const double v = p.log_scale ? std::log(f.estimates.at(i).value) : f.estimates.at(i).value;
      sum += v, squares += v * v;
    }
    const double mean = sum / count;
    const double spread = count > 1 ? std::sqrt(std::max(0.0, (squares - count * mean * mean) / (count - 1))) : kNaN;
    const double value = p.log_scale ? std::exp(mean) : mean;
    params.push_back(p);
    values.push_back(value);
    average.estimates.push_back(estimate(p, value, spread / std::sqrt(count), t_quantile_975(count - 1)));
  }
  for (const CalibrationResult& f : fits) {
    average.objective += f.objective, average.objective_start += f.objective_start;
    average.residual_count += f.residual_count, average.evaluations += f.evaluations;
    average.failed_runs += f.failed_runs;
    average.recordings.insert(average.recordings.end(), f.recordings.begin(), f.recordings.end());
  }
  average.model = model;
  apply_parameters(average.model, params, values);
  return average;
}

json calibrated_scenario(const json& model, const std::vector<ParameterEstimate>& fitted, const Recording& recording,
                         const std::string& table_file) {
  json document = recording_scenario(model, recording, table_file);
  std::vector<CalibrationParameter> parameters;
  std::vector<double> values;
  for (const ParameterEstimate& e : fitted) parameters.push_back(e.parameter), values.push_back(e.value);
  const double share = step_share(document);
  apply_parameters(document, parameters, values);
  keep_step_share(document, share);
  return document;
}

}  // namespace freestand
