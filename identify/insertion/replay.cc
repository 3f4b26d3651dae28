#include "identify/insertion/replay.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "core/input_error.h"
#include "trainer/start_state.h"
#include "trainer/world_simulation.h"

namespace colosim {

const std::vector<std::string>& organEffectNames() {
  static const std::vector<std::string> names = {"wall_friction", "colon_bending", "mesentery_stiffening",
                                                 "strain_stiffening", "stress_relaxation", "cyclic_softening",
                                                 "permanent_set"};
  return names;
}

int organEffectIndex(const std::string& effect) {
  const std::vector<std::string>& names = organEffectNames();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == effect) return static_cast<int>(i);
  return -1;
}

double organEffectValue(const OrganParams& p, const std::string& e) {
  if (e == "wall_friction") return p.friction;
  if (e == "colon_bending") return p.bending_EI_Nm2;
  if (e == "mesentery_stiffening") return p.stiffening_per_m2;
  if (e == "strain_stiffening") return p.fung_b;
  if (e == "stress_relaxation") return p.relax_g1;
  if (e == "cyclic_softening") return p.soften_d_inf;
  if (e == "permanent_set") return p.set_ratio;
  throw std::invalid_argument("unknown organ effect '" + e + "'");
}

void setOrganEffect(OrganParams& p, const std::string& e, double v) {
  if (e == "wall_friction") p.friction = v;
  else if (e == "colon_bending") p.bending_EI_Nm2 = v;
  else if (e == "mesentery_stiffening") p.stiffening_per_m2 = v;
  else if (e == "strain_stiffening") p.fung_b = v;
  else if (e == "stress_relaxation") p.relax_g1 = v;
  else if (e == "cyclic_softening") p.soften_d_inf = v;
  else if (e == "permanent_set") p.set_ratio = v;
  else throw std::invalid_argument("unknown organ effect '" + e + "'");
}

std::pair<std::string, std::string> organEffectParameter(const std::string& e) {
  if (e == "wall_friction") return {"friction_coefficient", "1"};
  if (e == "colon_bending") return {"bending_rigidity_Nm2", "N m^2"};
  if (e == "mesentery_stiffening") return {"mesentery_stiffening_per_m2", "1/m^2"};
  if (e == "strain_stiffening") return {"fung_b", "1"};
  if (e == "stress_relaxation") return {"relax_g1", "1"};
  if (e == "cyclic_softening") return {"soften_d_inf", "1"};
  if (e == "permanent_set") return {"set_ratio", "1"};
  throw std::invalid_argument("unknown organ effect '" + e + "'");
}

ReplaySetup makeReplaySetup(const Scenario& scenario, double spacing_m) {
  ReplaySetup s;
  s.scenario = scenario;
  s.dt_s = scenario.dt_s;
  // The parameters `colosim run` simulates the scenario with (its overrides applied); the
  // wall friction is then each replayed model's own (organParameters).
  s.params = scenarioParameters(scenario);
  if (spacing_m > 0) {
    s.params.colon.control_point_spacing_m = spacing_m;
    s.params.scope.segment_length_m = spacing_m;
  }
  return s;
}

Scenario recordingScenario(const InsertionRecording& rec) {
  Scenario scenario = findScenario(rec.scenario);
  if (!rec.params.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(rec.params, ec))
      throw InputError(rec.file + ": header key 'params': no such parameter file '" + rec.params + "'");
    useParameterFile(scenario, rec.params);
  }
  return scenario;
}

std::optional<ExtendedLawParams> organLawParams(const Parameters& params, const OrganParams& p) {
  if (!(p.fung_b > 0) && !(p.relax_g1 > 0) && !(p.soften_d_inf > 0) && !(p.set_ratio > 0)) return std::nullopt;
  ExtendedLawParams lp;
  lp.ea_N = params.colon.tension_EA_N;
  lp.ec_Ns = params.colon.tension_EC_Ns;
  if (p.fung_b > 0) {
    lp.enable("strain_stiffening");
    lp.fung_b = p.fung_b;
  }
  if (p.relax_g1 > 0) {
    lp.enable("stress_relaxation");
    lp.relax_g1 = p.relax_g1;
    lp.relax_tau1_s = kRelaxTau_s;
  }
  if (p.soften_d_inf > 0) {
    lp.enable("cyclic_softening");
    lp.soften_d_inf = p.soften_d_inf;
    lp.soften_a_c = kSoftenAc;
  }
  if (p.set_ratio > 0) {
    lp.enable("permanent_set");
    lp.set_ratio = p.set_ratio;
  }
  return lp;
}

Parameters organParameters(const Parameters& params, const OrganParams& p) {
  Parameters q = params;
  q.contact.friction_coefficient = p.friction;
  q.colon.bending_EI_Nm2 = p.bending_EI_Nm2;
  q.colon.mesentery_stiffening_per_m2 = p.stiffening_per_m2;
  q.tension_law = organLawParams(params, p);
  return q;
}

Prediction replayInsertion(const ReplaySetup& setup, const InsertionRecording& rec, const OrganParams& p,
                           const std::atomic<bool>* cancel) {
  // The simulation `colosim run` builds (WorldSimulation from the scenario and its
  // parameters, trainer/world_simulation.h), with the extensions of `p` in the parameter set
  // and the scope threaded to the recording's first input: a recording that `colosim run
  // --trace` made of the same model replays to the values it wrote. A scripted start's
  // set-up is part of the recording (colosim run traces it), so it is replayed, not redone.
  WorldModel model = loadWorldModel(setup.scenario.anatomy_path, organParameters(setup.params, p));
  const double dt = setup.dt_s;
  StartSpec start = startSpecOf(setup.scenario);
  start.dt_s = dt;
  if (setup.relax_s >= 0) start.relax_s = setup.relax_s;
  start.first_input = rec.input.front();
  WorldSimulation sim(std::move(model), start, "fcl");
  sim.measureHandleAndLoopOnly(true);  // the replay compares only these
  const WorldState& st = sim.state();
  Telemetry tel = sim.telemetry();

  Prediction out;
  const size_t n = rec.rows();
  out.force_N.resize(n);
  out.torque_Nm.resize(n);
  out.tip_m.resize(n);
  out.loop_turns.resize(n);
  // Step s (1, 2, ...) ends at s dt and takes the recorded input at its end time: a row of
  // colosim run --trace holds the step ending at its time and the input commanded in it.
  long step = 0;
  for (size_t k = 0; k < n; ++k) {
    // Steps whose end time reaches the row's time (recording time; 1 ns tolerance).
    while ((step * dt) < rec.time_s[k] - 1e-9) {
      if (cancel && cancel->load(std::memory_order_relaxed)) {
        out.ok = false;
        return out;
      }
      ++step;
      sim.step(recordedInput(rec, step * dt));
      tel = sim.telemetry();
      if (!st.colon.solver_ok || !st.scope.solver_ok) out.ok = false;
    }
    out.force_N[k] = tel.handle_force_N;
    out.torque_Nm[k] = tel.handle_torque_Nm;
    out.tip_m[k] = tel.tip_position_m;
    out.loop_turns[k] = tel.loop_turns;
    if (!std::isfinite(tel.handle_force_N) || !std::isfinite(tel.handle_torque_Nm)) out.ok = false;
  }
  return out;
}

}  // namespace colosim
