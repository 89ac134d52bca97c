#ifndef FREESTAND_POST_DIAGNOSIS_H
#define FREESTAND_POST_DIAGNOSIS_H

// `freestand diagnose` (docs/diagnose.md): where and why a simulation and a
// recording differ. Measurement issues first (delay, gain, bias, drift per
// channel); then event features of the recording against a nominal
// simulation and a small ensemble that measures their scatter (chaos plus
// noise); then a catalogue of candidate physics, each a real scenario option,
// fitted by a 1-D profile, the best accepted only when significant after
// counting every candidate tried and when the improvement holds on held-out
// data; repeated until nothing significant is left.

#include <nlohmann/json.hpp>

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "motion_analysis.h"
#include "recording.h"
#include "table_tracking.h"

namespace freestand::diagnosis {

// One entry of the catalogue (docs/diagnose.md, table of candidates).
struct CatalogueEntry {
  std::string name;          // "restitution", "com_offset_x", ...
  std::string scope;         // "interface", "body" or "table": one candidate per interface, per body, or one
  std::string fields;        // the scenario fields that represent the parameter
  std::string description;   // plain words, {} = the interface or body
  std::vector<std::string> similar;  // entries with much the same signature in the event features (symmetric)
};
const std::vector<CatalogueEntry>& catalogue();
// Catalogue entry `name`, or nullptr (the sensor candidates are not physics).
const CatalogueEntry* catalogue_entry(const std::string& name);

// A catalogue entry instantiated on one interface or body of a scenario.
struct Candidate {
  std::string name;          // "restitution[table/block]", "com_offset_x[tower]"
  std::string entry;         // catalogue name
  std::string where;         // interface "lower/upper", body name, or "table"
  std::string description;   // plain words
  std::string unit;          // of the parameter
  double lower = 0, upper = 0, nominal = 0;  // range and the value the model has
  bool log_scale = false;
  bool stated = false;       // the nominal states it: a fit is a recalibration, else missing physics
  bool at_boundary = false;  // the nominal value is a bound of the admissible range (LRT boundary correction)
  bool measurement = false;  // a measurement issue fitted by simulation (the replayed table): reported as
                             // such and never written into the improved scenario
  double prior_sd = 0;       // > 0: a known calibration N(nominal, prior_sd^2); its -2 log adds to chi2
  std::function<void(nlohmann::json&, double)> apply;  // sets the value in a scenario document
  // Measurement candidates (sensor delay, gain) change the recording, not the model:
  std::function<void(Recording&, double)> correct;  // undoes the issue in recording number `recording`
  std::size_t recording = 0;
  // An accepted effect stays a candidate, re-fitted around its value with profile steps
  // scaled by 0.1: a new candidate must beat a better value of the old one.
  int effect = -1;           // index in Diagnosis::effects, or -1
  double profile_scale = 1;  // the quick profile's steps (0.01 x 4^k of the range) times this
  std::vector<double> ladder;  // when not empty, the quick profile's offsets from the nominal instead
                               // (scaled units, signed); cleared once the candidate is accepted
  // A second parameter of the law that no profile fits (velocity weakening's decay): the settle
  // runs the value's ensemble points at each of `shapes`; another shape replaces it only when it
  // fits better beyond the Monte Carlo bound (Diagnoser::settled_point), else fits alike.
  std::string shape_name, shape_unit;  // "friction_decay", "s/m"; empty: the entry has none
  double shape = 0;                    // its value in `apply`
  std::vector<double> shapes;          // the values the settle tries (shape among them)
  std::function<void(nlohmann::json&, double, double)> apply_shaped;  // sets (value, shape) in a document
};
// A candidate's value v and its scaled position u in [0, 1] over its range (in ln v on a log
// scale), and what one scaled unit is in the value's units (in ln of it on a log scale).
double to_value(const Candidate& c, double u);
double to_scaled(const Candidate& c, double v);
double scaled_unit(const Candidate& c);
// v lies within scaled_tolerance of an end of c's range: a fit there found no minimum inside it.
bool at_range_end(const Candidate& c, double value, double scaled_tolerance);
// c with its second parameter at `shape` (apply set from apply_shaped).
Candidate reshaped(const Candidate& c, double shape);
// a and b are of similar signature: b's entry is listed as similar to a's, and two body
// candidates are on the same body.
bool of_similar_signature(const Candidate& a, const Candidate& b);

// Candidates of every available catalogue entry for a run document (bodies,
// interfaces, contact, table_motion as recording_scenario() makes it) whose
// needed channels `recording` has; the reasons others were left out go to `skipped`.
// With table_gain_sd 0 the replayed table acceleration is trusted exactly: no table_gain.
std::vector<Candidate> candidates_for(const nlohmann::json& document, const Recording& recording,
                                      double table_gain_sd, std::vector<std::string>* skipped);

// An event feature of one body (docs/diagnose.md lists them).
struct FeatureValue {
  double value = 0;   // SI
  double time = 0;    // s, when it happened (held-out split, localisation)
  double floor = 0;   // s.d. it cannot be measured better than (noise, sampling)
  std::string mode;   // rock, slide, twist, uplift
  bool event = false;   // marks an event (its time): whether it happens at all is evidence of its own
  bool present = true;  // false: an event simulations have that the recording lacks (value unused)
  bool splits = true;   // its time counts toward the held-out split; false for one read from the whole record at once
};
using Features = std::map<std::string, FeatureValue>;  // "block.rock_x.impact3.amplitude" -> value
// The only key of a failed simulation's features: a model that does not run fits nothing (its
// events are not merely absent).
inline const std::string kFailedSimulation = "simulation_failed";
// The slip events of every body of a recording (body -> its slips in time order): what the
// slips of a simulation, or of the recording corrected, are matched to.
using SlipReference = std::map<std::string, std::vector<analysis::SlipEvent>>;
SlipReference slip_reference(const Recording& recording, const nlohmann::json& analysis_nominal);

// For each of `slips`, the index of the `reference` slip it is the same event as, or -1.
// Two slips are the same event when they overlap in time; one to one, the pairs with the
// nearest onsets first. Not by their order: a short slip that one side has and the other
// lacks (a pause that splits a slip in two, a slip at the detection threshold) would
// renumber every later one, and their onsets would be compared across different events.
std::vector<int> matched_slips(const std::vector<analysis::SlipEvent>& slips,
                               const std::vector<analysis::SlipEvent>& reference);

// Features of every body of `recording`, analysed with `analysis_nominal`'s
// geometry and noise thresholds (the recording's nominal, for both sides). Slip i names the
// reference's slip i it is matched to (matched_slips); one matched to none is numbered on
// after the reference's, in time order (an event the reference lacks). Without a reference,
// slips are numbered in time order. `gains`: the calibration of the channels, the floor of a
// feature that is a ratio of two (the table carry, the pivot levers). `held_after`: the held-out
// split (s), where a feature read from the whole record (the pivot levers) is read apart on each
// side; infinite: read whole.
struct ChannelGainSd {
  double table = 0;   // relative s.d. of the recorded table acceleration's gain
  double sensor = 0;  // relative s.d. of each recorded body channel's gain
};
Features event_features(const Recording& recording, const nlohmann::json& analysis_nominal,
                        const SlipReference* reference = nullptr, ChannelGainSd gains = {},
                        double held_after = std::numeric_limits<double>::infinity());

// MeasurementIssue::channel of a delay of every body channel (the specimen's clock).
inline const std::string kEveryBody = "*";

// A measurement issue of one channel: recorded ~ gain * simulated(t - delay) + bias + drift t.
// A drift at rest belongs to each simulation it was measured against (added to it where
// significant; reported against the final model); a delay or gain, estimated against the
// nominal run, is accepted only as a candidate that beats every physics candidate on the
// event features.
struct MeasurementIssue {
  std::string channel;        // "block.rock_x"; a body ("block"): all its channels; kEveryBody: every body's
  std::size_t recording = 0;  // index of the recording it was measured on
  double delay = 0, gain = 1, gain_sd = 0, bias = 0, drift = 0;  // s, -, -, channel units, units/s
  double correlation = 0;
  bool delay_suspected = false, gain_suspected = false;  // worth a candidate
  bool delay_significant = false, gain_significant = false, drift_significant = false;  // accepted
  int round = 0;              // the search round that accepted it (0: a drift, against the final model)
  std::string text;           // plain words
};

// One candidate's value in a --hypothesis.
struct StatedValue {
  std::string candidate;      // a candidate's name as the candidate table prints it: "edge_inset[block]"
  double value = 0;           // SI, within the candidate's range
};
// --hypothesis NAME=VALUE[,NAME=VALUE...]: a cause the user suspects (values set together, e.g. the
// restitution of every interface of a stack), tested on the ensemble before the search.
using Hypothesis = std::vector<StatedValue>;

struct Options {
  int jobs = 2;               // simulations at a time
  int ensemble = 6;           // perturbed runs that measure the feature scatter
  double table_gain_sd = 0.02;  // relative s.d. of the recorded table acceleration's gain (accelerometer
                               // calibration, 1-2 %): each ensemble member replays the table with its own gain
  double sensor_gain_sd = 0.01;  // relative s.d. of each recorded body channel's gain (sensor calibration):
                               // each run's channels are read with their own gains
  int profile_points = 6;     // points of each candidate's quick profile (around the nominal)
  int profile_members = 1;    // ensemble members each profile point runs as (chi2 averaged; cost x that)
  double z_threshold = 3;     // |z| that flags a feature as mismatched
  double alpha = 0.01;        // family-wise error rate of the acceptance test (Holm)
  int max_effects = 3;        // iterations of the search
  std::vector<Hypothesis> hypotheses;  // each tested against the model as given at alpha / (2 x their number)
  bool shooting = false;      // multiple shooting: cut single-body recordings at rests (shooting.h)
  std::string work_directory; // run directories (empty: a fresh temporary one, removed)
  std::string improved_table_file = "table_motion.csv";  // the improved scenario's table record (Diagnosis::
                               // improved_table), relative to the improved scenario's folder
  std::function<void(const std::string& stage, long done, long total)> progress;
};

struct Mismatch {             // a feature beyond the threshold (simulated: the ensemble mean)
  std::string feature, body, mode;
  double time = 0, recorded = 0, simulated = 0, z = 0;
};

struct ChannelDivergence {
  std::string channel;
  double time = 0;            // s: first window of the divergence test beyond its threshold; NaN: never
};

struct FittedCandidate {
  Candidate candidate;
  double value = 0, standard_error = 0;  // SI; log-scale: s.e. of the natural log
  double chi2 = 0;            // -2 log L at the value (features of the fit set)
  double delta = 0;           // chi2 of the model before - chi2 here
  double delta_se = 0;        // Monte Carlo s.e. of delta (jackknife over ensemble members; 0: profile only)
  int members = 0;            // ensemble members of each model that chi2 and delta are over (0: only profiled)
  double p_value = 1;         // LRT at delta - 2 delta_se, boundary-corrected
  double delta_bic = 0;       // delta - 2 delta_se - ln(n): > 0 favours the candidate
  double held_out_delta = 0;  // improvement on the held-out features, value fitted without them
  int evaluations = 0;
  std::vector<std::pair<double, double>> profile;  // (value, chi2 + prior) of each profile point, by value
  std::vector<std::pair<double, double>> alike_shapes;  // (shape, value there): the candidate's other shapes whose
                                                        // settled value fits alike on the ensemble (Candidate::shapes)
};

struct Effect {               // an accepted candidate
  FittedCandidate fit;
  std::string verdict;        // "recalibrated", "missing physics" or "measurement"
  bool far_off = false;       // a stated value moved by a factor > 3 (or beyond its stated bound)
  std::vector<FittedCandidate> indistinguishable;  // rivals that fit as well on the ensemble, each at its own
                                                  // fitted value: the recording cannot tell them apart
  std::vector<std::pair<std::string, double>> similar;  // candidates of a similar entry that also helped: profile drop
  int candidates_tried = 0;   // counted in the Holm correction
  int round = 0;              // the search round that accepted it (1 = first)
};

struct HypothesisTest {       // a --hypothesis: the model as given with the stated value, on its own ensemble
  Hypothesis stated;
  FittedCandidate fit;        // at the stated values (one candidate setting them all; no s.e.: nothing fitted),
                              // scored as an accepted effect is
  bool supported = false;     // passes the acceptance test at alpha / (2 x hypotheses): two looks each
  std::string against_improved;  // effects were accepted: it fits "better", "worse" or "alike" than the improved
                                 // model (the rule of similar candidates, docs/diagnose.md step 4); else empty
  double improved_delta = 0, improved_delta_se = 0;  // chi2 of the improved model - chi2 at the hypothesis (> 0:
                                                     // the hypothesis fits better), Monte Carlo s.e.
};

struct HypothesisComparison {  // two --hypothesis met member by member (shared seeds, pooled scatter, all features)
  std::size_t first = 0, second = 0;  // indices in Diagnosis::hypotheses, first < second
  double delta = 0, delta_se = 0;     // chi2 at the first - chi2 at the second (> 0: the second fits better), MC s.e.
  std::string second_fits;            // "better", "worse" or "alike" than the first (the rule of similar candidates)
};

struct FeatureRow {           // one event feature, recorded and simulated
  std::string name, mode;
  double time = 0, recorded = 0, nominal = 0, improved = 0;  // nominal, improved: ensemble means (NaN: absent)
  double z_nominal = 0, z_improved = 0;  // the recording's z against each ensemble (existence and value)
  bool held_out = false;
};

struct NumericsCheck {         // a numerical setting of the model against its finest affordable one (numerics before physics)
  std::string quantity;       // "contact grid" or "time step"
  std::string model;          // the model checked: "as given", or its contacts at the softest profiled stiffness
  std::string reference;      // the finest setting (JSON: the grid's nodes, or the step in s)
  double distance = 0;        // chi2 of the finest setting's run against the model's ensemble (its z, as a recording's)
  double limit = 0;           // the mean of chi2(features): beyond it the model was not converged
  bool adopted = false;       // not converged: the model's setting was refined one step, to `setting`
  std::string setting;        // the setting adopted (JSON); empty when converged
};

struct Diagnosis {
  std::vector<NumericsCheck> numerics_checks;  // contact grid, then time step, in the order run
  std::vector<MeasurementIssue> measurement;
  std::vector<TableTracking> table;            // recorded table against the scenario's command, where it differs
  std::vector<Mismatch> mismatches;            // of the model as given, |z| beyond the threshold, in time order
  std::vector<ChannelDivergence> divergence;
  int feature_count = 0;
  double chi2_nominal = 0, chi2_final = 0;     // -2 log L of the model as given and as improved
  double chi2_noise_limit = 0;                 // 99 % quantile of chi2(feature_count): consistent with noise below
  int closing_members = 0;                     // members chi2_final is read on: M, or 2 M where M read it beyond the limit
  std::vector<std::vector<FittedCandidate>> rounds;  // every candidate's profile fit, per iteration
  std::vector<Effect> effects;
  std::vector<HypothesisTest> hypotheses;     // Options::hypotheses, in their order
  std::vector<HypothesisComparison> hypothesis_pairs;  // every two of them
  std::vector<Mismatch> unexplained;           // still beyond the threshold after the accepted effects
  std::vector<std::string> notes;              // candidates left out and why, held-out choice, ...
  nlohmann::json improved;                     // the scenario with the effects as model options, replaying the
                                               // first recording (its duration, rate and table acceleration)
  std::string improved_table;                  // CSV of that table acceleration, to be written as
                                               // Options::improved_table_file; empty: no table channel
  std::vector<FeatureRow> features;            // every recorded feature against both models
  std::vector<Recording> recorded;             // the recordings, corrected for accepted measurement issues
  std::vector<Recording> simulated_nominal, simulated_final;  // noise-free runs of the model as given and improved
  std::string verdict;                         // plain-language summary
  double z_threshold = 3;                      // Options::z_threshold used
  int simulations = 0;
  int failed_simulations = 0;                  // runs that failed twice: counted as not fitting (not chosen, not accepted)
  std::string first_failure;                   // the first one's error
};

// Diagnoses `recordings` (the last is held out when there are several; with
// one, the later half of its events is) against `scenario` (a model: its
// contact and simulation settings; its bodies and interfaces, when stated,
// must name the recordings' bodies). Throws InputError for bad input.
Diagnosis diagnose(const nlohmann::json& scenario, const std::vector<Recording>& recordings, const Options& options);

// The JSON of --json FILE.
nlohmann::json diagnosis_json(const Diagnosis& diagnosis);

}  // namespace freestand::diagnosis

#endif
