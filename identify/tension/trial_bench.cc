#include "identify/tension/trial_bench.h"

#include "identify/tension/synthetic.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace colosim {

namespace {

bool has(const TrialSpec& s, const char* effect) {
  return std::find(s.effects.begin(), s.effects.end(), effect) != s.effects.end();
}

// The commanded elongation as knots (time [s], elongation [m]), piecewise linear.
struct Knots {
  std::vector<double> t, e;
  void rampTo(double target_m, double speed_m_per_s) {
    t.push_back(t.back() + std::max(1e-3, std::abs(target_m - e.back()) / speed_m_per_s));
    e.push_back(target_m);
  }
  void hold(double seconds) {
    t.push_back(t.back() + seconds);
    e.push_back(e.back());
  }
  double at(double time) const {
    if (time <= t.front()) return e.front();
    if (time >= t.back()) return e.back();
    const size_t i = std::upper_bound(t.begin(), t.end(), time) - t.begin();
    return e[i - 1] + (time - t[i - 1]) / (t[i] - t[i - 1]) * (e[i] - e[i - 1]);
  }
};

// The protocol of a spec, drawn from its own stream so that it does not depend on the law.
Knots protocol(const TrialSpec& s, std::mt19937_64& rng) {
  Knots k;
  k.t = {0.0};
  k.e = {0.0};
  k.hold(uniformDraw(rng, 1.0, 3.0));
  const double top = s.max_strain * s.sample_length_m;  // [m]
  auto holdS = [&] { return uniformDraw(rng, 5.0, 15.0); };
  auto slack = [&] { return -uniformDraw(rng, 0.0, 2e-3); };
  if (s.protocol == "staircase") {
    // Up in n steps at the slow rate, down in n/2 steps, slack, up again at the fast rate.
    const int n = std::uniform_int_distribution<int>(4, 6)(rng);
    for (int i = 1; i <= n; ++i) k.rampTo(top * i / n, s.slow_speed_m_per_s), k.hold(holdS());
    const int m = n / 2;
    for (int i = m - 1; i >= 1; --i) k.rampTo(top * i / m, s.slow_speed_m_per_s), k.hold(holdS());
    k.rampTo(slack(), s.slow_speed_m_per_s);
    k.hold(uniformDraw(rng, 2.0, 5.0));
    for (int i = 1; i <= n; ++i) k.rampTo(top * i / n, s.fast_speed_m_per_s), k.hold(holdS());
    k.rampTo(slack(), s.fast_speed_m_per_s);
  } else {
    // Cycles of rising amplitude, alternating the two rates, each held at its top; then
    // two cycles at the largest amplitude, one at each rate.
    const int n = std::uniform_int_distribution<int>(4, 6)(rng);
    for (int c = 0; c < n + 2; ++c) {
      const double amp = c < n ? top * (0.35 + 0.65 * c / (n - 1)) : top;
      const double v = c % 2 ? s.fast_speed_m_per_s : s.slow_speed_m_per_s;
      k.rampTo(amp, v);
      k.hold(holdS());
      k.rampTo(slack(), v);
      k.hold(uniformDraw(rng, 2.0, 5.0));
    }
  }
  k.hold(2.0);
  return k;
}

// The hidden law along a strain history on a uniform grid of step h [s] (force [N]).
struct HiddenLaw {
  const TrialSpec& s;
  double e_prev = 0, e_max = 0, acc = 0, fs_prev = 0, h1 = 0, h2 = 0;

  double elastic(double e) const {
    double ep = 0;
    if (has(s, "permanent_set"))
      ep = s.forms == TrialForms::kOwn ? s.set_ratio * e_max : s.set_ratio * std::max(0.0, e_max - s.set_yield_strain);
    const double x = e - ep;
    double fe = s.ea_N * x;
    if (x > 0 && has(s, "strain_stiffening"))
      fe = s.forms == TrialForms::kOwn ? s.ea_N / s.fung_b * std::expm1(s.fung_b * x)
                                       : s.ea_N * (x + s.cubic_k * x * x * x);
    double d = 0;
    if (has(s, "cyclic_softening"))
      d = s.soften_d_inf * -std::expm1(-(s.forms == TrialForms::kOwn ? acc : e_max) / s.soften_scale);
    return (1 - d) * fe;
  }

