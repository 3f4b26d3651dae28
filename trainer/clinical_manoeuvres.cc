#include "trainer/clinical_manoeuvres.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

namespace colosim {

bool HookedUntwist::stays() const { return writhe_end * writhe_start > 0 && std::abs(writhe_end) > 0.5; }

HookedUntwist hookedUntwist(const Parameters& params, double rotation_scale) {
  Scenario sc = findScenario("sigmoid_untwist");
  for (Keyframe& k : sc.script) {
    k.input.rotation_rad *= rotation_scale;
    k.input.knob_updown_rad = 2.5;  // the tip hooked from the start (the script's steering replaced)
    k.input.knob_leftright_rad = 0.0;
  }
  WorldSimulation sim(sc, params);
  HookedUntwist o;
  const long steps = std::lround(12.0 / sim.dt_s());
  double tip_at_start_m = 0;
  for (long k = 0; k < steps; ++k) {
    sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
    const Telemetry t = sim.telemetry();
    if (k + 1 == std::lround(2.0 / sim.dt_s())) {
      o.writhe_start = t.loop_writhe;
      tip_at_start_m = t.tip_arclength_m;
    }
    o.peak_torque_Nm = std::max(o.peak_torque_Nm, std::abs(t.handle_torque_Nm));
    if (t.solver_limited > 0) ++o.limited_steps;
  }
  o.writhe_end = sim.telemetry().loop_writhe;
  o.tip_back_m = tip_at_start_m - sim.telemetry().tip_arclength_m;
  return o;
}

HookedWithdrawal hookedWithdrawal(const Parameters& params, double withdraw_m, double withdraw_s, double turn_rad) {
  Scenario sc = findScenario("free_insertion");
  const double t0 = 30.0;
  std::vector<Keyframe> script;
  for (const Keyframe& k : sc.script)
    if (k.t_s <= t0) script.push_back(k);
  Keyframe k = script.back();
  k.t_s = t0 + 1.0;
  k.input.knob_updown_rad = 2.5;
  script.push_back(k);
  k.t_s = t0 + 1.0 + withdraw_s;
  k.input.insertion_m -= withdraw_m;
  k.input.rotation_rad += turn_rad;
  script.push_back(k);
  k.t_s += 3.0;
  script.push_back(k);
  sc.script = script;
  sc.abdominal_pressure.clear();
  sc.duration_s = k.t_s;
  WorldSimulation sim(sc, params);
  int sigmoid = -1;
  for (size_t r = 0; r < sim.model().colon.region_names.size(); ++r)
    if (sim.model().colon.region_names[r] == "sigmoid") sigmoid = static_cast<int>(r);
  if (sigmoid < 0) throw std::runtime_error("hookedWithdrawal: the anatomy of free_insertion has no sigmoid region");
  HookedWithdrawal w;
  double tip_at_hook = 0;
  w.sigmoid_least = 1e9;
  const long hook_step = std::lround(t0 / sim.dt_s());
  for (long i = 0; i < sc.steps(); ++i) {
    sim.step(scriptedInput(sc.script, static_cast<double>(i) * sim.dt_s()));
    if (i + 1 < hook_step) continue;
    const Telemetry t = sim.telemetry();
    if (i + 1 == hook_step) {
      w.sigmoid_before = t.region_length_ratio[sigmoid];
      tip_at_hook = t.tip_arclength_m;
    }
    w.sigmoid_least = std::min(w.sigmoid_least, t.region_length_ratio[sigmoid]);
    if (t.solver_limited > 0) ++w.limited_steps;
  }
  w.tip_back_m = tip_at_hook - sim.telemetry().tip_arclength_m;
  return w;
}

Scenario everythingAtOnce(double time_scale, double knob_scale) {
  Scenario sc = findScenario(assetPath("scenarios/extreme/extreme_all.json"));
  sc.duration_s *= time_scale;
  for (Keyframe& k : sc.script) {
    k.t_s *= time_scale;
    k.input.knob_updown_rad *= knob_scale;
    k.input.knob_leftright_rad *= knob_scale;
  }
  return sc;
}

}  // namespace colosim
