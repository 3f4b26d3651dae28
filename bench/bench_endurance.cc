// colosim bench endurance [--hours H]: H hours (default 1) of simulated, cyclic scripted
// use of the colon + scope + contacts simulation (insert and withdraw, rotate, both
// knobs), stepped through the same stepAndRecord and scoring as colosim run (no session
// file). Every window of simulated time (a minute, or a quarter of a short run) it notes
// the mechanical energy's minimum and maximum, the largest kinetic energy, the resident
// memory (VmRSS, VmHWM from /proc/self/status) and the steps per wall second, so that
// "energy bounded, memory flat" can be read off the first and last windows (issue 8,
// docs/hardening.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "bench/registry.h"
#include "core/colon_step.h"
#include "core/numbers.h"
#include "core/scope_step.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/score.h"
#include "trainer/world_simulation.h"

namespace colosim {

namespace {

// The cyclic use, period 60 s [SI]: the scope pushed from 5 cm to 65 cm at 2.4 cm/s
// (25 s), held 5 s, withdrawn at the same pace, held 5 s; the handle rolled +-1.2 rad
// every 8 s; the up/down knob +-1.2 rad every 6 s and the left/right knob +-0.8 rad every
// 10 s; all start at zero but the depth (5 cm), where the scope starts. A clinical pace:
// nothing here should engage a solver limit.
HandleInput cyclicUse(double t_s) {
  const double c = std::fmod(t_s, 60.0);
  double depth_m;
  if (c < 25.0) depth_m = 0.05 + 0.60 * c / 25.0;
  else if (c < 30.0) depth_m = 0.65;
  else if (c < 55.0) depth_m = 0.65 - 0.60 * (c - 30.0) / 25.0;
  else depth_m = 0.05;
  HandleInput in;
  in.insertion_m = depth_m;
  in.rotation_rad = 1.2 * std::sin(2 * kPi * t_s / 8.0);
  in.knob_updown_rad = 1.2 * std::sin(2 * kPi * t_s / 6.0);
  in.knob_leftright_rad = 0.8 * std::sin(2 * kPi * t_s / 10.0);
  return in;
}

// VmRSS and VmHWM of this process [kB] (0 when /proc is not there).
void residentMemory_kB(long* rss, long* hwm) {
  *rss = *hwm = 0;
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line)) {
    std::istringstream in(line);
    std::string key;
    long v = 0;
    in >> key >> v;
    if (key == "VmRSS:") *rss = v;
    if (key == "VmHWM:") *hwm = v;
  }
}

struct Window {
  double t_end_s = 0;
  double energy_min_J = 1e300, energy_max_J = -1e300, kinetic_max_J = 0;
  long rss_kB = 0, hwm_kB = 0;
  double steps_per_s = 0;
  long limited_steps = 0;
};

}  // namespace