  // Moves to strain e at rate edot over a step of h [s]; returns the force at the end.
  double step(double e, double edot, double h) {
    if (e > 0) acc += std::max(0.0, e - std::max(0.0, e_prev));
    e_max = std::max(e_max, e);
    e_prev = e;
    const double fs = elastic(e);
    double g_inf = 1;
    if (has(s, "stress_relaxation")) {
      const double x1 = h / s.relax_tau1_s, x2 = h / s.relax_tau2_s;
      h1 = std::exp(-x1) * h1 + s.relax_g1 * -std::expm1(-x1) / x1 * (fs - fs_prev);
      g_inf -= s.relax_g1;
      if (s.forms == TrialForms::kOther) {
        h2 = std::exp(-x2) * h2 + s.relax_g2 * -std::expm1(-x2) / x2 * (fs - fs_prev);
        g_inf -= s.relax_g2;
      }
    }
    fs_prev = fs;
    return g_inf * fs + h1 + h2 + s.ec_Ns * edot;
  }
};

}  // namespace

TrialSpec drawTrialSpec(uint64_t seed, const std::vector<std::string>& effects, TrialForms forms) {
  std::mt19937_64 rng(seed * 0x2545F4914F6CDD1DULL + 17);
  TrialSpec s;
  s.seed = seed;
  s.forms = forms;
  for (const char* e : {"strain_stiffening", "stress_relaxation", "cyclic_softening", "permanent_set"})
    if (std::find(effects.begin(), effects.end(), e) != effects.end()) s.effects.push_back(e);
  if (s.effects.size() != effects.size()) throw std::invalid_argument("drawTrialSpec: unknown or repeated effect");
  s.protocol = uniformDraw(rng, 0, 1) < 0.5 ? "staircase" : "rising_cycles";
  s.sample_length_m = uniformDraw(rng, 0.12, 0.22);
  s.max_strain = uniformDraw(rng, 0.35, 0.65);
  s.slow_speed_m_per_s = uniformDraw(rng, 3e-3, 6e-3);
  s.fast_speed_m_per_s = s.slow_speed_m_per_s * uniformDraw(rng, 3.0, 5.0);
  s.actuator_tau_s = uniformDraw(rng, 0.03, 0.3);
  s.sample_rate_hz = uniformDraw(rng, 50.0, 200.0);
  s.offset_N = uniformDraw(rng, -0.3, 0.3);
  s.white_sd_N = uniformDraw(rng, 0.01, 0.06);
  s.coloured_sd_N = uniformDraw(rng, 0.0, 0.5) * s.white_sd_N;
  const double fmax = uniformDraw(rng, 5.0, 15.0);  // force of the virgin curve at max_strain [N]
  s.ec_Ns = uniformDraw(rng, 0.01, 0.08);
  // Effect parameters, always drawn (the same seed, the same protocol and noise).
  const double stiff_ratio = uniformDraw(rng, 3.0, 8.0);  // tangent at max_strain / tangent at 0
  const double g1_other = uniformDraw(rng, 0.10, 0.20), tau1_other = uniformDraw(rng, 0.5, 2.0);
  const double g2_other = uniformDraw(rng, 0.15, 0.30), tau2_other = uniformDraw(rng, 15.0, 60.0);
  const double g1_own = uniformDraw(rng, 0.25, 0.45), tau1_own = uniformDraw(rng, 3.0, 15.0);
  const double d_inf = uniformDraw(rng, 0.15, 0.35);
  const double ec_over_max = uniformDraw(rng, 0.3, 0.6);      // e_c / max_strain (other)
  const double cycles_to_sat = uniformDraw(rng, 2.0, 5.0);    // loading strain to saturation / a_c (own)
  const double set = uniformDraw(rng, 0.08, 0.20);
  const double yield_over_max = uniformDraw(rng, 0.2, 0.5);
  const double smax = s.max_strain;
  double shape = smax;  // Fe(smax) / EA
  if (has(s, "strain_stiffening")) {
    if (forms == TrialForms::kOwn) {
      s.fung_b = std::log(stiff_ratio) / smax;
      shape = std::expm1(s.fung_b * smax) / s.fung_b;
    } else {
      s.cubic_k = (stiff_ratio - 1) / (3 * smax * smax);
      shape = smax + s.cubic_k * smax * smax * smax;
    }
  }
  s.ea_N = fmax / shape;
  if (has(s, "stress_relaxation")) {
    if (forms == TrialForms::kOwn) s.relax_g1 = g1_own, s.relax_tau1_s = tau1_own;
    else s.relax_g1 = g1_other, s.relax_tau1_s = tau1_other, s.relax_g2 = g2_other, s.relax_tau2_s = tau2_other;
  }
  if (has(s, "cyclic_softening")) {
    s.soften_d_inf = d_inf;
    if (forms == TrialForms::kOwn) {
      // a_c from the protocol's accumulated loading strain (a protocol draw of its own).
      std::mt19937_64 prng(seed ^ 0x51ed2701a3b4c5d6ULL);
      const Knots k = protocol(s, prng);
      double total = 0;
      for (size_t i = 1; i < k.e.size(); ++i) total += std::max(0.0, std::max(0.0, k.e[i]) - std::max(0.0, k.e[i - 1]));
      s.soften_scale = total / s.sample_length_m / cycles_to_sat;
    } else {
      s.soften_scale = ec_over_max * smax;
    }
  }
  if (has(s, "permanent_set")) {
    s.set_ratio = set;
    if (forms == TrialForms::kOther) s.set_yield_strain = yield_over_max * smax;
  }
  return s;
}

