#include "trainer/lumen_following.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/scope_step.h"
#include "core/spline.h"
#include "trainer/world_simulation.h"

namespace colosim {

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

std::string format(const char* fmt, double a, double b, double c, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

}  // namespace

HandleInput steerTowardsLumen(const WorldSimulation& sim, double tip_arclength_m, const HandleInput& cur,
                              double lookahead_m, double max_knob_change_rad) {
  const ScopeModel& sm = sim.model().scope;
  const WorldState& st = sim.state();
  HandleInput next = cur;
  // The knobs turn the tip from the shaft behind the bending section, so the direction to
  // the target is read in that segment's frame.
  if (st.scope.inside <= sm.bending_joints + 1) return next;
  const Vec3 tip = tipPosition(sm, st.scope);
  const Vec3 target = centrelineAt(sim.model().colon, st.colon.q, tip_arclength_m + lookahead_m);
  const Mat3& S = st.scope.R_WS[sm.bending_joints];
  const Vec3 u = S.transpose() * (target - tip).normalized();
  const double lateral = std::hypot(u.x(), u.y());
  if (lateral <= 1e-9) return next;
  const double theta = std::atan2(lateral, u.z());
  // Within the design's knob stops.
  const double ud_max = sm.params.knob_updown_max_rad, lr_max = sm.params.knob_leftright_max_rad;
  const double up = std::clamp(theta * u.y() / lateral, -ud_max, ud_max);
  const double lr = std::clamp(-theta * u.x() / lateral, -lr_max, lr_max);
  const double dk = max_knob_change_rad;
  next.knob_updown_rad = round4(cur.knob_updown_rad + std::clamp(up - cur.knob_updown_rad, -dk, dk));
  next.knob_leftright_rad = round4(cur.knob_leftright_rad + std::clamp(lr - cur.knob_leftright_rad, -dk, dk));
  return next;
}

LumenFollowing::LumenFollowing(const WorldSimulation& sim, const LumenFollowingOptions& options) : o_(options) {
  const ScopeModel& sm = sim.model().scope;
  max_in_m_ = (sm.segment_count - 1) * sm.h_m;
  window_ = static_cast<size_t>(std::lround(o_.window_s / o_.key_dt_s)) + 1;
}

Keyframe LumenFollowing::next(const WorldSimulation& sim, double t, const HandleInput& cur,
                              const std::function<void(const std::string&)>& log) {
  const WorldState& st = sim.state();
  const Telemetry tel = sim.telemetry();
  const double L = cur.insertion_m, s_tip = tel.tip_arclength_m;
  history_.emplace_back(L, s_tip);
  if (history_.size() > window_) history_.pop_front();
  HandleInput next = cur;
  const HandleInput steered = steerTowardsLumen(sim, s_tip, cur, o_.lookahead_m, o_.max_knob_change_rad);
  next.knob_updown_rad = steered.knob_updown_rad;
  next.knob_leftright_rad = steered.knob_leftright_rad;
  auto advanceAgain = [&](const char* why) {
    mode_ = kAdvance;
    history_.clear();
    if (log) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "t %.1f s: advance%s (insertion %.3f m, tip %.3f m, handle %.1f N)", t, why, L,
                    s_tip, st.scope.handle.force_N);
      log(buf);
    }
  };
  if (tel.tip_to_caecum_m < o_.done_m) mode_ = kDone;
  if (mode_ == kAdvance) {
    const double dL = L - history_.front().first, ds = s_tip - history_.front().second;
    const bool looping =
        history_.size() == window_ && dL - ds > o_.loop_m && ds < dL / 3 && L - s_tip > 0.05 && L > 0.3;
    // At the end of the working length with the tip stalled: take the slack out.
    const bool stalled_at_end = history_.size() == window_ && L > max_in_m_ - 0.005 && std::abs(ds) < 0.01;
    if (looping || stalled_at_end) {
      mode_ = kWithdraw;
      paused_ = 0;
      withdraw_from_L_ = L, withdraw_from_s_ = s_tip;
      ++withdrawals_;
      if (log)
        log(format("t %.1f s: withdraw (insertion %.3f m, tip %.3f m, slack %.3f m)", t, L, s_tip, L - s_tip));
    }
  } else if (mode_ == kWithdraw && (withdraw_from_L_ - L >= o_.withdraw_m || s_tip < withdraw_from_s_ - o_.back_m)) {
    advanceAgain("");
  }
  // An expert does not pull harder than pull_max_N: the withdrawal pauses while the handle
  // pulls more than that, and after 2 s of pausing it advances again.
  if (mode_ == kWithdraw) {
    const bool pulling_hard = st.scope.handle.force_N < -o_.pull_max_N;
    if (!pulling_hard) {
      next.insertion_m = round4(std::max(0.0, L - o_.speed_m_per_s * o_.key_dt_s));
    } else if (++paused_ >= 4) {
      advanceAgain(" after pulling hard");
    }
  }
  if (mode_ == kAdvance) next.insertion_m = round4(std::min(max_in_m_, L + o_.speed_m_per_s * o_.key_dt_s));
  Keyframe kf;
  kf.t_s = round4(t + o_.key_dt_s);
  kf.input = next;
  return kf;
}

