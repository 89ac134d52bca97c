// freestand generate CASES.json: recordings with one concealed effect, their
// answer keys kept apart, for proving `freestand diagnose`
// (docs/diagnose-cases.md).

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "atomic_file.h"
#include "commands.h"
#include "recording_generator.h"

namespace freestand::cli {

namespace fs = std::filesystem;

namespace {

struct GenerateOptions {
  std::string cases;       // CASES.json
  std::string recordings;  // NAME.csv + NAME.nominal.json, manifest.json
  std::string answers;     // NAME.answer.json, NAME.model.*, answers.json
  std::string cache;       // simulation runs (default: ANSWERS/runs)
  std::vector<std::string> only;  // case names to generate (default: all)
  std::string concealment;  // overrides every case's effect.concealment when set
  int jobs = 2;
  bool keep_going = false;
};

// A listing written by an earlier run (empty when there is none), so that
// generating some cases again keeps the others listed.
nlohmann::json read_listing(const fs::path& path) {
  std::ifstream in(path);
  const nlohmann::json listing = in ? nlohmann::json::parse(in, nullptr, false) : nlohmann::json::object();
  return listing.is_object() ? listing : nlohmann::json::object();
}

// `earlier` without the cases generated now (`done`), then `now`.
nlohmann::json merged(const nlohmann::json& earlier, const nlohmann::json& now, const std::set<std::string>& done,
                      const char* key) {
  nlohmann::json out = nlohmann::json::array();
  if (earlier.is_array())
    for (const nlohmann::json& entry : earlier) {
      std::string name = entry.value(key, "");
      if (std::string(key) == "recording") name = name.substr(0, name.rfind(".csv"));
      if (!done.count(name)) out.push_back(entry);
    }
  for (const nlohmann::json& entry : now) out.push_back(entry);
  return out;
}

int generate(const GenerateOptions& o) {
  const std::string cache = o.cache.empty() ? (fs::path(o.answers) / "runs").string() : o.cache;
  check_folders_apart(o.recordings, o.answers);  // before any simulation; the runs hold the truth too
  check_folders_apart(o.recordings, cache);
  std::vector<CaseSpec> cases = read_case_file(o.cases);
  if (!o.concealment.empty())
    for (CaseSpec& spec : cases) spec.effect.rule = concealment_rule(o.concealment, "--concealment");
  nlohmann::json manifest = nlohmann::json::array(), answers = nlohmann::json::array(),
                 failed = nlohmann::json::array();
  std::set<std::string> done;
  for (const CaseSpec& spec : cases) {
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), spec.name) == o.only.end()) continue;
    done.insert(spec.name);
    fmt::print("freestand generate: {} ({})\n", spec.name, spec.effect.name);
    std::fflush(stdout);
    try {
      const GeneratedCase generated = generate_case(spec, cache, o.jobs);
      write_case(generated, spec.name, o.recordings, o.answers);
      const nlohmann::json& c = generated.answer["concealment"];
      fmt::print(
          "  magnitude {} {} ({}): RMS error change {:.3g} m, scatter {:.3g} m, effect alone {:.3g} m "
          "(ideal detector's deflection {:.3g})\n",
          generated.answer["effect"]["magnitude"].get<double>(), generated.answer["effect"]["unit"].get<std::string>(),
          c["rule"].get<std::string>(), c["change"].get<double>(), c["scatter"].get<double>(),
          c["effect_rms"].get<double>(), c["effect_deflection"].get<double>());
      manifest.push_back({{"recording", spec.name + ".csv"},
                          {"nominal", spec.name + ".nominal.json"},
                          {"ground_motion", generated.recording.nominal["ground_motion"]},
                          {"bodies", generated.recording.body_names()}});
      answers.push_back({{"case", spec.name}, {"answer", spec.name + ".answer.json"},
                         {"effect", generated.answer["effect"]["name"]},
                         {"magnitude", generated.answer["effect"]["magnitude"]},
                         {"change", c["change"]}, {"scatter", c["scatter"]}, {"effect_rms", c["effect_rms"]},
                         {"effect_deflection", c["effect_deflection"]}});
    } catch (const std::exception& e) {
      if (!o.keep_going) throw;
      std::fprintf(stderr, "freestand generate: case '%s' skipped: %s\n", spec.name.c_str(), e.what());
      failed.push_back({{"case", spec.name}, {"effect", spec.effect.name}, {"error", e.what()}});
    }
  }
  fs::create_directories(o.recordings);
  fs::create_directories(o.answers);
  const fs::path manifest_file = fs::path(o.recordings) / "manifest.json", answers_file = fs::path(o.answers) / "answers.json";
  nlohmann::json old_manifest = read_listing(manifest_file), old_answers = read_listing(answers_file);
  write_file_atomically(manifest_file.string(),
                        nlohmann::json{{"recordings", merged(old_manifest["recordings"], manifest, done, "recording")},
                                       {"format", "../shared/recording-format.md"}}
                                .dump(2) + "\n");
  write_file_atomically(answers_file.string(),
                        nlohmann::json{{"cases", merged(old_answers["cases"], answers, done, "case")},
                                       {"failed", merged(old_answers["failed"], failed, done, "case")}}
                                .dump(2) + "\n");
  fmt::print("freestand generate: {} recordings made in {}, answer keys in {}{}\n", manifest.size(), o.recordings,
             o.answers, failed.empty() ? "" : fmt::format(", {} cases failed (listed in answers.json)", failed.size()));
  return 0;
}

}  // namespace

void add_generate_command(CLI::App& app) {
  auto options = std::make_shared<GenerateOptions>();
  CLI::App* sub = app.add_subcommand(
      "generate",
      "Write test recordings for `freestand diagnose`: each case simulates a truth with one concealed effect\n"
      "from the catalogue (or none), finer than the model, measures it like a lab (servo table, gain error,\n"
      "causal anti-alias filter, noise) and writes NAME.csv + NAME.nominal.json (the nominal model only);\n"
      "the answer key goes to a separate folder (docs/diagnose-cases.md).");
  sub->add_option("cases", options->cases, "case file: {\"defaults\": {...}, \"cases\": [{...}, ...]}")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", options->recordings, "folder for the recordings and manifest.json")->required();
  sub->add_option("--answers", options->answers, "folder for the answer keys (never the recordings' folder)")
      ->required();
  sub->add_option("--cache", options->cache, "folder for the simulation runs, reused (default: ANSWERS/runs)");
  sub->add_option("--concealment", options->concealment,
                  "what concealed means, for every case (default: each case's effect.concealment, paired_change):\n"
                  "paired_change or within_scatter (docs/diagnose-cases.md)")
      ->check(CLI::IsMember({"paired_change", "within_scatter"}));
  sub->add_option("--case", options->only, "generate only this case (repeatable)");
  sub->add_option("-j,--jobs", options->jobs, "simulations at a time")->capture_default_str()->check(
      CLI::PositiveNumber);
  sub->add_flag("--keep-going", options->keep_going, "skip a failing case (listed in answers.json) and go on");
  sub->callback([options] { guarded([&] { return generate(*options); }); });
}

}  // namespace freestand::cli
