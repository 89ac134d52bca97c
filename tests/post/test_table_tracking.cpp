// table_tracking: recordings of a table made from a known command with a known
// lag, gain, echo and noise; the estimates must recover them within the
// uncertainty they report, and a table that followed its command is not flagged.

#include "table_tracking.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "scenario.h"

namespace freestand {
namespace {

// A 1-8 Hz sweep of 2 m/s^2 over 10 s: a table command with broadband content.
ShakeTable sweep_command() {
  Scenario s;
  s.document = {{"table_motion",
                 {{"x", {{"motion", "sweep"}, {"amplitude", {2.0, "m/s^2"}}, {"frequency", 1.0}, {"frequency_end", 8.0},
                         {"duration", 10.0}}}}}};
  return *commanded_table(s);
}

// What the table did: gain * command(t - delay) + echo * command(t - 0.05) + white noise,
// sampled at 200 Hz, with the noise stated in the nominal.
Recording table_recording(const ShakeTable& command, double delay, double gain, double echo, double noise,
                          unsigned seed) {
  Recording r;
  r.nominal = {{"sensor_noise", {{"acceleration", noise}}}};
  RecordingChannel a{"table_ax", {}, false};
  std::mt19937 random(seed);
  std::normal_distribution<double> white(0.0, noise);
  const auto at = [&](double t) { return t < 0 ? 0.0 : command.at(t).acceleration.x(); };
  for (int k = 0; k <= 2000; ++k) {
    const double t = k / 200.0;
    r.time.push_back(t);
    a.values.push_back(gain * at(t - delay) + echo * at(t - 0.05) + white(random));
  }
  r.channels.push_back(a);
  return r;
}

TEST(TableTracking, RecoversLagAndGainOfAServo) {
  const ShakeTable command = sweep_command();
  const std::vector<TableTracking> k = table_tracking(table_recording(command, 0.0113, 0.981, 0, 0.05, 1), command);
  ASSERT_EQ(k.size(), 1u);
  // Within 4 of the reported s.d. (the estimates are unbiased for white noise); the s.d.
  // themselves are checked against the scatter over seeds below.
  EXPECT_NEAR(k[0].delay, 0.0113, 4 * k[0].delay_sd);
  EXPECT_NEAR(k[0].gain, 0.981, 4 * k[0].gain_sd);
  EXPECT_TRUE(k[0].delay_significant && k[0].gain_significant);
  EXPECT_FALSE(k[0].left_significant) << "lag and gain explain it all: " << k[0].left_share;
  EXPECT_NE(k[0].text.find("lags by 11."), std::string::npos) << k[0].text;
}

TEST(TableTracking, ReportedDelayUncertaintyMatchesTheScatterOverNoise) {
  const ShakeTable command = sweep_command();
  std::vector<double> delays;
  double reported = 0;
  for (unsigned seed = 1; seed <= 30; ++seed) {
    const TableTracking k = table_tracking(table_recording(command, 0.008, 1.0, 0, 0.2, seed), command).at(0);
    delays.push_back(k.delay), reported = k.delay_sd;
  }
  double mean = 0, var = 0;
  for (double d : delays) mean += d / delays.size();
  for (double d : delays) var += (d - mean) * (d - mean) / (delays.size() - 1);
  // The sample s.d. of 30 draws scatters by 1/sqrt(2 x 29) = 13 %; 40 % is 3 of those. The
  // Cramer-Rao bound is what a cross-correlation delay reaches at this signal-to-noise.
  EXPECT_NEAR(std::sqrt(var) / reported, 1.0, 0.4) << "scatter " << std::sqrt(var) << " reported " << reported;
  RecordProperty("delay_scatter_over_reported_sd", std::to_string(std::sqrt(var) / reported));
}

TEST(TableTracking, ATableThatFollowedItsCommandIsNotFlagged) {
  const ShakeTable command = sweep_command();
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const TableTracking k = table_tracking(table_recording(command, 0, 1, 0, 0.05, seed), command).at(0);
    EXPECT_TRUE(k.text.empty()) << k.text;
    EXPECT_TRUE(k.noise_stated);
  }
}

TEST(TableTracking, DistortionBeyondLagAndGainIsFlagged) {
  // An echo 50 ms late at 5 % of the command: no single lag and gain makes it.
  const ShakeTable command = sweep_command();
  const TableTracking k = table_tracking(table_recording(command, 0, 1, 0.05, 0.05, 3), command).at(0);
  EXPECT_TRUE(k.left_significant) << k.left_share;
  EXPECT_GT(k.left_share, k.noise_share);  // what is left is the noise plus the part of the echo no lag absorbs
}

TEST(TableTracking, WithoutStatedNoiseItIsEstimatedFromSecondDifferences) {
  const ShakeTable command = sweep_command();
  Recording r = table_recording(command, 0.0113, 0.981, 0, 0.05, 4);
  r.nominal = nlohmann::json::object();
  const TableTracking k = table_tracking(r, command).at(0);
  EXPECT_FALSE(k.noise_stated);
  // The sweep's own second differences at 200 Hz can only add to the 0.05 of the noise.
  EXPECT_GE(k.noise, 0.05 * 0.9);
  EXPECT_NEAR(k.delay, 0.0113, 4 * k.delay_sd);
}

TEST(TableTracking, AnAxisNotCommandedOrNotRecordedIsLeftOut) {
  const ShakeTable command = sweep_command();
  Recording r = table_recording(command, 0, 1, 0, 0.05, 5);
  r.channels[0].name = "table_ay";
  EXPECT_TRUE(table_tracking(r, command).empty());
}

}  // namespace
}  // namespace freestand
