#include "identify/insertion/synthetic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace colosim {

std::pair<double, double> syntheticRange(const std::string& e) {
  if (e == "wall_friction") return {0.1, 0.3};
  if (e == "colon_bending") return {0.01, 0.05};
  if (e == "mesentery_stiffening") return {2000, 10000};
  if (e == "strain_stiffening") return {3.0, 8.0};
  if (e == "stress_relaxation") return {0.3, 0.6};
  if (e == "cyclic_softening") return {0.2, 0.5};
  if (e == "permanent_set") return {0.1, 0.3};
  throw std::invalid_argument("unknown organ effect '" + e + "'");
}

SyntheticInsertionSpec drawSyntheticInsertion(uint64_t seed, int effect_index, double duration_s, int cycles,
                                              int holds) {
  std::mt19937_64 rng(seed);
  auto U = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  SyntheticInsertionSpec s;
  s.seed = seed;
  s.duration_s = duration_s;
  if (effect_index >= 0) {
    s.effect = organEffectNames().at(effect_index);
    const auto r = syntheticRange(s.effect);
    s.value = std::exp(U(std::log(r.first), std::log(r.second)));
  }
  s.start_insertion_m = U(0.10, 0.15);
  s.push_speed_m_per_s = U(0.04, 0.08);
  s.pull_back_m = U(0.02, 0.04);
  s.rotation_amplitude_rad = U(0.2, 0.5);
  s.knob_updown_rad = U(0.1, 0.4);
  s.force_noise_N = U(0.03, 0.06);
  s.force_offset_N = U(-0.2, 0.2);
  s.torque_noise_Nm = U(0.001, 0.003);
  s.torque_offset_Nm = U(-0.01, 0.01);
  if (cycles > 0) {
    s.cycles = cycles;
    s.cycle_amplitude_m = U(0.06, 0.10);
    s.start_insertion_m = U(0.12, 0.18);
  } else if (holds > 0) {
    s.holds = holds;
    s.hold_step_m = U(0.04, 0.07);
    s.start_insertion_m = U(0.40, 0.50);
  }
  return s;
}

SyntheticInsertionSpec drawTwoRateInsertion(uint64_t seed, int effect_index, double duration_s) {
  SyntheticInsertionSpec s = drawSyntheticInsertion(seed, effect_index, duration_s);
  std::mt19937_64 rng(seed * 104729 + 3);
  auto U = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  s.two_rate = true;
  s.start_insertion_m = U(0.40, 0.50);
  s.slow_push_m = U(0.03, 0.05);
  s.fast_push_m = U(0.03, 0.05);
  s.pull_back_m = U(0.02, 0.04);
  s.rotation_amplitude_rad = U(0.1, 0.3);
  s.wiggle_hz = U(1.0, 2.0);
  s.knob_leftright_rad = U(-0.3, 0.3);
  return s;
}

