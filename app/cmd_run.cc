// colosim run SCENARIO [--duration S] [--record FILE] [--frames DIR] [--video FILE.mp4] [--view ...]
// [--fps N] [--size WxH] [--trace CSV] [--score] [--json]: a scenario's scripted inputs, headless, on the colon +
// scope simulation. `settle` is the colon alone settling under gravity and its mesentery.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "app/commands.h"
#include "app/options.h"
#include "identify/insertion/recording.h"
#include "trainer/progress.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"
#include "trainer/assets.h"
#include "trainer/settle.h"
#include "trainer/strict_json.h"
#include "trainer/tension_law_file.h"

namespace colosim::app {

namespace {

struct RunOptions {
  std::string scenario = "settle";
  double duration_s = -1;   // [s]; negative: the scenario's duration (10 s for settle)
  double dt_s = 1e-3;       // settle only [s]
  std::string params;       // settle only
  std::string anatomy;      // settle only
  std::string scope;        // scope design file (scenarios only); empty: the scenario's
  std::string tension_law;  // law file (colosim identify --law-out); empty: the parameters' Voigt law
  std::string record;
  std::string frames;
  std::string video;        // a new video file (FFmpeg: H.264 in MP4)
  std::string view = "onboard";
  double fps = 10;
  std::string size = "640x480";
  bool score = false;
  bool json = false;
  std::string query = "fcl";
  std::string trace;        // CSV of the telemetry (a new file)
  double trace_hz = 10;     // trace rows per simulated second
  int threads = 1;          // 2: each step's independent halves on two threads (scenarios only)
};

// The header of a --trace file: a recorded insertion of this run (scenario and parameter
// file named as a session names them) and how it was simulated.
void writeTraceHeader(std::FILE* f, const Scenario& scenario, const WorldSimulation& sim) {
  std::fprintf(f, "# colosim-measurement v1\n# experiment: insertion\n# scenario: %s\n",
               (scenario.id.empty() ? scenario.file : scenario.id).c_str());
  if (scenario.params_replaced) std::fprintf(f, "# params: %s\n", scenario.params_path.c_str());
  std::fprintf(f, "# note: colosim run --trace (simulated, no sensor noise); columns after tip_z_m are telemetry\n");
  std::fprintf(f, "# simulated_with: %d control points (mean spacing %.4g m), dt %.4g s\n", sim.model().colon.n,
               sim.model().colon.rest_length_m.mean(), sim.dt_s());
  const std::vector<std::string> columns = insertionTraceColumns();
  for (size_t c = 0; c < columns.size(); ++c) std::fprintf(f, "%s%s", c ? "," : "", columns[c].c_str());
  std::fprintf(f, "\n");
}

// One row: inputs to 1e-10 (the replay threads and steps with them), force and torque to
// 1e-7 N and N m.
void writeTraceRow(std::FILE* f, const Telemetry& t) {
  std::fprintf(f, "%.6f,%.10f,%.10f,%.10f,%.10f,%.7f,%.8f,%.6f,%.6f,%.6f,%.4f,%.5f,%.4f,%.4f,%g\n", t.time_s,
               t.input.insertion_m, t.input.rotation_rad, t.input.knob_updown_rad, t.input.knob_leftright_rad,
               t.handle_force_N, t.handle_torque_Nm, t.tip_position_m.x(), t.tip_position_m.y(),
               t.tip_position_m.z(), t.wall_force_peak_N, t.tip_to_caecum_m, t.tip_arclength_m, t.mesentery_stretch,
               t.loop_turns);
}

int runSettle(const RunOptions& o) {
  if (!o.scope.empty()) throw InputError("--scope: the settle run simulates the colon alone, without a scope");
  if (o.threads != 1) throw InputError("--threads: the settle run simulates the colon alone, on one thread");
  const Parameters params = loadParameters(o.params.empty() ? assetPath("params/default.json") : o.params);
  std::shared_ptr<const TensionLaw> law;
  if (!o.tension_law.empty()) law = loadTensionLaw(o.tension_law);
  const WorldModel world =
      loadWorldModel(o.anatomy.empty() ? assetPath("anatomy/adult.json") : o.anatomy, params, law);
  const ColonModel& model = world.colon;
  const SettleSummary s = settleColon(world, o.duration_s > 0 ? o.duration_s : 10.0, o.dt_s);
  std::printf("colosim run settle: adult colon, %d control points over %.3f m, %.1f s at dt = %.4f s (%ld steps)\n",
              s.n_control_points, s.length_m, s.duration_s, s.dt_s, s.steps);
  if (law || params.tension_law) printTensionLaw(*model.tension_law, law ? o.tension_law : params.file);
  std::printf("  energy at start      %10.5f J\n", s.energy_start_J);
  std::printf("  energy at end        %10.5f J (kinetic %.3e J)\n", s.energy_end_J, s.kinetic_end_J);
  std::printf("  max displacement     %10.2f mm (in the %s)\n", 1e3 * s.max_displacement_m,
              s.max_displacement_region.c_str());
  std::printf("  max speed at end     %10.3e m/s\n", s.max_speed_end_m_per_s);
  std::printf("  time per step        %10.2f us (median of blocks of 100 steps)\n", s.us_per_step_median);
  std::printf("  state finite         %10s\n", s.finite ? "yes" : "NO");
  std::printf("  state hash     %016llx\n", static_cast<unsigned long long>(s.state_hash));
  return s.finite ? 0 : 1;
}


int runScripted(const RunOptions& o) {
  // Every input is read and checked before any output is opened.
  Scenario scenario = findScenario(o.scenario);
  // A session holds the scenario, the parameter file and the inputs: what it cannot name
  // would make its replay differ, so such a run is not recorded.
  if (!o.record.empty() && !o.tension_law.empty())
    throw InputError("--record with --tension-law: a session cannot name the law, so it would not replay; put the "
                     "law in a parameter file (colon.tension_law) and give that with --params");
  if (!o.record.empty() && o.query != "fcl")
    throw InputError("--record with --query " + o.query + ": sessions replay with the FCL query only");
  // Another parameter file, e.g. an identified one (colosim identify --law-out on a recorded
  // insertion): it states the wall friction (and tension law) to simulate, so the scenario's
  // wall_friction override gives way to the file's friction_coefficient.
  std::optional<double> dropped_friction;
  if (!o.params.empty()) dropped_friction = useParameterFile(scenario, o.params);
  if (!o.scope.empty()) useScopeDesign(scenario, o.scope);
  const SizePx size = parseSize(o.size, 16);
  std::shared_ptr<const TensionLaw> law;
  if (!o.tension_law.empty()) law = loadTensionLaw(o.tension_law);
  if (!o.trace.empty() && std::filesystem::exists(o.trace))
    throw InputError(o.trace + ": exists (--trace never overwrites a file)");
  if (!o.frames.empty()) checkFramesDir(o.frames);
  if (!o.video.empty()) checkVideoFile(o.video, o.view, size);
  WorldSimulation sim(scenario, law, o.query);
  sim.useTwoLanes(o.threads == 2);
  const double dt_s = sim.dt_s();
  const long steps = o.duration_s > 0 ? std::lround(o.duration_s / dt_s) : scenario.steps();

  std::unique_ptr<SessionWriter> writer;
  if (!o.record.empty()) writer = std::make_unique<SessionWriter>(o.record, sessionHeaderFor(scenario, COLOSIM_VERSION));
  RunHooks hooks;
  ProgressBar bar("run " + scenario.name + (o.video.empty() ? "" : " (video)"), steps, stderrIsTerminal() && !o.json);
  hooks.on_progress = [&](long done) { bar.update(done); };
  double peak_push = 0, peak_pull = 0, peak_torque = 0, max_loop = 0;
  hooks.on_step = [&](const Telemetry& t) {
    peak_push = std::max(peak_push, t.handle_force_N);
    peak_pull = std::max(peak_pull, -t.handle_force_N);
    peak_torque = std::max(peak_torque, std::abs(t.handle_torque_Nm));
    max_loop = std::max(max_loop, std::abs(t.loop_turns));
  };
  // --trace: a recorded insertion (docs/organ-identification.md, "The recording format")
  // with the telemetry after its columns: a row at the start state and one every
  // 1 / trace_hz simulated seconds. Each row is the step ending at its time with the input
  // commanded in that step (as colosim identify replays a row: identify/insertion/replay.h),
  // so that the trace plus sensor noise is a recording that replays to the noise.
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> trace(nullptr, &std::fclose);
  if (!o.trace.empty()) {
    trace.reset(std::fopen(o.trace.c_str(), "wx"));
    if (!trace) throw InputError(o.trace + ": cannot create the file");
    writeTraceHeader(trace.get(), scenario, sim);
    writeTraceRow(trace.get(), sim.telemetry());
    const long every = std::max(1L, std::lround(1.0 / (o.trace_hz * dt_s)));
    long done = 0;
    hooks.on_step = [&, every, done, record = hooks.on_step](const Telemetry& t) mutable {
      record(t);
      if (++done % every == 0) writeTraceRow(trace.get(), t);
    };
  }
  const std::shared_ptr<FrameExporter> frames = addFrameExport(hooks, o.frames, o.video, o.view, size, o.fps, dt_s);
  const RunResult r = runScenario(scenario, sim, writer.get(), hooks, steps);
  if (frames) frames->finish();
  bar.finish();
  // The solvers could not keep up somewhere: say so (the session has the events).
  if (r.scores.value("solver_limited_steps", 0L) > 0)
    std::fprintf(stderr, "colosim run %s: solver limits engaged in %ld steps (%ld episodes): forces or speeds beyond "
                 "what one step is trusted with were limited (docs/hardening.md)%s\n",
                 scenario.name.c_str(), r.scores["solver_limited_steps"].get<long>(),
                 r.scores["solver_limited_episodes"].get<long>(),
                 o.record.empty() ? "" : "; the session records each as a solver_limited event");
  // The scope was not where the contact model placed it somewhere: say so (core/lumen_check.h).
  if (r.scores.value("lumen_exit_steps", 0L) > 0)
    std::fprintf(stderr, "colosim run %s: a scope slice lay outside the lumen it is tracked in during %ld steps "
                 "(largest track jump %.4f m, deepest penetration %.4f m)\n",
                 scenario.name.c_str(), r.scores["lumen_exit_steps"].get<long>(),
                 r.scores["max_track_jump_m"].get<double>(), r.scores["max_wall_penetration_m"].get<double>());
  if (o.json) {
    std::cout << (o.score ? r.scores.dump() : nlohmann::json{{"scenario", scenario.name}, {"steps", r.steps},
                                                             {"final_state_hash", hashToHex(r.final_state_hash)}}
                                                  .dump())
              << "\n";
    return 0;
  }
  const Telemetry t = sim.telemetry();
  std::printf("colosim run %s: %ld steps (%.3f s at dt = %g s)\n", scenario.name.c_str(), r.steps, r.steps * dt_s,
              dt_s);
  if (!o.params.empty()) {
    std::printf("  parameters           %s: wall friction %.4g", o.params.c_str(),
                sim.model().contact.friction_coefficient);
    if (dropped_friction) std::printf(" (the scenario's override %.4g not applied)", *dropped_friction);
    std::printf(", colon bending %.4g N m^2, lifter stiffening %.4g 1/m^2\n", sim.model().colon.bending_EI_Nm2,
                sim.model().colon.mesentery_stiffening_per_m2);
  }
  if (sim.model().colon.tension_law->internalSize() > 0 || !o.tension_law.empty())
    printTensionLaw(*sim.model().colon.tension_law, o.tension_law.empty() ? o.params : o.tension_law);
  std::printf("  insertion at end     %8.3f m (tip %.3f m from the caecal pole)\n", t.input.insertion_m,
              t.tip_to_caecum_m);
  std::printf("  handle force         peak push %.2f N, peak pull %.2f N, peak torque %.3f N m\n", peak_push,
              peak_pull, peak_torque);
  std::printf("  loop                 largest %.2f turns, %.2f turns at the end\n", max_loop, t.loop_turns);
  std::printf("  contact topology     largest track jump %.4f m, deepest penetration %.4f m, %ld steps out of the lumen\n",
              r.scores["max_track_jump_m"].get<double>(), r.scores["max_wall_penetration_m"].get<double>(),
              r.scores["lumen_exit_steps"].get<long>());
  std::printf("  final state hash     %s\n", hashToHex(r.final_state_hash).c_str());
  if (!o.record.empty()) std::printf("  session recorded in  %s\n", o.record.c_str());
  if (!o.frames.empty()) std::printf("  frames written in    %s\n", o.frames.c_str());
  if (!o.video.empty()) std::printf("  video written in     %s (%ld frames)\n", o.video.c_str(), frames->frames());
  if (o.score) printScores(r.scores);
  return 0;
}

}  // namespace

void addRunCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a scenario's scripted inputs headless");
  cmd->add_option("SCENARIO", o->scenario,
                  "scenario file, or the name of one in assets/scenarios/; 'settle': the colon alone settling")
      ->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "simulated time [s] (default: the scenario's)")
      ->check(CLI::Range(1e-3, 1e5));
  cmd->add_option("--record", o->record, "record the session into this file (JSON Lines)");
  cmd->add_option("--frames", o->frames, "write PNG frames into this new or empty folder");
  cmd->add_option("--video", o->video, "encode the frames (at --fps, --view, --size) into this new video file "
                  "(H.264 in MP4 through FFmpeg; never overwrites a file)");
  cmd->add_option("--view", o->view, "which view the frames show")
      ->check(CLI::IsMember({"onboard", "global", "both"}))->capture_default_str();
  cmd->add_option("--fps", o->fps, "frames per simulated second")->check(CLI::Range(0.1, 1000.0))->capture_default_str();
  cmd->add_option("--size", o->size, "frame size WxH [px] (each view)")->capture_default_str();
  cmd->add_option("--trace", o->trace,
                  "write the telemetry (handle force and torque, tip, mesentery stretch, loop turns) as CSV "
                  "into this new file");
  cmd->add_option("--trace-hz", o->trace_hz, "trace rows per simulated second")
      ->check(CLI::Range(0.1, 1000.0))->capture_default_str();
  cmd->add_flag("--score", o->score, "print the scores of the run");
  cmd->add_flag("--json", o->json, "print one JSON object on stdout (the scores with --score)");
  cmd->add_option("--query", o->query, "contact queries: fcl, fcl:MANAGER or the paper's scan")
      ->capture_default_str();
  cmd->add_option("--tension-law", o->tension_law,
                  "tension law file for the colon's tension elements (written by colosim identify --law-out on a "
                  "tension test); replaces the parameter file's colon.tension_law");
  cmd->add_option("--threads", o->threads,
                  "2: each step's independent halves (the contact queries, the colon's and the scope's steps) on "
                  "two threads, for a run with a second core to itself; the same results bit for bit (scenarios "
                  "only)")
      ->check(CLI::Range(1, 2))
      ->capture_default_str();
  cmd->add_option("--dt", o->dt_s, "time step [s] (settle only)")->check(CLI::Range(1e-5, 1e-2))->capture_default_str();
  cmd->add_option("--params", o->params, "parameter file (for a scenario: replaces the one it names and its wall_friction "
                  "override, e.g. written by colosim identify --law-out on a recorded insertion: friction, colon bending, "
                  "lifter stiffening and tension law)");
  cmd->add_option("--scope", o->scope, "scope design file (assets/scopes/*.json) in place of the one the scenario "
                  "names; sessions record it");
  cmd->add_option("--anatomy", o->anatomy, "anatomy file (settle only; scenarios name their own)");
  cmd->callback([&action, o] {
    action = [o]() -> int { return o->scenario == "settle" ? runSettle(*o) : runScripted(*o); };
  });
}

}  // namespace colosim::app