long runWithLumenSteering(Scenario& sc, WorldSimulation& sim, double from_s, double key_dt_s, double lookahead_m,
                          double max_knob_change_rad, const std::function<void(const WorldSimulation&)>& on_step) {
  const std::vector<Keyframe> planned = sc.script;
  // The decision times: the grid from from_s and the script's own keyframes after from_s.
  std::vector<double> times;
  for (long i = 1; from_s + i * key_dt_s < sc.duration_s - 1e-9; ++i) times.push_back(round4(from_s + i * key_dt_s));
  for (const Keyframe& k : planned)
    if (k.t_s > from_s + 1e-9 && k.t_s < sc.duration_s - 1e-9) times.push_back(k.t_s);
  times.push_back(sc.duration_s);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
              times.end());
  auto onPath = [&](double t_s) {
    Keyframe k;
    k.t_s = t_s;
    k.input = scriptedInput(planned, t_s);
    k.input.insertion_m = std::round(k.input.insertion_m * 1e6) / 1e6;
    k.input.rotation_rad = std::round(k.input.rotation_rad * 1e6) / 1e6;
    return k;
  };
  sc.script.erase(std::remove_if(sc.script.begin(), sc.script.end(), [&](const Keyframe& k) { return k.t_s >= from_s; }),
                  sc.script.end());
  sc.script.push_back(onPath(from_s));
  long k = 0;
  auto stepUntil = [&](double t_s) {
    for (const long until = std::lround(t_s / sim.dt_s()); k < until; ++k) {
      sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
      if (on_step) on_step(sim);
    }
  };
  stepUntil(from_s);
  for (double t : times) {
    Keyframe kf = onPath(t);
    const HandleInput steered =
        steerTowardsLumen(sim, sim.telemetry().tip_arclength_m, sc.script.back().input, lookahead_m, max_knob_change_rad);
    kf.input.knob_updown_rad = steered.knob_updown_rad;
    kf.input.knob_leftright_rad = steered.knob_leftright_rad;
    sc.script.push_back(kf);
    stepUntil(t);
  }
  return k;
}

long runLumenFollowing(Scenario& sc, WorldSimulation& sim, double from_s, double end_s,
                       const LumenFollowingOptions& options, const LumenFollowingHooks& hooks) {
  // The script up to from_s, then a keyframe at from_s with the input in force there.
  const HandleInput at_from = scriptedInput(sc.script, from_s);
  sc.script.erase(std::remove_if(sc.script.begin(), sc.script.end(), [&](const Keyframe& k) { return k.t_s >= from_s; }),
                  sc.script.end());
  Keyframe first;
  first.t_s = from_s;
  first.input = at_from;
  sc.script.push_back(first);
  long k = 0;
  auto stepUntil = [&](double t_s) {
    const long until = std::lround(t_s / sim.dt_s());
    for (; k < until; ++k) {
      sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
      if (hooks.on_step) hooks.on_step(sim);
    }
  };
  stepUntil(std::min(from_s, end_s));
  LumenFollowing controller(sim, options);
  for (double t = from_s; t < end_s - 1e-9; t += options.key_dt_s) {
    const HandleInput cur = sc.script.back().input;
    if (hooks.on_decision) hooks.on_decision(t, cur);
    Keyframe kf = controller.next(sim, t, cur, hooks.log);
    if (options.stiffness_level >= 0 && kf.t_s >= options.stiffen_from_s)
      kf.input.stiffness_level = options.stiffness_level;
    sc.script.push_back(kf);
    stepUntil(hooks.step_to_last_keyframe ? kf.t_s : std::min(kf.t_s, end_s));
  }
  sc.duration_s = sc.script.back().t_s;
  return k;
}

}  // namespace colosim
