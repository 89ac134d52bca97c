// freestand diagnose [SCENARIO] RECORDING...: locates where a simulation and
// recordings differ, names the physics the model left out, adds it as a model
// option, refits and shows the improvement is real (docs/diagnose.md).

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "atomic_file.h"
#include "commands.h"
#include "diagnosis.h"
#include "diagnosis_report.h"
#include "freestand/input_error.h"
#include "progress.h"
#include "scenario.h"

namespace freestand::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct DiagnoseOptions {
  std::vector<std::string> inputs;  // [SCENARIO] RECORDING...
  std::string output;               // improved scenario
  std::string json_file;            // --json
  std::string report;               // --report (HTML)
  std::vector<std::string> hypotheses;  // --hypothesis NAME=VALUE
  diagnosis::Options options;
};

// A scenario is a .json that is not a recording's sidecar (NAME.nominal.json).
bool is_scenario(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  return fs::path(path).extension() == ".json" && name.find(".nominal.json") == std::string::npos;
}

void print_candidates(const diagnosis::Diagnosis& d) {
  for (std::size_t r = 0; r < d.rounds.size(); ++r) {
    fmt::print("round {}: {:<44} {:>12} {:>10} {:>8} {:>9} {:>9} {:>9}\n", r + 1, "candidate", "value", "delta chi2",
               "MC s.e.", "p", "dBIC", "held-out");
    for (const diagnosis::FittedCandidate& f : d.rounds[r])
      fmt::print("         {:<44} {:>12.4g} {:>10.1f} {:>8.1f} {:>9.2g} {:>9.1f} {:>9}\n", f.candidate.name, f.value,
                 f.delta, f.delta_se, f.p_value, f.delta_bic,
                 std::isfinite(f.held_out_delta) ? fmt::format("{:.1f}", f.held_out_delta) : "n/a");
  }
}

