#include "diagnosis_verdict.h"

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace freestand::diagnosis {

using nlohmann::json;

std::string format_value(const Candidate& c, double v) {
  return c.unit.empty() ? fmt::format("{:.3g}", v) : fmt::format("{:.3g} {}", v, c.unit);
}

std::string format_shape(const Candidate& c) {
  return c.shape_name.empty() ? "" : fmt::format(" ({} {:.3g} {})", c.shape_name, c.shape, c.shape_unit);
}

namespace {

constexpr double kRangeEndTolerance = 1e-6;  // scaled units: the settle clamps a value to its range's end exactly

// The candidates of a similar catalogue entry that also improved an accepted effect's profile.
std::string similar_words(const Effect& e) {
  if (e.similar.empty()) return "";
  std::vector<std::string> parts;
  for (const auto& [name, drop] : e.similar) parts.push_back(fmt::format("{} (profile chi2 drop {:.1f})", name, drop));
  return fmt::format(" Of similar signature, also improving the single-run profile, not named: {}.", fmt::join(parts, ", "));
}

// Where a mismatched feature is: the impact of its axis, else its time and name.
std::string event_words(const Mismatch& m) {
  const std::size_t impact = m.feature.find(".impact");
  if (impact != std::string::npos)
    return fmt::format("at impact {} of {}", std::stoi(m.feature.substr(impact + 7)),
                       m.feature.substr(m.feature.find('.') + 1, impact - m.feature.find('.') - 1));
  return fmt::format("at t = {:.2f} s ({})", m.time, m.feature.substr(m.feature.find('.') + 1));
}

// The other shapes of an effect's law that fit alike, each at its own value.
std::string alike_shape_words(const FittedCandidate& f) {
  if (f.alike_shapes.empty()) return "";
  std::vector<std::string> parts;
  for (const auto& [shape, value] : f.alike_shapes)
    parts.push_back(fmt::format("{:.3g} {} with {}", shape, f.candidate.shape_unit, format_value(f.candidate, value)));
  return fmt::format(" Its {} is not resolved: {} fit as well.", f.candidate.shape_name, fmt::join(parts, ", "));
}

// The members a test's misfits are over: the chi2 of a model far off in a feature grows with
// them (the predictive z's tails narrow as its scatter's dof grow), so a test on 2M members can
// read a larger misfit of the model as given than its M-member ensemble alone does.
std::string members_words(const FittedCandidate& f) {
  return f.members > 0 ? fmt::format(" on {} members of each model", f.members) : "";
}

// A fitted value's uncertainty: a factor for a log-scale one.
std::string uncertainty_words(const FittedCandidate& f) {
  return !std::isfinite(f.standard_error) ? "uncertainty not resolved"
         : f.candidate.log_scale          ? fmt::format("x/ {:.2f}", std::exp(f.standard_error))
                                          : fmt::format("+- {:.2g}", f.standard_error);
}

// The rivals that fit as well, each at its own value and in plain words: the user must know
// what else the recording allows (an off-axis centre of mass or worn edges are different
// repairs), not only its name.
std::string alike_words(const Effect& e) {
  if (e.indistinguishable.empty()) return "";
  std::vector<std::string> parts;
  for (const FittedCandidate& g : e.indistinguishable)
    parts.push_back(fmt::format("{} = {} ({}): {}", g.candidate.name, format_value(g.candidate, g.value),
                                uncertainty_words(g), g.candidate.description));
  return fmt::format(" Fits as well, so this recording cannot tell them apart: {}.", fmt::join(parts, "; "));
}

// A value settled at its range's end (a corner gap at 5 % of the base width, case23 of the proof
// study: 36 mm for 16, its chi2 still falling there) is where the search stopped, not a
// minimum: its uncertainty is the curvature's near the end and says nothing past it.
bool at_searched_end(const FittedCandidate& f) {
  const Candidate& c = f.candidate;
  return at_range_end(c, f.value, kRangeEndTolerance) &&
         std::abs(to_scaled(c, f.value) - to_scaled(c, c.nominal)) > kRangeEndTolerance;
}

std::string range_end_words(const FittedCandidate& f) {
  if (!at_searched_end(f)) return "";
  return fmt::format(" It lies at the end of the range searched ({} to {}): the recording may want it further, so "
                     "this value is a bound, and its uncertainty does not reach past it.",
                     format_value(f.candidate, f.candidate.lower), format_value(f.candidate, f.candidate.upper));
}

// One accepted effect: what, the value and its uncertainty, the misfit before and after, and
// what fits alike.
std::string effect_words(const Effect& e) {
  const FittedCandidate& f = e.fit;
  return fmt::format("{}: {} ({} = {}{}, {}; model had {}). Misfit {:.1f} -> {:.1f} (+- {:.1f}){}, p = {:.2g} "
                     "after {} candidates, held-out improvement {:.1f}.{}{}{}{}{}\n",
                     e.verdict == "recalibrated" ? "Recalibrated" : e.verdict == "measurement" ? "Measurement"
                                                                                              : "Missing physics",
                     f.candidate.description, f.candidate.name, format_value(f.candidate, f.value),
                     format_shape(f.candidate), uncertainty_words(f),
                     format_value(f.candidate, f.candidate.nominal), f.chi2 + f.delta, f.chi2, f.delta_se, members_words(f),
                     f.p_value, e.candidates_tried, f.held_out_delta, range_end_words(f), alike_shape_words(f),
                     e.far_off ? " FAR from the stated value: check the nominal." : "",
                     alike_words(e), similar_words(e));
}

// A chi2 difference between two models, the second's "lower" when delta > 0.
std::string difference_words(double delta, double se) {
  return fmt::format("its chi2 {:.1f} +- {:.1f} {}", std::abs(delta), se, delta >= 0 ? "lower" : "higher");
}

// A --hypothesis: supported or not against the model as given, and against the improved one.
std::string hypothesis_words(const HypothesisTest& h, std::size_t number) {
  const FittedCandidate& f = h.fit;
  std::vector<std::string> values;
  for (const StatedValue& s : h.stated)
    values.push_back(h.stated.size() == 1 ? fmt::format("{} = {}", s.candidate, format_value(f.candidate, s.value))
                                          : fmt::format("{} = {:.3g}", s.candidate, s.value));
  std::string v = fmt::format("Hypothesis {}: {} ({}): {}. Misfit {:.1f} -> {:.1f} (+- {:.1f}){} against the model "
                              "as given, p = {:.2g}, dBIC {:.1f}, held-out improvement {:.1f}.",
                              number, fmt::join(values, ", "), f.candidate.description,
                              h.supported ? "supported" : "not supported", f.chi2 + f.delta, f.chi2, f.delta_se,
                              members_words(f), f.p_value, f.delta_bic, f.held_out_delta);
  if (!h.against_improved.empty())
    v += fmt::format(" Against the improved model it fits {} ({}).", h.against_improved,
                     difference_words(h.improved_delta, h.improved_delta_se));
  return v + "\n";
}

// Where the search ended: within the noise (with or without effects), or what is unexplained.
std::string closing_words(const Diagnosis& d) {
  const std::string misfit = fmt::format("misfit {:.1f} for {} features on {} members, 99 % noise limit {:.1f}",
                                         d.chi2_final, d.feature_count, d.closing_members, d.chi2_noise_limit);
  const bool noise_only = d.chi2_final <= d.chi2_noise_limit && d.unexplained.empty();
  if (noise_only && d.effects.empty())
    return "No missing physics found: the model matches the recording within noise and chaos (" + misfit + ").\n";
  if (noise_only) return "Nothing significant is left (" + misfit + ").\n";
  std::string v = "Unexplained: no candidate explains the rest (" + misfit + ").";
  if (!d.unexplained.empty())
    v += fmt::format(" Mismatched from t = {:.2f} s ({}) to t = {:.2f} s.", d.unexplained.front().time,
                     event_words(d.unexplained.front()), d.unexplained.back().time);
  return v + "\n";
}

// A numerical setting as the JSON names it: a time step in s to 3 digits, a grid as given.
std::string setting_words(const std::string& setting) {
  const json value = json::parse(setting, nullptr, false);
  return value.is_number() ? fmt::format("{:.3g} s", value.get<double>()) : setting;
}

// One line per quantity and model refined: each check's distance from the setting it was made on
// (the model's own first; the last one converged or the finest adopted), and the setting adopted.
// The finest setting adopted was checked against nothing finer, and the line says so.
std::string numerics_words(const std::vector<NumericsCheck>& checks) {
  std::string v;
  for (std::size_t i = 0, end = 0; i < checks.size(); i = end) {
    const NumericsCheck& first = checks[i];
    std::vector<std::string> moved;
    std::string on = "the model's", adopted;
    for (end = i; end < checks.size() && checks[end].quantity == first.quantity && checks[end].model == first.model; ++end) {
      moved.push_back(fmt::format("by {:.0f} from {}", checks[end].distance, on));
      if (checks[end].adopted) adopted = checks[end].setting, on = setting_words(adopted);
    }
    if (adopted.empty()) continue;
    v += fmt::format("Numerics: the model's {0} was not converged for the model {1}: the finest {0}, {2}, moved the "
                     "features {3} (limit {4:.0f}, chi2's mean); refined to {5}{6}.\n", first.quantity, first.model,
                     setting_words(first.reference), fmt::join(moved, ", "), first.limit, setting_words(adopted),
                     adopted == first.reference ? ", the finest checked, itself not checked against a finer one" : "");
  }
  return v;
}

}  // namespace

// The verdict: measurement and numerics first, then where the model as given mismatched,
// each effect, and where the search ended.
std::string verdict_text(const Diagnosis& d) {
  std::string v;
  for (const TableTracking& k : d.table)
    v += "Measurement: " + k.text + ". The simulations replay the recorded table motion, so the bodies are "
         "compared under what the table did.\n";
  v += numerics_words(d.numerics_checks);
  for (const MeasurementIssue& m : d.measurement) v += "Measurement: " + m.text + " (corrected for in the comparison).\n";
  if (!d.mismatches.empty()) {
    const Mismatch& first = d.mismatches.front();
    std::set<std::string> modes, bodies;
    for (const Mismatch& m : d.mismatches) modes.insert(m.mode), bodies.insert(m.body);
    v += fmt::format("Mismatch: {} ({}) from t = {:.2f} s, first {}; {} of {} event features beyond {} s.d.\n",
                     fmt::join(bodies, ", "), fmt::join(modes, ", "), first.time, event_words(first),
                     d.mismatches.size(), d.feature_count, d.z_threshold);
  }
  for (const Effect& e : d.effects) v += effect_words(e);
  for (std::size_t k = 0; k < d.hypotheses.size(); ++k) v += hypothesis_words(d.hypotheses[k], k + 1);
  for (const HypothesisComparison& c : d.hypothesis_pairs)
    v += fmt::format("Hypothesis {} against {}: fits {} ({}, every feature).\n", c.second + 1, c.first + 1,
                     c.second_fits, difference_words(c.delta, c.delta_se));
  if (d.failed_simulations > 0)
    v += fmt::format("Caution: {} of {} simulations failed, also when run again (first: {}). A failed run counts as not "
                     "fitting, so a candidate value that failed was neither chosen nor accepted: an effect may be "
                     "missing from this verdict.\n", d.failed_simulations, d.simulations, d.first_failure);
  return v + closing_words(d);
}

json diagnosis_json(const Diagnosis& d) {
  auto fitted = [](const FittedCandidate& f) {
    json j{{"candidate", f.candidate.name}, {"catalogue", f.candidate.entry}, {"where", f.candidate.where},
                {"description", f.candidate.description}, {"unit", f.candidate.unit}, {"value", f.value},
                {"standard_error", std::isfinite(f.standard_error) ? json(f.standard_error) : json(nullptr)},
                {"standard_error_of_log", f.candidate.log_scale}, {"nominal", f.candidate.nominal},
                {"range", {f.candidate.lower, f.candidate.upper}}, {"stated", f.candidate.stated},
                {"chi2", f.chi2}, {"delta_chi2", f.delta}, {"delta_chi2_se", f.delta_se}, {"members", f.members}, {"p_value", f.p_value}, {"delta_bic", f.delta_bic},
                {"held_out_delta_chi2", f.held_out_delta}, {"evaluations", f.evaluations},
                {"profile", f.profile}};
    if (!f.candidate.shape_name.empty())
      j["shape"] = {{"name", f.candidate.shape_name}, {"value", f.candidate.shape}, {"unit", f.candidate.shape_unit},
                    {"tried", f.candidate.shapes}, {"alike", json::array()}};
    for (const auto& [shape, value] : f.alike_shapes) j["shape"]["alike"].push_back({{"shape", shape}, {"value", value}});
    return j;
  };
  auto mismatch = [](const Mismatch& m) {
    return json{{"feature", m.feature}, {"body", m.body}, {"mode", m.mode}, {"time", m.time},
                {"recorded", m.recorded}, {"simulated", m.simulated}, {"z", m.z}};
  };
  json out = {{"verdict", d.verdict}, {"feature_count", d.feature_count}, {"chi2_nominal", d.chi2_nominal},
              {"chi2_final", d.chi2_final}, {"closing_members", d.closing_members}, {"chi2_noise_limit_99", d.chi2_noise_limit},
              {"simulations", d.simulations}, {"failed_simulations", d.failed_simulations},
              {"first_failure", d.first_failure}, {"notes", d.notes}, {"improved_scenario", d.improved}};
  out["numerics_checks"] = json::array();
  for (const NumericsCheck& c : d.numerics_checks)
    out["numerics_checks"].push_back({{"quantity", c.quantity}, {"model", c.model}, {"reference", json::parse(c.reference)},
                                      {"distance", c.distance}, {"limit", c.limit}, {"adopted", c.adopted},
                                      {"setting", c.setting.empty() ? json() : json::parse(c.setting)}});
  out["measurement_issues"] = json::array();
  for (const MeasurementIssue& m : d.measurement)
    out["measurement_issues"].push_back({{"channel", m.channel}, {"text", m.text}, {"delay", m.delay},
                                         {"delay_significant", m.delay_significant}, {"gain", m.gain},
                                         {"gain_sd", m.gain_sd}, {"gain_significant", m.gain_significant},
                                         {"bias", m.bias}, {"drift", m.drift}, {"drift_significant", m.drift_significant},
                                         {"correlation", m.correlation}, {"round", m.round},
                                         {"catalogue", m.delay_significant ? "sensor_delay"
                                                       : m.gain_significant ? "sensor_gain" : "sensor_drift"}});
  out["table_tracking"] = json::array();
  for (const TableTracking& k : d.table)
    out["table_tracking"].push_back({{"channel", k.channel}, {"text", k.text}, {"delay", k.delay},
                                     {"delay_sd", k.delay_sd}, {"gain", k.gain}, {"gain_sd", k.gain_sd},
                                     {"left_share", k.left_share}, {"noise_share", k.noise_share},
                                     {"correlation", k.correlation}});
  out["effects"] = out["recalibrated"] = json::array();
  for (const Effect& e : d.effects) {
    json j = fitted(e.fit);
    json similar = json::array();
    for (const auto& [name, drop] : e.similar) similar.push_back({{"candidate", name}, {"profile_delta_chi2", drop}});
    json alike = json::array();
    for (const FittedCandidate& g : e.indistinguishable) alike.push_back(fitted(g));
    j.update({{"far_off", e.far_off}, {"at_range_end", at_searched_end(e.fit)}, {"indistinguishable_from", alike},
              {"similar_signature", similar}, {"candidates_tried", e.candidates_tried}, {"round", e.round}});
    if (e.verdict == "measurement") j["channel"] = e.fit.candidate.where;
    out[e.verdict == "recalibrated" ? "recalibrated" : e.verdict == "measurement" ? "measurement_issues" : "effects"].push_back(j);
  }
  out["hypotheses"] = json::array();
  for (const HypothesisTest& h : d.hypotheses) {
    json j = fitted(h.fit);
    j["supported"] = h.supported;
    j["stated"] = json::array();
    for (const StatedValue& s : h.stated) j["stated"].push_back({{"candidate", s.candidate}, {"value", s.value}});
    if (!h.against_improved.empty()) j.update({{"against_improved", h.against_improved}, {"improved_delta_chi2", h.improved_delta}, {"improved_delta_chi2_se", h.improved_delta_se}});
    out["hypotheses"].push_back(j);
  }
  out["hypothesis_pairs"] = json::array();
  for (const HypothesisComparison& c : d.hypothesis_pairs)
    out["hypothesis_pairs"].push_back({{"first", c.first}, {"second", c.second}, {"delta_chi2", c.delta},
                                       {"delta_chi2_se", c.delta_se}, {"second_fits", c.second_fits}});
  out["mismatches"] = out["unexplained"] = out["divergence"] = out["candidates"] = json::array();
  for (const Mismatch& m : d.mismatches) out["mismatches"].push_back(mismatch(m));
  for (const Mismatch& m : d.unexplained) out["unexplained"].push_back(mismatch(m));
  for (const ChannelDivergence& c : d.divergence)
    out["divergence"].push_back({{"channel", c.channel}, {"time", std::isfinite(c.time) ? json(c.time) : json(nullptr)}});
  for (std::size_t r = 0; r < d.rounds.size(); ++r)
    for (const FittedCandidate& f : d.rounds[r]) {
      json j = fitted(f);
      j["round"] = r + 1;
      out["candidates"].push_back(j);
    }
  return out;
}

}  // namespace freestand::diagnosis
