#ifndef FREESTAND_POST_CALIBRATION_H
#define FREESTAND_POST_CALIBRATION_H

// Calibration of the contact model against recordings (docs/calibration.md):
// each recording is simulated with freestand-lmp under candidate parameter
// values, its recorded channels are reduced to residuals (per-impact features
// for free rocking, histories for a moving table, the pose for a tossed or
// launched body), Levenberg-Marquardt (Eigen) or a derivative-free NLopt
// method minimises the sum of squared residuals, and a
// Gauss-Newton covariance at the optimum, inflated for residuals correlated
// in time, gives the uncertainty.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "recording.h"
#include "results.h"

namespace freestand {

// A fitted parameter: its name, bounds and start (SI), and whether it is
// optimised in log space (stiffness spans decades).
struct CalibrationParameter {
  std::string name;   // stiffness, restitution, mu, mu_s, mu_k, friction_decay, table_height
  double lower = 0.0, upper = 0.0, start = 0.0;
  bool log_scale = false;
};

// "NAME" (default bounds and start), "NAME:LOWER:UPPER" or "NAME:LOWER:UPPER:START".
// Throws InputError for an unknown name or bad bounds.
CalibrationParameter parse_calibration_parameter(const std::string& spec);

// Sets the parameters in a scenario document: stiffness -> contact.stiffness
// (N/m^3 per area; interfaces' contact_stiffness removed), table_height at the
// top, the others on every interface (on `contact` when there is none). mu_k
// is capped at mu_s (kinetic friction cannot exceed static).
void apply_parameters(nlohmann::json& document, const std::vector<CalibrationParameter>& parameters,
                      const std::vector<double>& values);

// How a recording is compared (docs/calibration.md).
enum class RecordingKind {
  kRocking,     // fixed table, released at rest: impact times and amplitudes
  kHistory,     // moving table, or a fixed one without rocking (a face-on drop): histories of
                // the channels that move (slide, uplift, rock, twist)
  kTrajectory,  // fixed table, launched with a velocity: pose (position and rotation)
};
RecordingKind classify_recording(const Recording& recording);
const char* kind_name(RecordingKind kind);

// What a recording's nominal states of the model, and a re-run takes from it
// whatever the model says (recording_scenario, the improved scenario of diagnose).
inline constexpr const char* kNominalModelKeys[] = {"bodies", "interfaces", "gravity", "table_height"};

// The scenario document that re-runs `recording` under `model` (its contact
// and simulation settings): the recording's bodies, interfaces, gravity and
// table_height, its duration and sampling rate, and its table acceleration as
// a record `table_file` (written by simulate_recording).
nlohmann::json recording_scenario(const nlohmann::json& model, const Recording& recording,
                                  const std::string& table_file);

// Runs a scenario document in `directory` (created; relative paths in it
// resolve from there) and returns its results as a recording. Throws
// InputError with the LIGGGHTS error when the run fails.
Recording run_scenario_document(const nlohmann::json& document, const std::string& directory);

// The recording's table acceleration as the CSV a recording_scenario's table
// record reads (t from 0, then ax, ay, az as recorded); empty when it has no
// table channel. Throws InputError where a sample is lost: a replay needs all.
std::string table_acceleration_csv(const Recording& recording);

// Simulates `recording` under `model` in `directory` (created; left in place)
// and returns the results as a recording. Throws InputError with the
// LIGGGHTS error when the run fails.
Recording simulate_recording(const nlohmann::json& model, const Recording& recording,
                             const std::string& directory);

// Residuals of `simulated` against `recorded` (same body names), dimensionless
// (docs/calibration.md); a fixed number for a given recording and kind.
std::vector<double> calibration_residuals(RecordingKind kind, const Recording& recorded,
                                          const Recording& simulated);

// Pose comparison of a launched body (the cube tosses), `size` the length the
// position errors are divided by (the cube's edge).
struct TrajectoryErrors {
  double mean_position = 0.0;   // mean over samples of |x_sim - x_rec| / size
  double final_position = 0.0;  // at the last sample, / size
  double final_rotation = 0.0;  // angle of R_sim^T R_rec at the last sample (rad)
  bool same_rest_face = false;  // the same body axis points down at the end
  double rest_time_recorded = 0.0, rest_time_simulated = 0.0;  // s (definition in docs/calibration.md)
};
// The length position errors are divided by: the cube root of the body's
// volume in the recording's nominal (a cube's edge).
double body_size(const Recording& recording, const std::string& body);

TrajectoryErrors trajectory_errors(const Recording& recorded, const Recording& simulated, const std::string& body,
                                   double size);

struct CalibrationOptions {
  std::vector<CalibrationParameter> parameters;
  int jobs = 2;                  // simulations at a time
  int max_evaluations = 60;      // evaluations by the optimiser (LM: Jacobian points included)
  std::string algorithm = "lm";  // lm (Levenberg-Marquardt), bobyqa, sbplx, neldermead (NLopt LN_*)
  double tolerance = 1e-3;       // stop when a step changes the scaled parameters by less
  bool uncertainty = true;       // Gauss-Newton covariance (2 x parameters more evaluations)
  std::string work_directory;    // run directories go here (empty: a fresh temporary one, removed)
  std::function<void(int evaluation, double objective)> progress;  // after each evaluation
};

struct ParameterEstimate {
  CalibrationParameter parameter;
  double value = 0.0;
  double standard_error = 0.0;   // SI; for log-scale parameters of log(value) (a relative error)
  double lower95 = 0.0, upper95 = 0.0;  // approximate 95 % interval (SI)
};

struct RecordingFit {
  std::string path;
  RecordingKind kind = RecordingKind::kRocking;
  double rms_start = 0.0, rms_fitted = 0.0;  // RMS residual at the start and at the fit
  double variance_inflation = 1.0;  // (1 + rho) / (1 - rho), rho the serial correlation of its residuals at the fit
};

struct CalibrationResult {
  std::vector<ParameterEstimate> estimates;
  std::vector<RecordingFit> recordings;
  double objective_start = 0.0, objective = 0.0;  // sum of squared residuals
  int residual_count = 0;
  int evaluations = 0;
  int failed_runs = 0;           // runs that failed twice; each counted as a far miss of its recording
  Eigen::MatrixXd correlation;   // of the estimates (empty without uncertainty)
  nlohmann::json model;          // the model with the fitted values applied
};

// Fits `options.parameters` of `model` to `recordings`.
CalibrationResult calibrate(const nlohmann::json& model, const std::vector<Recording>& recordings,
                            const CalibrationOptions& options);

// One model from fits of several configurations, as the paper did: per
// parameter the mean of the fitted values (geometric mean for log-scale ones),
// its standard error the spread between configurations over sqrt(count).
CalibrationResult average_calibrations(const std::vector<CalibrationResult>& fits, const nlohmann::json& model);

// Simulates many (model, recording) pairs, `jobs` at a time, each in its own
// subdirectory of `directory` (removed after reading); results in input order.
// A failed run throws, or with `failures` given leaves its exception there
// (and an empty recording in its place).
std::vector<Recording> simulate_recordings(const std::vector<nlohmann::json>& models,
                                           const std::vector<const Recording*>& recordings,
                                           const std::string& directory, int jobs,
                                           std::vector<std::exception_ptr>* failures = nullptr);

// Simulates many (model, recording) pairs, `jobs` at a time, each in its own
// subdirectory of `directory` (removed after reading), and hands each result to
// `done(index, simulated, failure)` as it finishes, on the worker's thread (so
// `done` may do the per-run analysis while the other workers simulate; it must
// not touch shared state without a lock). A failed run is run once more; one that
// fails again passes its exception. An exception thrown by `done` stops the workers
// after their current run and is rethrown here, the first one, once all have joined.
void simulate_each(const std::vector<nlohmann::json>& models, const std::vector<const Recording*>& recordings,
                   const std::string& directory, int jobs,
                   const std::function<void(std::size_t, Recording&&, std::exception_ptr)>& done);

// The scenario that predicts `recording` with a calibrated model: the
// recording's scenario (recording_scenario) with the `fitted` values set on top
// (apply_parameters), as the fit simulated it. The nominal's interface mu and
// table_height would otherwise override the values the calibrated model holds
// in `contact` and at its top level.
nlohmann::json calibrated_scenario(const nlohmann::json& model, const std::vector<ParameterEstimate>& fitted,
                                   const Recording& recording, const std::string& table_file);

}  // namespace freestand

#endif
