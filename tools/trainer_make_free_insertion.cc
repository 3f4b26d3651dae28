// Writes a scripted insertion by driving the simulation with a lumen-following "expert":
//   trainer_make_free_insertion TEMPLATE.json OUT.json [END_S]
// TEMPLATE is a scenario (anatomy, parameters, start, overrides, abdominal pressure; its
// script is replaced). Every 0.5 s the controller decides the next keyframe from the state:
// the knobs point the tip at the colon centreline LOOKAHEAD_M ahead of it (as an
// endoscopist steers towards the lumen; at most 0.4 rad of change per keyframe); the
// insertion advances at 2 cm/s. It withdraws at 2 cm/s, steering on (the hooked withdrawal
// that takes a loop out), when over the last WINDOW_S the tip gained less than a third of
// the scope pushed in and LOOP_M less in all (with more than 5 cm of slack), or when the
// scope is at the end of its working length with the tip still; it advances again after
// WITHDRAW_M came out or once the tip has come back BACK_M. It stops advancing once the
// tip is within 2.5 cm of the caecal pole. The simulation is stepped with the script's own
// interpolation (scriptedInput), so OUT.json replays the same run (colosim run OUT.json).
// The settings are environment variables (defaults: LOOKAHEAD_M 0.05, WINDOW_S 10,
// LOOP_M 0.15, WITHDRAW_M 0.3, BACK_M 0.02; PULL_MAX_N, off by default: the withdrawal
// pauses while the handle pulls harder, and after 2 s of pausing it advances again); VERBOSE=1 prints the state every 10 s.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/scope_step.h"
#include "core/spline.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

