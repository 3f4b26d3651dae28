// colosim bench untwist: sigmoid_untwist headless without frames, the real-time factor
// at dt = 1 ms (simulated seconds per wall second), and what recording a session and
// replaying it cost on top of simulating. The simulation is the one colosim runs:
// colon, scope and their contacts with FCL queries (trainer/world_simulation.h).
#include <chrono>
#include <cstdio>
#include <algorithm>
#include <filesystem>
#include <vector>

#include <unistd.h>

#include "bench/registry.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

namespace colosim {

namespace {

// Times blocks of 1000 steps through the progress hook; the real-time factor is the
// simulated time of a block over its median wall time (robust on a shared machine).
struct BlockTimer {
  std::vector<double> block_s;
  long last_done = 0;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  RunHooks hooks() {
    RunHooks h;
    h.on_progress = [this](long done) {
      const auto now = std::chrono::steady_clock::now();
      if (done - last_done == 1000) block_s.push_back(std::chrono::duration<double>(now - last).count());
      last_done = done;
      last = now;
    };
    return h;
  }
  double realtimeFactor(double dt_s) {
    std::nth_element(block_s.begin(), block_s.begin() + block_s.size() / 2, block_s.end());
    return 1000 * dt_s / block_s[block_s.size() / 2];
  }
};

}  // namespace

BenchOutput benchUntwist() {
  const Scenario sc = findScenario("sigmoid_untwist");
  const double simulated_s = sc.steps() * sc.dt_s;
  const std::string session = (std::filesystem::temp_directory_path() /
                               ("colosim-bench-untwist-" + std::to_string(::getpid()) + ".jsonl")).string();
  // 1. Simulation and scoring only.
  BlockTimer plain, record, replaying, two_lanes;
  uint64_t hash_one = 0, hash_two = 0;
  {
    WorldSimulation sim(sc);
    runScenario(sc, sim, nullptr, plain.hooks());
    hash_one = sim.stateHash();
  }
  // 1b. The same on two lanes (WorldSimulation::useTwoLanes): the same final state.
  {
    WorldSimulation sim(sc);
    sim.useTwoLanes(true);
    runScenario(sc, sim, nullptr, two_lanes.hooks());
    hash_two = sim.stateHash();
  }
  // 2. The same, recording the session.
  {
    WorldSimulation sim(sc);
    SessionWriter w(session, sessionHeaderFor(sc, "bench"));
    runScenario(sc, sim, &w, record.hooks());
  }
  const auto session_bytes = std::filesystem::file_size(session);
  // 3. Replaying it (re-simulating, checking the hashes, scoring; reading is done first).
  const ReplayPlan plan = planReplay(session);
  WorldSimulation sim(plan.scenario);
  const ReplayResult r = replay(plan, sim, replaying.hooks());
  std::filesystem::remove(session);
  const double rtf = plain.realtimeFactor(sc.dt_s), rtf_record = record.realtimeFactor(sc.dt_s),
               rtf_replay = replaying.realtimeFactor(sc.dt_s), rtf_lanes = two_lanes.realtimeFactor(sc.dt_s);

  BenchOutput out;
  out.json = {{"benchmark", "untwist"},
              {"simulation", "world (colon, scope, FCL contacts)"},
              {"dt_s", sc.dt_s},
              {"simulated_s", simulated_s},
              {"realtime_factor", rtf},
              {"realtime_factor_recording", rtf_record},
              {"realtime_factor_replay", rtf_replay},
              {"realtime_factor_two_lanes", rtf_lanes},
              {"two_lanes_same_state", hash_one == hash_two},
              {"recording_cost_ratio", rtf / rtf_record},
              {"session_bytes", session_bytes},
              {"replay_hash_ok", r.hashOk()}};
  char text[768];
  std::snprintf(text, sizeof text,
                "sigmoid_untwist, %.0f s simulated at dt = %g s, colon + scope + contacts\n"
                "(median over blocks of 1000 steps)\n"
                "  real-time factor            %8.2f (simulation and scoring)\n"
                "  real-time factor recording  %8.2f (session file %.2f MB; cost ratio %.3f)\n"
                "  real-time factor replaying  %8.2f (hashes %s)\n"
                "  real-time factor, two lanes %8.2f (simulation and scoring; state %s)\n",
                simulated_s, sc.dt_s, rtf, rtf_record, session_bytes / 1e6, rtf / rtf_record, rtf_replay,
                r.hashOk() ? "reproduced" : "DIFFER", rtf_lanes, hash_one == hash_two ? "identical" : "DIFFERENT");
  out.text = text;
  return out;
}

}  // namespace colosim
