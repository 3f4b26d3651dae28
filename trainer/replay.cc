#include "trainer/replay.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

#include "trainer/assets.h"
#include "trainer/score.h"
#include "trainer/strict_json.h"

namespace colosim {

SessionHeader sessionHeaderFor(const Scenario& scenario, const std::string& colosim_version) {
  SessionHeader h;
  h.scenario = scenario.id.empty() ? scenario.file : scenario.id;
  h.scenario_hash = scenario.file_hash;
  h.params_hash = hashFile(scenario.params_path);
  if (scenario.params_replaced) h.params = scenario.params_path;
  h.anatomy_hash = hashFile(scenario.anatomy_path);
  h.scope_hash = hashFile(scenario.scope_path);
  if (scenario.scope_replaced) h.scope = scenario.scope_path;
  h.colosim_version = colosim_version;
  h.dt_s = scenario.dt_s;
  h.seed = scenario.seed;
  h.mode = "scripted";
  if (scenario.patient_position_chosen && scenario.overrides.patient_position)
    h.patient_position = *scenario.overrides.patient_position;
  return h;
}

void stepAndRecord(Simulation& sim, const HandleInput& in, long step, Scorer& scorer, SessionWriter* writer,
                   const RunHooks& hooks) {
  if (writer) writer->input(step, in);
  sim.step(in);
  const long done = step + 1;
  const Telemetry t = sim.telemetry();
  scorer.add(t);
  if (writer) {
    for (const SimulationEvent& e : sim.events()) writer->event(done, e.name, e.detail);
    if (writer->checkpointDue(done)) writer->checkpoint(done, sim.stateHash());
  }
  if (hooks.on_step) hooks.on_step(t);
  if (hooks.on_frame && hooks.frame_every_steps > 0 && done % hooks.frame_every_steps == 0) hooks.on_frame(sim, done);
  if (hooks.on_progress && done % 1000 == 0) hooks.on_progress(done);
}

RunResult runScenario(const Scenario& scenario, Simulation& sim, SessionWriter* writer, const RunHooks& hooks,
                      long steps) {
  if (steps < 0) steps = scenario.steps();
  Scorer scorer(scenario.scoring);
  if (hooks.on_frame && hooks.frame_every_steps > 0) hooks.on_frame(sim, 0);
  for (long k = 0; k < steps; ++k) {
    // The input of step k is the script at the step's start time k dt.
    const HandleInput in = scriptedInput(scenario.script, static_cast<double>(k) * sim.dt_s());
    stepAndRecord(sim, in, k, scorer, writer, hooks);
  }
  RunResult r;
  r.steps = steps;
  r.final_state_hash = sim.stateHash();
  r.scores = scorer.json();
  if (writer) writer->end(steps, r.final_state_hash, nlohmann::json{{"scores", r.scores}});
  if (hooks.on_progress) hooks.on_progress(steps);
  return r;
}

ReplayPlan planReplay(const std::string& session_path) {
  ReplayPlan p;
  p.session = readSession(session_path);
  const SessionHeader& h = p.session.header;
  try {
    p.scenario = findScenario(h.scenario);
  } catch (const InputError& e) {
    throw InputError(session_path + ":1: scenario: " + e.what());
  }
  // A file the run used in place of the scenario's (header key `key`) must still exist.
  auto requireRecordedFile = [&](const std::string& key, const std::string& what, const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw InputError(session_path + ":1: " + key + ": the " + what + " " + path +
                       " the session was recorded with does not exist");
  };
  // The parameter file (colosim run --params) and the scope design (--scope) of the run.
  if (!h.params.empty()) {
    requireRecordedFile("params", "parameter file", h.params);
    useParameterFile(p.scenario, h.params);
  }
  if (!h.scope.empty()) {
    requireRecordedFile("scope", "scope design", h.scope);
    useScopeDesign(p.scenario, h.scope);
  }
  // The patient position the trainee chose on the trainer's start screen.
  if (!h.patient_position.empty()) choosePatientPosition(p.scenario, h.patient_position);
  // The recording's time step and seed rule (a run may have overridden the scenario's).
  p.scenario.dt_s = h.dt_s;
  p.scenario.seed = h.seed;
  auto warnIf = [&](bool changed, const std::string& what, const std::string& file) {
    if (changed)
      p.warnings.push_back(session_path + ":1: the " + what + " file " + file +
                           " has changed since the session was recorded: the replay may differ");
  };
  warnIf(p.scenario.file_hash != h.scenario_hash, "scenario", p.scenario.file);
  warnIf(hashFile(p.scenario.params_path) != h.params_hash, "parameter", p.scenario.params_path);
  warnIf(hashFile(p.scenario.anatomy_path) != h.anatomy_hash, "anatomy", p.scenario.anatomy_path);
  warnIf(h.scope_hash != 0 && hashFile(p.scenario.scope_path) != h.scope_hash, "scope design", p.scenario.scope_path);
  return p;
}

ReplayResult replay(const ReplayPlan& plan, Simulation& sim, const RunHooks& hooks) {
  const Session& s = plan.session;
  ReplayResult r;
  r.file = s.file;
  r.scenario = s.header.scenario;
  r.complete = s.complete;
  r.truncated = s.truncated;
  r.message = s.message;
  r.warnings = plan.warnings;
  Scorer scorer(plan.scenario.scoring);
  size_t next_input = 0, next_checkpoint = 0, next_assist = 0;
  HandleInput in;
  if (hooks.on_frame && hooks.frame_every_steps > 0) hooks.on_frame(sim, 0);
  for (long k = 0; k < s.steps; ++k) {
    while (next_input < s.inputs.size() && s.inputs[next_input].step == k) in = s.inputs[next_input++].input;
    // The assistance recorded from this step on (an unknown position: the reader refused it).
    while (next_assist < s.assists.size() && s.assists[next_assist].step == k) sim.assist(s.assists[next_assist++].assist);
    stepAndRecord(sim, in, k, scorer, nullptr, hooks);
    if (next_checkpoint < s.checkpoints.size() && s.checkpoints[next_checkpoint].step == k + 1) {
      const SessionCheckpoint& c = s.checkpoints[next_checkpoint++];
      ++r.checkpoints_checked;
      const uint64_t h = sim.stateHash();
      if (h != c.state_hash && r.mismatch.empty())
        r.mismatch = s.file + ":" + std::to_string(c.line) + ": state hash after step " + std::to_string(c.step) +
                     " is " + hashToHex(h) + ", the recording says " + hashToHex(c.state_hash);
    }
  }
  r.steps = s.steps;
  r.final_state_hash = sim.stateHash();
  if (s.complete) {
    r.final_hash_checked = true;
    if (r.final_state_hash != s.final_state_hash && r.mismatch.empty())
      r.mismatch = s.file + ":" + std::to_string(s.lines) + ": final state hash is " + hashToHex(r.final_state_hash) +
                   ", the recording says " + hashToHex(s.final_state_hash);
  }
  r.scores = scorer.json();
  if (hooks.on_progress) hooks.on_progress(s.steps);
  return r;
}

std::vector<ReplayResult> replaySessions(const std::vector<std::string>& session_paths,
                                         const SimulationFactory& factory, unsigned threads,
                                         const std::function<void(long, long)>& on_progress,
                                         const SessionHooksFactory& add_hooks) {
  // Read and check everything first: a bad file stops the batch before any work.
  std::vector<ReplayPlan> plans;
  plans.reserve(session_paths.size());
  long total_steps = 0;
  for (const std::string& p : session_paths) {
    plans.push_back(planReplay(p));
    total_steps += plans.back().session.steps;
    // An hour at 1 kHz holds millions of input records: keep only what the batch needs
    // and read each session again when its turn comes (memory: one session per thread).
    plans.back().session = Session{};
  }
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = std::min<unsigned>(threads, std::max<size_t>(1, plans.size()));

  std::vector<ReplayResult> results(plans.size());
  std::vector<std::exception_ptr> errors(plans.size());
  std::atomic<size_t> next{0};
  std::atomic<long> steps_done{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (size_t i = next++; i < plans.size(); i = next++) {
      try {
        const ReplayPlan plan = planReplay(session_paths[i]);
        std::unique_ptr<Simulation> sim = factory(plan.scenario);
        long reported = 0;
        RunHooks hooks;
        if (add_hooks) add_hooks(i, plan, hooks);
        hooks.on_progress = [&](long done) {
          const long all = steps_done += done - reported;
          reported = done;
          if (on_progress) {
            std::lock_guard<std::mutex> lock(progress_mutex);
            on_progress(all, total_steps);
          }
        };
        results[i] = replay(plan, *sim, hooks);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  // The first failure in the order given, whichever thread met it first.
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return results;
}

}  // namespace colosim
