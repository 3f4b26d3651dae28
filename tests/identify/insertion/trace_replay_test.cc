// `colosim run --trace` writes a recorded insertion (issue 17, item 4): every column of the
// recording, the knobs and the handle inputs as commanded, and the parameter file of the
// run. The identification's replay (identify/insertion/replay.h) builds the simulation the
// run built, so the trace of the paper's model replays to the values it wrote, and the
// trace plus sensor noise replays to the noise.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixture.h"
#include "identify/insertion/identify.h"

namespace colosim {
namespace {

// The shipped default parameters at 3 cm (short runs) with the paper's model: no wall
// friction, bending or lifter stiffening, the Voigt law (writeOrganParameters of an empty fit).
std::string paperParameters(const test::TempDir& dir) {
  nlohmann::json j = nlohmann::json::parse(test::readFile(test::asset("params/default.json")));
  j["colon"]["control_point_spacing"]["value"] = 0.03;
  j["scope"]["segment_length"]["value"] = 0.03;
  const std::string coarse = dir.write("coarse.json", j.dump(2));
  const std::string path = dir.file("paper.json");
  writeOrganParameters(path, coarse, InsertionFit{}, "test: the paper's model");
  return path;
}

// 1.2 s from 40 cm, where a push stretches the sigmoid: a quick push of 6 cm turning and
// steering up, a hold, a pull of 3 cm steering left. The scenario's overrides (friction and
// axial rigidity) are those --params drops. The parameter file is the paper's model, the base
// the organ replay starts from (params/default.json adds the patient's colon bending).
std::string traceScenario(const test::TempDir& dir) {
  return dir.write("trace_scenario.json", R"({
    "format": "colosim-scenario", "version": 1, "name": "trace_replay",
    "description": "test", "anatomy": "anatomy/adult.json", "params": "params/paper.json",
    "dt_s": 0.001, "duration_s": 1.2, "seed": 1,
    "start": {"kind": "rest"},
    "overrides": {"wall_friction": 0.15, "colon_axial_rigidity_N": 500.0},
    "script": [
      {"t_s": 0.0, "insertion_m": 0.40, "rotation_rad": 0.0, "knob_updown_rad": 0.0, "knob_leftright_rad": 0.0},
      {"t_s": 0.3, "insertion_m": 0.46, "rotation_rad": 0.3, "knob_updown_rad": 0.4, "knob_leftright_rad": 0.0},
      {"t_s": 0.8, "insertion_m": 0.46, "rotation_rad": -0.2, "knob_updown_rad": 0.4, "knob_leftright_rad": 0.0},
      {"t_s": 1.2, "insertion_m": 0.43, "rotation_rad": 0.0, "knob_updown_rad": 0.2, "knob_leftright_rad": 0.3}]})");
}

// colosim run SCENARIO --trace TRACE --trace-hz 1000 [extra]; the trace as a recording.
InsertionRecording runTrace(const test::TempDir& dir, const std::string& scenario, const std::string& name,
                            const std::string& extra) {
  const std::string trace = dir.file(name);
  const test::CommandResult r = test::runCommand(std::string(COLOSIM_EXE) + " run " + scenario + " --trace " + trace +
                                                 " --trace-hz 1000 " + extra + " 2>&1");
  EXPECT_EQ(r.code, 0) << r.out;
  return readInsertionRecording(trace);
}

double rmsDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t k = 0; k < a.size(); ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(s / a.size());
}

TEST(OrganTrace, IsARecordingThatThePapersModelReplaysToTheNoise) {
  const test::TempDir dir;
  const std::string params = paperParameters(dir);
  const InsertionRecording rec = runTrace(dir, traceScenario(dir), "paper.csv", "--params " + params);
  // Every column of a recording, the start state at time 0 and one row per step after it.
  ASSERT_EQ(rec.rows(), 1201u);
  EXPECT_DOUBLE_EQ(rec.time_s.front(), 0.0);
  EXPECT_TRUE(rec.has_tip);
  EXPECT_EQ(rec.params, params);
  EXPECT_NEAR(rec.input.front().insertion_m, 0.40, 1e-12);
  // The knobs as commanded: the row ending at 0.301 s holds the script at 0.300 s.
  EXPECT_NEAR(rec.input[301].knob_updown_rad, 0.4, 1e-9);
  EXPECT_NEAR(rec.input[1200].knob_leftright_rad, 0.3 * 0.399 / 0.4, 1e-9);

  const ReplaySetup setup = makeReplaySetup(recordingScenario(rec));
  EXPECT_EQ(setup.params.contact.friction_coefficient, 0.0);  // the file's, not the scenario's override
  const Prediction paper = replayInsertion(setup, rec, OrganParams{});
  ASSERT_TRUE(paper.ok);
  double largest = 0, spread = 0;
  for (size_t k = 0; k < rec.rows(); ++k) {
    largest = std::max(largest, std::abs(paper.force_N[k] - rec.force_N[k]));
    spread = std::max(spread, std::abs(rec.force_N[k] - rec.force_N.front()));
  }
  std::printf("trace force range %.3f N, replay differs by at most %.3g N\n", spread, largest);
  EXPECT_GT(spread, 0.5);      // the run pushes: a force the comparison can miss
  EXPECT_LT(largest, 1e-5);    // the rounding of the written inputs and forces, not a model

  // Plus sensor noise and an offset, it replays to the noise.
  std::mt19937_64 rng(17);
  std::normal_distribution<double> noise(0.0, 0.05);
  InsertionRecording noisy = rec;
  double mean = 0;
  for (size_t k = 0; k < rec.rows(); ++k) {
    noisy.force_N[k] = rec.force_N[k] + 0.1 + noise(rng);
    mean += noisy.force_N[k] - paper.force_N[k];
  }
  mean /= rec.rows();
  double sse = 0;
  for (size_t k = 0; k < rec.rows(); ++k) sse += std::pow(noisy.force_N[k] - paper.force_N[k] - mean, 2);
  EXPECT_NEAR(std::sqrt(sse / rec.rows()), 0.05, 0.005);
}

TEST(OrganTrace, ReplaysTheScenariosOverridesAndOnlyThoseItWasRunWith) {
  // Without --params the run has the scenario's friction 0.15 and axial rigidity 500 N: the
  // replay with that friction reproduces it, the paper's model (no friction) does not.
  const test::TempDir dir;
  const std::string scenario = traceScenario(dir);
  const InsertionRecording rec = runTrace(dir, scenario, "override.csv", "");
  EXPECT_TRUE(rec.params.empty());
  const ReplaySetup setup = makeReplaySetup(recordingScenario(rec));
  EXPECT_EQ(setup.params.colon.tension_EA_N, 500.0);
  OrganParams with_friction;
  with_friction.friction = 0.15;
  const Prediction same = replayInsertion(setup, rec, with_friction);
  const Prediction paper = replayInsertion(setup, rec, OrganParams{});
  const double same_rms = rmsDifference(same.force_N, rec.force_N), paper_rms = rmsDifference(paper.force_N, rec.force_N);
  std::printf("replay with friction 0.15: %.3g N RMS from the trace; without: %.3g N\n", same_rms, paper_rms);
  EXPECT_LT(same_rms, 1e-5);
  EXPECT_GT(paper_rms, 0.02);
}

}  // namespace
}  // namespace colosim