namespace {

double round4(double x) { return std::round(x * 1e4) / 1e4; }

// The current centreline point at rest arclength s [m].
Vec3 centrelineAt(const ColonModel& m, const Points& q, double s) {
  s = std::clamp(s, 0.0, m.length_m());
  int j = 0;
  while (j + 2 < m.n && m.s_rest_m(j + 1) <= s) ++j;
  const double p = std::clamp((s - m.s_rest_m(j)) / m.segment_length_m(j), 0.0, 1.0);
  return splinePoint(q, j, p);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s TEMPLATE.json OUT.json [END_S]\n", argv[0]);
    return 2;
  }
  const double end_s = argc > 3 ? std::atof(argv[3]) : 180.0;
  Scenario sc = findScenario(argv[1]);
  sc.script.resize(1);
  sc.script[0].t_s = 0;
  sc.script[0].input = HandleInput();
  WorldSimulation sim(sc);
  const ScopeModel& sm = sim.model().scope;
  const ColonModel& cm = sim.model().colon;
  auto knob = [](const char* name, double fallback) {
    const char* v = std::getenv(name);
    return v ? std::atof(v) : fallback;
  };
  const double key_dt = 0.5, speed = 0.02, max_in = (sm.segment_count - 1) * sm.h_m;
  const double lookahead_m = knob("LOOKAHEAD_M", 0.05), window_s = knob("WINDOW_S", 10.0);
  const double loop_m = knob("LOOP_M", 0.15), withdraw_m = knob("WITHDRAW_M", 0.30), back_m = knob("BACK_M", 0.02);
  const double pull_max_N = knob("PULL_MAX_N", 1e9);
  const size_t window = static_cast<size_t>(std::lround(window_s / key_dt)) + 1;
  enum { kAdvance, kWithdraw, kDone } mode = kAdvance;
  std::deque<std::pair<double, double>> history;  // (insertion, tip arclength) per keyframe, over WINDOW_S
  double withdraw_from_L = 0, withdraw_from_s = 0;
  long k = 0;
  int withdrawals = 0, paused = 0;
  for (double t = 0; t < end_s - 1e-9; t += key_dt) {
    const WorldState& st = sim.state();
    const Telemetry tel = sim.telemetry();
    const HandleInput cur = sc.script.back().input;
    const double L = cur.insertion_m, s_tip = tel.tip_arclength_m;
    history.emplace_back(L, s_tip);
    if (history.size() > window) history.pop_front();
    HandleInput next = cur;
    // Steering: the knobs that turn the tip (from the shaft behind the bending section)
    // towards the centreline LOOKAHEAD_M ahead.
    if (st.scope.inside > sm.bending_joints + 1) {
      const Vec3 tip = tipPosition(sm, st.scope);
      const Vec3 target = centrelineAt(cm, st.colon.q, s_tip + lookahead_m);
      const Mat3& S = st.scope.R_WS[sm.bending_joints];
      const Vec3 u = S.transpose() * (target - tip).normalized();
      const double lateral = std::hypot(u.x(), u.y());
      if (lateral > 1e-9) {
        const double theta = std::atan2(lateral, u.z());
        const double up = std::clamp(theta * u.y() / lateral, -kKnobUpDownMax_rad, kKnobUpDownMax_rad);
        const double lr = std::clamp(-theta * u.x() / lateral, -kKnobLeftRightMax_rad, kKnobLeftRightMax_rad);
        next.knob_updown_rad = round4(cur.knob_updown_rad + std::clamp(up - cur.knob_updown_rad, -0.4, 0.4));
        next.knob_leftright_rad = round4(cur.knob_leftright_rad + std::clamp(lr - cur.knob_leftright_rad, -0.4, 0.4));
      }
    }
    if (std::getenv("VERBOSE") && std::fmod(t, 10.0) < 1e-9)
      std::printf("t %.1f s: insertion %.3f m, tip %.3f m along the colon, %.3f m from the pole, handle %.1f N, knobs %.2f %.2f\n",
                  t, L, s_tip, tel.tip_to_caecum_m, st.scope.handle.force_N, cur.knob_updown_rad, cur.knob_leftright_rad);
    auto advanceAgain = [&](const char* why) {
      mode = kAdvance;
      history.clear();
      std::printf("t %.1f s: advance%s (insertion %.3f m, tip %.3f m, handle %.1f N)\n", t, why, L, s_tip,
                  st.scope.handle.force_N);
    };
    if (tel.tip_to_caecum_m < 0.025) mode = kDone;
    if (mode == kAdvance) {
      const double dL = L - history.front().first, ds = s_tip - history.front().second;
      const bool looping = history.size() == window && dL - ds > loop_m && ds < dL / 3 && L - s_tip > 0.05 && L > 0.3;
      // At the end of the working length with the tip stalled: take the slack out.
      const bool stalled_at_end = history.size() == window && L > max_in - 0.005 && std::abs(ds) < 0.01;
      if (looping || stalled_at_end) {
        mode = kWithdraw;
        paused = 0;
        withdraw_from_L = L, withdraw_from_s = s_tip;
        ++withdrawals;
        std::printf("t %.1f s: withdraw (insertion %.3f m, tip %.3f m, slack %.3f m)\n", t, L, s_tip, L - s_tip);
      }
    } else if (mode == kWithdraw && (withdraw_from_L - L >= withdraw_m || s_tip < withdraw_from_s - back_m)) {
      advanceAgain("");
    }
    // An expert does not pull harder than PULL_MAX_N: the withdrawal pauses while the handle
    // pulls more than that, and after 2 s of pausing it advances again.
    if (mode == kWithdraw) {
      const bool pulling_hard = st.scope.handle.force_N < -pull_max_N;
      if (!pulling_hard) {
        next.insertion_m = round4(std::max(0.0, L - speed * key_dt));
      } else if (++paused >= 4) {
        advanceAgain(" after pulling hard");
      }
    }
    if (mode == kAdvance) next.insertion_m = round4(std::min(max_in, L + speed * key_dt));
    Keyframe kf;
    kf.t_s = round4(t + key_dt);
    kf.input = next;
    sc.script.push_back(kf);
    const long until = std::lround(kf.t_s / sim.dt_s());
    for (; k < until; ++k) sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
  }
  const Telemetry tel = sim.telemetry();
  std::printf("end %.1f s: insertion %.3f m, tip %.3f m along the colon, %.3f m from the caecal pole, %d withdrawals, "
              "hash %016llx\n",
              sim.time_s(), sc.script.back().input.insertion_m, tel.tip_arclength_m, tel.tip_to_caecum_m, withdrawals,
              static_cast<unsigned long long>(sim.stateHash()));
  // The template with its script replaced.
  std::ifstream in(argv[1]);
  nlohmann::json j = nlohmann::json::parse(in);
  j["duration_s"] = sc.script.back().t_s;
  nlohmann::json script = nlohmann::json::array();
  for (const Keyframe& f : sc.script)
    script.push_back({{"t_s", f.t_s}, {"insertion_m", f.input.insertion_m}, {"rotation_rad", f.input.rotation_rad},
                      {"knob_updown_rad", f.input.knob_updown_rad}, {"knob_leftright_rad", f.input.knob_leftright_rad}});
  j["script"] = script;
  std::ofstream(argv[2]) << j.dump(1) << "\n";
  return 0;
}
