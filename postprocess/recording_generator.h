#ifndef FREESTAND_POST_RECORDING_GENERATOR_H
#define FREESTAND_POST_RECORDING_GENERATOR_H

// Recordings with one concealed effect, to prove `freestand diagnose`
// (docs/diagnose-cases.md). A case is a nominal model (a scenario), a table
// command (a ground-motion window) and at most one effect from the catalogue.
// The truth is simulated with the effect and with more fidelity than the
// model (finer contact-node grid, smaller time step), driven by what a servo
// table does with the command; it is then measured the way a lab does (gain
// error, causal anti-alias filter, sampling, Gaussian noise). The recording's
// nominal.json states only the nominal model; what was concealed, and proof
// that it is concealed, go into a separate answer key.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "recording.h"

namespace freestand {

// The sensors and the digitiser (applied in this order: gain, filter,
// sampling, noise).
struct SensorModel {
  double angle = 5e-4;         // noise sd on rock_x, rock_y, twist (rad)
  double length = 5e-4;        // noise sd on slide_x, slide_y, uplift, table_dx (m)
  double acceleration = 0.02;  // noise sd on table_ax (m/s^2)
  double gain_sd = 0.01;       // sd of each channel's gain error (relative)
  double lowpass_hz = 0.0;     // anti-alias cutoff; 0: sampling_hz / 4
  int lowpass_order = 4;       // causal Butterworth order
  int oversample = 5;          // truth samples per recorded sample, before the filter
};

// How the table follows its command: a causal second-order Butterworth servo
// response, a gain error, and hydraulic noise entering with the command.
struct TableTracking {
  double bandwidth_hz = 20.0;  // servo -3 dB frequency
  double gain_sd = 0.02;       // sd of the table's gain error (relative)
  double noise = 0.05;         // sd of white acceleration noise added to the command at 1 kHz (m/s^2)
};

// How much finer the truth is than the model.
struct TruthFidelity {
  nlohmann::json nodes = {{"layout", "surface"}, {"per_edge", 2}};  // every body's contact nodes
  int time_step_divisor = 4;   // truth time step = model time step / this
};

// Small random initial velocities of every body (sd), for the scatter runs.
struct Perturbation {
  int runs = 4;                // perturbed runs that measure the scatter (>= 2)
  double velocity = 1e-4;      // m/s, horizontal
  double omega = 1e-3;         // rad/s, each axis
};

// When an effect counts as concealed, E the global RMS error against the
// nominal model's prediction (docs/diagnose-cases.md, "The concealment criterion").
enum class Concealment {
  kPairedChange,   // |E(with) - E(same draw without)| <= sd of E over the perturbed draws
  kWithinScatter,  // E(with) <= largest E of the draws without it (same, perturbed) + that sd
};
// "paired_change" or "within_scatter"; InputError naming `where` otherwise.
Concealment concealment_rule(const std::string& name, const std::string& where);

// The concealed effect: a catalogue name (effect_catalogue()) or "none".
// magnitude < 0: the largest concealed magnitude is searched from the
// catalogue's start value by halving (or doubling up to its max).
struct ConcealedEffect {
  std::string name = "none";
  double magnitude = -1.0;
  std::string body;            // target body (default: the top body)
  Concealment rule = Concealment::kPairedChange;  // what "concealed" means
};

struct CaseSpec {
  std::string name;            // file stem of the recording
  std::string scenario;        // the nominal model: bodies, interfaces, contact, simulation.time_step
  nlohmann::json motion;       // table command along x: record, units, format, column, scale, skip, duration
  nlohmann::json motion_y;     // table command along y, the same keys and duration (null: none)
  ConcealedEffect effect;
  double sampling_hz = 200.0;
  SensorModel sensors;
  TableTracking table;
  TruthFidelity truth;
  Perturbation perturbation;
  unsigned seed = 1;
};

// One catalogue entry (docs/diagnose-cases.md says what each does to the truth).
struct EffectInfo {
  std::string name;
  std::string unit;            // of the magnitude
  double start = 0.0;          // first magnitude tried by the search
  double max = 0.0;            // the search goes up (doubling) to this when start is concealed
  std::string what;            // one line
};
const std::vector<EffectInfo>& effect_catalogue();

// Cases of a case file: {"defaults": {...}, "cases": [{...}, ...]}, each case
// the defaults with its own fields merged over them. Relative paths resolve
// from the file's folder. InputError names the file, case and field at fault.
std::vector<CaseSpec> read_case_file(const std::string& path);
CaseSpec parse_case(const nlohmann::json& fields, const std::string& folder, const std::string& where);

struct GeneratedCase {
  Recording recording;         // what the lab recorded; nominal = the nominal model only
  Recording model;             // the nominal model's prediction (the reference of the criterion)
  nlohmann::json answer;       // the effect, its magnitude and the concealment numbers
};

// Simulates and measures one case. Runs go to `cache` (one directory per
// distinct run document, reused when it holds results, so cases on the same
// base share their model and scatter runs), `jobs` at a time. Throws
// InputError when no tried magnitude is concealed or a given one is not.
GeneratedCase generate_case(const CaseSpec& spec, const std::string& cache, int jobs);

// InputError unless the two folders differ and neither holds the other, so
// an answer key never sits beside or below the recordings.
void check_folders_apart(const std::string& recordings, const std::string& answers);

// Writes RECORDINGS/NAME.csv + NAME.nominal.json, ANSWERS/NAME.answer.json and
// ANSWERS/NAME.model.csv (+ nominal), after check_folders_apart.
void write_case(const GeneratedCase& generated, const std::string& name, const std::string& recordings,
                const std::string& answers);

// The concealment measure: RMS over every body channel and sample of
// recording minus reference (reference interpolated at the recording's
// times), angles times the body's bounding radius about its centre of mass,
// so every term is a displacement (m). Lost samples are skipped.
double global_rms_error(const Recording& recording, const Recording& reference);

// The effect's size against the sensor noise: sqrt(sum over every body
// channel and sample of ((with - without) / the channel's noise sd)^2), with
// `without` interpolated at `with`'s times. It is the deflection of the ideal
// (Neyman-Pearson) detector that knows the effect's noise-free trace exactly,
// in the white Gaussian noise the sensors add after their filter: no method
// that must also estimate the trace, or see it through chaos, does better.
double effect_deflection(const Recording& with, const Recording& without, const SensorModel& sensors);

// y filtered by a causal Butterworth low-pass of `order` at `cutoff_hz`,
// y sampled every `dt` s, starting from rest at y[0].
std::vector<double> butterworth_lowpass(const std::vector<double>& y, double dt, double cutoff_hz, int order);

}  // namespace freestand

#endif