InsertionRecording makeSyntheticInsertion(const ReplaySetup& setup, const SyntheticInsertionSpec& s) {
  std::mt19937_64 rng(s.seed * 7919 + 17);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  InsertionRecording r;
  r.scenario = s.scenario;
  r.has_tip = s.with_tip;
  // Irregular time base (+-5 %), from 0 to the duration.
  const double dt = 1.0 / s.sample_hz;
  for (double t = 0; t <= s.duration_s + 1e-9; t += dt * (1 + jitter(rng))) r.time_s.push_back(std::round(t * 1e4) / 1e4);
  // Protocol: push 45 % of the time, hold 10 %, pull back over 15 %, push again.
  const double T = s.duration_s;
  for (double t : r.time_s) {
    HandleInput in;
    const double d1 = s.push_speed_m_per_s * 0.45 * T;
    double ins;
    if (s.cycles > 0) ins = s.cycle_amplitude_m * (1 - std::cos(2 * M_PI * s.cycles * t / T)) / 2;
    else if (s.two_rate) {
      const double x = t / T;  // slow push, hold, quick push, hold, withdrawal
      ins = s.slow_push_m * std::min(1.0, x / 0.30) + s.fast_push_m * std::clamp((x - 0.45) / 0.10, 0.0, 1.0) -
            s.pull_back_m * std::clamp((x - 0.75) / 0.25, 0.0, 1.0);
    }
    else if (s.holds > 0) {
      // Stage i (of `holds`, each T / holds long): i steps done, the next pushed over the ramp.
      const double stage = T / s.holds;
      const int i = std::min(s.holds - 1, static_cast<int>(t / stage));
      const double ramp = std::clamp((t - i * stage) / (s.hold_ramp_fraction * stage), 0.0, 1.0);
      ins = s.hold_step_m * (i + ramp);
    }
    else if (t < 0.45 * T) ins = s.push_speed_m_per_s * t;
    else if (t < 0.55 * T) ins = d1;
    else if (t < 0.70 * T) ins = d1 - s.pull_back_m * (t - 0.55 * T) / (0.15 * T);
    else ins = d1 - s.pull_back_m + s.push_speed_m_per_s * (t - 0.70 * T);
    in.insertion_m = std::round((s.start_insertion_m + ins) * 1e6) / 1e6;
    const double turns = s.two_rate ? s.wiggle_hz * t : t / T;  // rotation cycles so far
    in.rotation_rad = std::round(s.rotation_amplitude_rad * std::sin(2 * M_PI * turns) * 1e5) / 1e5;
    in.knob_leftright_rad = std::round(s.knob_leftright_rad * std::min(1.0, t / (0.3 * T)) * 1e5) / 1e5;
    in.knob_updown_rad = std::round(s.knob_updown_rad * std::min(1.0, t / (0.3 * T)) * 1e5) / 1e5;
    r.input.push_back(in);
  }
  OrganParams hidden;
  if (!s.effect.empty()) setOrganEffect(hidden, s.effect, s.value);
  const Prediction truth = replayInsertion(setup, r, hidden);
  for (size_t k = 0; k < r.rows(); ++k) {
    r.force_N.push_back(std::round((truth.force_N[k] + s.force_offset_N + s.force_noise_N * n01(rng)) * 1e4) / 1e4);
    r.torque_Nm.push_back(
        std::round((truth.torque_Nm[k] + s.torque_offset_Nm + s.torque_noise_Nm * n01(rng)) * 1e5) / 1e5);
    if (s.with_tip) {
      Vec3 tip = truth.tip_m[k];
      for (int d = 0; d < 3; ++d) tip(d) = std::round((tip(d) + s.tip_noise_m * n01(rng)) * 1e5) / 1e5;
      r.tip_m.push_back(tip);
    }
  }
  char buf[256];
  r.metadata.push_back({"note", "SYNTHETIC: made by colosim's simulator (identify/insertion/synthetic.h), not measured"});
  std::snprintf(buf, sizeof buf, "%s%s%.6g", s.effect.empty() ? "none" : s.effect.c_str(), s.effect.empty() ? "" : " = ",
                s.value);
  r.metadata.push_back({"hidden_effect", s.effect.empty() ? std::string("none") : std::string(buf)});
  std::snprintf(buf, sizeof buf, "%.4g m control-point spacing, dt %.4g s, seed %llu", setup.params.colon.control_point_spacing_m,
                setup.dt_s, static_cast<unsigned long long>(s.seed));
  r.metadata.push_back({"simulated_with", buf});
  std::snprintf(buf, sizeof buf, "force %.4g N sd, offset %+.4g N; torque %.4g N m sd, offset %+.4g N m; tip %.4g m sd",
                s.force_noise_N, s.force_offset_N, s.torque_noise_Nm, s.torque_offset_Nm, s.tip_noise_m);
  r.metadata.push_back({"sensor_noise", buf});
  if (s.cycles > 0) {
    std::snprintf(buf, sizeof buf, "%d insert / withdraw cycles of %.4g m from %.4g m", s.cycles, s.cycle_amplitude_m,
                  s.start_insertion_m);
    r.metadata.push_back({"protocol", buf});
  } else if (s.two_rate) {
    std::snprintf(buf, sizeof buf,
                  "two rates from %.4g m: slow push %.4g m, quick push %.4g m, withdrawal %.4g m; rotation %.3g rad at "
                  "%.3g Hz, left-right knob %.3g rad",
                  s.start_insertion_m, s.slow_push_m, s.fast_push_m, s.pull_back_m, s.rotation_amplitude_rad,
                  s.wiggle_hz, s.knob_leftright_rad);
    r.metadata.push_back({"protocol", buf});
  } else if (s.holds > 0) {
    std::snprintf(buf, sizeof buf, "%d push-and-hold stages of %.4g m (pushed over %.3g of each) from %.4g m", s.holds,
                  s.hold_step_m, s.hold_ramp_fraction, s.start_insertion_m);
    r.metadata.push_back({"protocol", buf});
  }
  return r;
}

}  // namespace colosim