// NAME=VALUE, split at the last '=' (a name has none); the value a finite number.
diagnosis::StatedValue parsed_value(const std::string& text, const std::string& option) {
  const std::size_t eq = text.rfind('=');
  diagnosis::StatedValue v;
  std::size_t used = 0;
  try {
    if (eq != std::string::npos) v.value = std::stod(text.substr(eq + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (eq == std::string::npos || eq == 0 || used == 0 || used != text.size() - eq - 1 || !std::isfinite(v.value))
    throw InputError(fmt::format("diagnose: --hypothesis {}: expected NAME=VALUE[,NAME=VALUE...] with each VALUE a "
                                 "number in SI units, e.g. edge_inset[block]=0.01", option));
  v.candidate = text.substr(0, eq);
  return v;
}

// NAME=VALUE[,NAME=VALUE...]: the values one hypothesis sets together.
diagnosis::Hypothesis parsed_hypothesis(const std::string& text) {
  diagnosis::Hypothesis h;
  std::size_t from = 0;
  for (std::size_t comma = text.find(','); ; comma = text.find(',', from)) {
    h.push_back(parsed_value(text.substr(from, comma - from), text));
    if (comma == std::string::npos) return h;
    from = comma + 1;
  }
}

// The scenario with its table records' paths made absolute: relative ones resolve from the
// scenario's folder, and the improved scenario is written elsewhere.
json portable(json scenario, const std::string& scenario_path) {
  if (!scenario.contains("table_motion")) return scenario;
  for (auto& [axis, motion] : scenario["table_motion"].items())
    if (motion.contains("record") && fs::path(motion["record"].get<std::string>()).is_relative())
      motion["record"] = fs::weakly_canonical(fs::absolute(scenario_path).parent_path() /
                                              motion["record"].get<std::string>()).string();
  return scenario;
}

int diagnose_command(DiagnoseOptions& o) {
  json scenario = json::object();
  std::string scenario_path;
  std::vector<Recording> recordings;
  for (const std::string& input : o.inputs) {
    if (is_scenario(input) && scenario_path.empty() && recordings.empty()) {
      scenario_path = input;
      scenario = portable(read_scenario(input).document, input);  // table records resolve from anywhere
    } else {
      print_warnings(recordings.emplace_back(read_recording(input)));
    }
  }
  if (recordings.empty()) throw InputError("diagnose: no recording given (NAME.csv with NAME.nominal.json, or NAME.h5)");
  for (const std::string& h : o.hypotheses) o.options.hypotheses.push_back(parsed_hypothesis(h));
  const fs::path output = !o.output.empty() ? o.output
                          : (fs::path(scenario_path.empty() ? recordings.front().path : scenario_path).stem().string() +
                             ".diagnosed.json");
  const fs::path table = output.parent_path() / (output.stem().string() + ".table.csv");  // what it replays
  o.options.improved_table_file = table.filename().string();
  fmt::print("freestand diagnose: {} recording{} against {}, {} jobs\n", recordings.size(),
             recordings.size() > 1 ? "s" : "", scenario_path.empty() ? "the recordings' nominal" : scenario_path,
             o.options.jobs);
  std::fflush(stdout);
  std::unique_ptr<ProgressBar> bar;
  std::string stage;
  o.options.progress = [&](const std::string& s, long done, long total) {
    if (s != stage) {
      if (bar) bar->finish();
      bar = std::make_unique<ProgressBar>("  " + s);
      stage = s;
    }
    bar->update(done, total);
  };
  const diagnosis::Diagnosis d = diagnosis::diagnose(scenario, recordings, o.options);
  if (bar) bar->finish();
  fmt::print("\n{}\n", d.verdict);
  print_candidates(d);
  for (const std::string& n : d.notes) fmt::print("  note: {}\n", n);
  if (!d.improved_table.empty()) write_file_atomically(table.string(), d.improved_table);
  write_file_atomically(output.string(), d.improved.dump(2) + "\n");
  fmt::print("  improved scenario: {} ({} simulations){}\n", output.string(), d.simulations,
             d.improved_table.empty() ? "" : ", replaying the table acceleration in " + table.string());
  if (!o.json_file.empty()) write_file_atomically(o.json_file, diagnosis::diagnosis_json(d).dump(2) + "\n");
  if (!o.report.empty()) {
    HtmlReport report("freestand diagnose");
    if (!scenario_path.empty()) report.add_metadata("scenario", scenario_path);
    for (const Recording& r : recordings) report.add_metadata("recording", r.path);
    report.add_metadata("simulations", std::to_string(d.simulations));
    diagnosis::add_diagnosis_sections(report, d);
    report.write(o.report);
    fmt::print("  report: {}\n", o.report);
  }
  return 0;
}

}  // namespace

void add_diagnose_command(CLI::App& app) {
  auto o = std::make_shared<DiagnoseOptions>();
  CLI::App* sub = app.add_subcommand(
      "diagnose",
      "Where and why a simulation and recordings differ (docs/diagnose.md): measurement issues per channel,\n"
      "event features against a nominal run and an ensemble (chaos and noise), a catalogue of candidate physics\n"
      "fitted one by one, the best accepted only when significant after counting every candidate and when it\n"
      "holds on held-out data. Prints a verdict and writes the improved scenario.");
  sub->add_option("inputs", o->inputs, "[SCENARIO.json] RECORDING...: the model (optional) and recordings")
      ->required();
  sub->add_option("-o,--output", o->output, "improved scenario, replaying the first recording (default: SCENARIO or RECORDING stem + .diagnosed.json); its table acceleration is written beside it as STEM.table.csv");
  sub->add_option("--json", o->json_file, "write the diagnosis (effects, recalibrations, measurement issues, ...) as JSON");
  sub->add_option("--report", o->report, "write an HTML report (verdict, before/after overlays, candidates, features)");
  sub->add_option("--jobs", o->options.jobs, "simulations at a time")->capture_default_str()->check(CLI::PositiveNumber);
  sub->add_option("--ensemble", o->options.ensemble,
                  "perturbed runs that measure the feature scatter (twice as many where one ensemble cannot decide a test)")
      ->capture_default_str()
      ->check(CLI::Range(3, 50));  // the jackknife of a chi2 drop needs 3 member pairs
  sub->add_option("--table-gain-sd", o->options.table_gain_sd,
                  "relative s.d. of the recorded table acceleration's gain, drawn per ensemble member")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.2));
  sub->add_option("--sensor-gain-sd", o->options.sensor_gain_sd,
                  "relative s.d. of each recorded body channel's gain (sensor calibration), drawn per run and channel")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.2));
  sub->add_option("--profile-points", o->options.profile_points, "grid points of each candidate's quick profile")
      ->capture_default_str()
      ->check(CLI::Range(2, 16));
  sub->add_option("--profile-members", o->options.profile_members,
                  "ensemble members each profile point runs as, their chi2 averaged: a steadier profile of a chaotic "
                  "model at that many times the profiles' cost")
      ->capture_default_str()
      ->check(CLI::Range(1, 50));
  sub->add_option("--z-threshold", o->options.z_threshold, "|z| that flags a feature as mismatched")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--alpha", o->options.alpha, "family-wise error rate of the acceptance test")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 0.5));
  sub->add_option("--max-effects", o->options.max_effects, "effects searched for at most")
      ->capture_default_str()
      ->check(CLI::Range(0, 10));
  sub->add_option("--hypothesis", o->hypotheses,
                  "NAME=VALUE[,NAME=VALUE...] (repeatable): test a cause you suspect before the search, e.g. "
                  "edge_inset[block]=0.01 (candidate names as the candidate table prints them, values in SI; values "
                  "joined by commas are set together): the model as given with them, on its own ensemble, judged as an "
                  "accepted effect is and compared with the improved model")
      ->allow_extra_args(false);  // one NAME=VALUE per --hypothesis: the recordings that follow stay inputs
  sub->add_flag("--shooting", o->options.shooting,
                "multiple shooting: cut a single-body recording where the body rests before a motion episode and "
                "start each piece from the measured rest state (docs/diagnose.md)");
  sub->callback([o] { guarded([&] { return diagnose_command(*o); }); });
}

}  // namespace freestand::cli