TensionTest generateTrialTest(const TrialSpec& s) {
  std::mt19937_64 prng(s.seed ^ 0x51ed2701a3b4c5d6ULL);
  const Knots cmd = protocol(s, prng);
  std::mt19937_64 rng(s.seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> normal(0.0, 1.0);

  // The bench on a 1 ms grid: a critically damped actuator (x'' = (u - x) / tau^2 - 2 x' / tau,
  // semi-implicit Euler), then the hidden law.
  const double h = 1e-3;
  const size_t nf = static_cast<size_t>(std::ceil(cmd.t.back() / h)) + 1;
  std::vector<double> ef(nf), force(nf);
  double x = 0, v = 0;
  HiddenLaw law{s};
  const double tau = s.actuator_tau_s;
  for (size_t k = 0; k < nf; ++k) {
    const double t = k * h;
    const double x_old = x;
    if (k > 0) {
      v += h * ((cmd.at(t) - x) / (tau * tau) - 2 * v / tau);
      x += h * v;
    }
    ef[k] = x;
    const double e = x / s.sample_length_m;
    const double edot = k ? (x - x_old) / h / s.sample_length_m : 0.0;
    force[k] = std::max(0.0, law.step(e, edot, h));
  }

  // Sampling: intervals of 1 / rate +-10 %, time stamps off by up to +-10 % of an interval,
  // coloured noise with a correlation time of 0.1 s, 1 um encoder, 0.1 mN and 0.1 ms digits.
  TensionTest t;
  t.sample_length_m = s.sample_length_m;
  t.metadata = {{"source", "synthetic: colosim trial bench (identify/tension/trial_bench.h), seed " +
                               std::to_string(s.seed)}};
  const double dt = 1.0 / s.sample_rate_hz;
  const double phi = std::exp(-dt / 0.1);
  double coloured = s.coloured_sd_N * normal(rng);
  double time = 0;
  const double t_end = (nf - 1) * h;
  while (time < t_end) {
    const double xi = time / h;
    const size_t i = std::min(nf - 2, static_cast<size_t>(xi));
    const double w = xi - i;
    const double e = (1 - w) * ef[i] + w * ef[i + 1];
    const double f = (1 - w) * force[i] + w * force[i + 1];
    coloured = phi * coloured + s.coloured_sd_N * std::sqrt(1 - phi * phi) * normal(rng);
    const double stamp = time + 0.1 * dt * uniformDraw(rng, -1, 1);
    if (t.time_s.empty() || std::round(stamp * 1e4) / 1e4 > t.time_s.back()) {
      t.time_s.push_back(std::round(std::max(0.0, stamp) * 1e4) / 1e4);
      t.elongation_m.push_back(std::round(e * 1e6) / 1e6);
      t.force_N.push_back(std::round((s.offset_N + f + coloured + s.white_sd_N * normal(rng)) * 1e4) / 1e4);
    }
    time += dt * uniformDraw(rng, 0.9, 1.1);
  }
  return t;
}

}  // namespace colosim