BenchOutput benchEndurance(const BenchOptions& options) {
  const double hours = options.hours;
  // The adult colon with the default parameters, settled for 2 s, the scope in at the
  // cycle's start (no jump at the first step).
  Scenario sc = findScenario("free_insertion");
  sc.script = {Keyframe{0.0, cyclicUse(0.0)}};
  WorldSimulation sim(sc);
  const double dt = sim.dt_s();
  const long steps = std::lround(hours * 3600.0 / dt);
  const double window_s = std::min(60.0, std::max(dt, hours * 3600.0 / 4));
  const long window_steps = std::max(1L, std::lround(window_s / dt));
  Scorer scorer(sc.scoring);
  long rss0 = 0, hwm0 = 0;
  residentMemory_kB(&rss0, &hwm0);

  std::vector<Window> windows;
  Window w;
  bool finite = true;
  long first_nonfinite_step = -1;
  double e_min = 1e300, e_max = -1e300, k_max = 0;
  const auto start = std::chrono::steady_clock::now();
  auto window_start = start;
  for (long k = 0; k < steps; ++k) {
    stepAndRecord(sim, cyclicUse(k * dt), k, scorer, nullptr);
    const WorldModel& m = sim.model();
    const WorldState& s = sim.state();
    const double kinetic = colonEnergy(m.colon, s.colon).kinetic_J + scopeKineticEnergy(m.scope, s.scope);
    const double energy = colonEnergy(m.colon, s.colon).total() + scopeKineticEnergy(m.scope, s.scope);
    if (!std::isfinite(energy) && finite) finite = false, first_nonfinite_step = k + 1;
    w.energy_min_J = std::min(w.energy_min_J, energy);
    w.energy_max_J = std::max(w.energy_max_J, energy);
    w.kinetic_max_J = std::max(w.kinetic_max_J, kinetic);
    if (sim.telemetry().solver_limited > 0) ++w.limited_steps;
    if ((k + 1) % window_steps == 0 || k + 1 == steps) {
      const auto now = std::chrono::steady_clock::now();
      const long n = (k + 1) % window_steps == 0 ? window_steps : (k + 1) % window_steps;
      w.t_end_s = (k + 1) * dt;
      w.steps_per_s = n / std::chrono::duration<double>(now - window_start).count();
      residentMemory_kB(&w.rss_kB, &w.hwm_kB);
      e_min = std::min(e_min, w.energy_min_J);
      e_max = std::max(e_max, w.energy_max_J);
      k_max = std::max(k_max, w.kinetic_max_J);
      windows.push_back(w);
      std::fprintf(stderr, "endurance: %.0f of %.0f s simulated, energy %.4f..%.4f J, RSS %ld kB, %.0f steps/s\n",
                   w.t_end_s, steps * dt, w.energy_min_J, w.energy_max_J, w.rss_kB, w.steps_per_s);
      w = Window();
      window_start = now;
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  long rss1 = 0, hwm1 = 0;
  residentMemory_kB(&rss1, &hwm1);

  BenchOutput out;
  nlohmann::json per_window = nlohmann::json::array();
  for (const Window& x : windows)
    per_window.push_back({{"t_end_s", x.t_end_s},
                          {"energy_min_J", x.energy_min_J},
                          {"energy_max_J", x.energy_max_J},
                          {"kinetic_max_J", x.kinetic_max_J},
                          {"rss_kB", x.rss_kB},
                          {"hwm_kB", x.hwm_kB},
                          {"steps_per_s", x.steps_per_s},
                          {"solver_limited_steps", x.limited_steps}});
  const Window& first = windows.front();
  const Window& last = windows.back();
  out.json = {{"benchmark", "endurance"},
              {"hours", hours},
              {"simulated_s", steps * dt},
              {"steps", steps},
              {"dt_s", dt},
              {"wall_s", wall_s},
              {"steps_per_s", steps / wall_s},
              {"finite", finite},
              {"first_nonfinite_step", first_nonfinite_step},
              {"energy_min_J", e_min},
              {"energy_max_J", e_max},
              {"kinetic_max_J", k_max},
              {"first_window", {{"energy_min_J", first.energy_min_J}, {"energy_max_J", first.energy_max_J}}},
              {"last_window", {{"energy_min_J", last.energy_min_J}, {"energy_max_J", last.energy_max_J}}},
              {"window_s", window_steps * dt},
              {"rss_kB_start", rss0},
              {"hwm_kB_start", hwm0},
              {"rss_kB_first_window", first.rss_kB},
              {"rss_kB_end", rss1},
              {"hwm_kB_end", hwm1},
              {"solver_limited_steps", scorer.solverLimitedSteps()},
              {"solver_limited_episodes", scorer.solverLimitedEpisodes()},
              {"windows", per_window}};
  std::ostringstream t;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "endurance: %.4g h (%.0f s) of cyclic scripted use (free_insertion's colon and scope, dt = %g s)\n"
                "  %ld steps in %.1f s of wall time: %.0f steps/s (real-time factor %.2f)\n"
                "  state finite: %s; solver limits engaged in %ld steps\n"
                "  mechanical energy (colon + scope kinetic) %.5f .. %.5f J; kinetic at most %.5f J\n"
                "  first window %.5f .. %.5f J, last window %.5f .. %.5f J\n"
                "  memory: VmRSS %ld kB at the start, %ld kB after the first window, %ld kB at the end;"
                " VmHWM %ld -> %ld kB\n",
                hours, steps * dt, dt, steps, wall_s, steps / wall_s, steps * dt / wall_s, finite ? "yes" : "NO",
                scorer.solverLimitedSteps(), e_min, e_max, k_max, first.energy_min_J, first.energy_max_J,
                last.energy_min_J, last.energy_max_J, rss0, first.rss_kB, rss1, hwm0, hwm1);
  t << buf << "  window end [s]   energy min..max [J]     kinetic max [J]   VmRSS [kB]  steps/s\n";
  for (const Window& x : windows) {
    std::snprintf(buf, sizeof buf, "  %12.0f   %9.5f .. %9.5f   %12.6f   %10ld  %7.0f\n", x.t_end_s, x.energy_min_J,
                  x.energy_max_J, x.kinetic_max_J, x.rss_kB, x.steps_per_s);
    t << buf;
  }
  out.text = t.str();
  return out;
}

}  // namespace colosim
