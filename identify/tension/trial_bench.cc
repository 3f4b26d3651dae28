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

// Elastic curve of the harder stiffening forms per unit EA: Fe(x) / EA for x > 0 [-].
double harderStiffShape(const TrialSpec& s, double x) {
  if (s.stiff_form == "power") return x * (1 + s.power_c * std::pow(x, s.power_p));
  // Toe and linear region: tangent 1 up to x_t, rising linearly to R over the width w, R beyond.
  const double xt = s.toe_strain, w = s.toe_width, r = s.linear_ratio;
  if (x <= xt) return x;
  if (x <= xt + w) return x + (r - 1) * (x - xt) * (x - xt) / (2 * w);
  return xt + w + (r - 1) * w / 2 + r * (x - xt - w);
}

// The hidden law along a strain history on a uniform grid of step h [s] (force [N]).
struct HiddenLaw {
  const TrialSpec& s;
  double e_prev = 0, e_max = 0, acc = 0, fs_prev = 0, h1 = 0, h2 = 0;
  // Harder forms: the damage and the set as state, the Maxwell branch forces.
  double d_state = 0, ep_state = 0, acc_yield = 0;
  std::vector<double> hb = std::vector<double>(s.prony_g.size(), 0.0);

  double elastic(double e) const {
    if (s.forms == TrialForms::kHarder) {
      const double x = e - ep_state;
      const double fe = x > 0 && has(s, "strain_stiffening") ? s.ea_N * harderStiffShape(s, x) : s.ea_N * x;
      return (1 - d_state) * fe;
    }
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

  // The harder forms' damage and set move to strain e (rate edot [1/s]) over a step of h [s];
  // e_prev is the strain before the step; e_max, acc and de_load (the loading strain of the
  // step) include it.
  void advanceHarder(double e, double edot, double h, double de_load) {
    // At rest: the strain is not rising (below 1e-3 1/s; an actuator settling into a hold
    // creeps on for ever).
    const bool rest = edot <= 1e-3;
    if (has(s, "cyclic_softening")) {
      const double driver = s.soften_form == "recovering_accumulated" ? acc : e_max;
      const double d_star = s.soften_d_inf * -std::expm1(-driver / s.soften_scale);
      if (de_load > 0) d_state += std::max(0.0, d_star - d_state) * std::min(1.0, de_load / s.soften_reload_strain);
      const double floor = (1 - s.soften_q) * d_star;
      if (rest && d_state > floor) d_state += (floor - d_state) * -std::expm1(-h / s.soften_rec_tau_s);
    }
    if (has(s, "permanent_set")) {
      if (s.set_form == "shakedown_ratchet") {
        acc_yield += std::max(0.0, e - std::max(std::max(0.0, e_prev), s.set_yield_strain));
        ep_state = s.set_ratchet_c * s.set_shakedown_strain * -std::expm1(-acc_yield / s.set_shakedown_strain);
      } else {
        if (de_load > 0) ep_state = std::max(ep_state, s.set_ratio * std::max(0.0, e - s.set_yield_strain));
        const double floor = (1 - s.set_q) * s.set_ratio * std::max(0.0, e_max - s.set_yield_strain);
        if (e < ep_state && ep_state > floor) ep_state += (floor - ep_state) * -std::expm1(-h / s.set_rec_tau_s);
      }
    }
  }

  // Moves to strain e at rate edot over a step of h [s]; returns the force at the end.
  double step(double e, double edot, double h) {
    const double de_load = e > 0 ? std::max(0.0, e - std::max(0.0, e_prev)) : 0.0;
    acc += de_load;
    e_max = std::max(e_max, e);
    if (s.forms == TrialForms::kHarder) advanceHarder(e, edot, h, de_load);
    e_prev = e;
    const double fs = elastic(e);
    double g_inf = 1;
    if (has(s, "stress_relaxation") && s.forms == TrialForms::kHarder) {
      double sum = 0;
      for (size_t i = 0; i < hb.size(); ++i) {
        const double x = h / s.prony_tau_s[i];
        hb[i] = std::exp(-x) * hb[i] + s.prony_g[i] * -std::expm1(-x) / x * (fs - fs_prev);
        g_inf -= s.prony_g[i];
        sum += hb[i];
      }
      fs_prev = fs;
      return g_inf * fs + sum + s.ec_Ns * edot;
    }
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

// Strain the protocol of a spec adds while loading (sum of its ramps' increases of the
// positive strain) [-], counting only what lies above the strain `above` [-].
double loadingStrain(const TrialSpec& s, double above) {
  std::mt19937_64 prng(s.seed ^ 0x51ed2701a3b4c5d6ULL);
  const Knots k = protocol(s, prng);
  double total = 0;
  for (size_t i = 1; i < k.e.size(); ++i)
    total += std::max(0.0, k.e[i] / s.sample_length_m - std::max(above, k.e[i - 1] / s.sample_length_m));
  return total;
}

// The harder forms of a spec (forms = kHarder), drawn after everything the other and own
// forms draw (so those stay as they were): the form of each effect and its parameters,
// always all of them (the same seed, the same forms in every class). Sets EA so that the
// virgin curve reaches fmax [N] at the largest strain.
void harderForms(TrialSpec* sp, std::mt19937_64& rng, double stiff_ratio, double d_inf, double ec_over_max,
                 double cycles_to_sat, double set, double yield_over_max, double fmax) {
  TrialSpec& s = *sp;
  const double smax = s.max_strain;
  const bool power = uniformDraw(rng, 0, 1) < 0.5;
  const double power_p = uniformDraw(rng, 1.2, 4.0);
  const double toe_over_max = uniformDraw(rng, 0.15, 0.4), width_over_max = uniformDraw(rng, 0.1, 0.3);
  const bool box = uniformDraw(rng, 0, 1) < 0.5;
  const double g_total = uniformDraw(rng, 0.3, 0.5);
  const double tau_lo = uniformDraw(rng, 0.3, 1.0), tau_hi = uniformDraw(rng, 30.0, 100.0);
  const int branches = std::uniform_int_distribution<int>(4, 6)(rng);
  std::vector<double> branch_tau(6), branch_w(6);
  for (int i = 0; i < 6; ++i)
    branch_tau[i] = std::exp(uniformDraw(rng, std::log(0.3), std::log(100.0))), branch_w[i] = uniformDraw(rng, 0.5, 1.5);
  const bool accumulated = uniformDraw(rng, 0, 1) < 0.5;
  const double soften_q = uniformDraw(rng, 0.3, 0.7), soften_tau = uniformDraw(rng, 10.0, 40.0);
  const bool ratchet = uniformDraw(rng, 0, 1) < 0.5;
  const double set_q = uniformDraw(rng, 0.3, 0.7), set_tau = uniformDraw(rng, 1.0, 4.0);

  double shape = smax;  // Fe(smax) / EA
  if (has(s, "strain_stiffening")) {
    s.stiff_form = power ? "power" : "toe_linear";
    if (power) {
      s.power_p = power_p;
      s.power_c = (stiff_ratio - 1) / ((power_p + 1) * std::pow(smax, power_p));  // tangent at smax: ratio EA
    } else {
      s.toe_strain = toe_over_max * smax;
      s.toe_width = width_over_max * smax;
      s.linear_ratio = stiff_ratio;  // reached before smax (x_t + w <= 0.7 smax)
    }
    shape = harderStiffShape(s, smax);
  }
  s.ea_N = fmax / shape;
  if (has(s, "stress_relaxation")) {
    s.relax_form = box ? "box_spectrum" : "branches";
    if (box) {
      // Fung's QLV box spectrum, discretised: 24 branches of equal weight, log-spaced times.
      constexpr int kBox = 24;
      for (int i = 0; i < kBox; ++i) {
        s.prony_tau_s.push_back(tau_lo * std::pow(tau_hi / tau_lo, (i + 0.5) / kBox));
        s.prony_g.push_back(g_total / kBox);
      }
    } else {
      std::vector<std::pair<double, double>> b;
      double wsum = 0;
      for (int i = 0; i < branches; ++i) b.push_back({branch_tau[i], branch_w[i]}), wsum += branch_w[i];
      std::sort(b.begin(), b.end());
      for (const auto& [tau, w] : b) s.prony_tau_s.push_back(tau), s.prony_g.push_back(g_total * w / wsum);
    }
  }
  if (has(s, "cyclic_softening")) {
    s.soften_form = accumulated ? "recovering_accumulated" : "recovering_largest";
    s.soften_d_inf = d_inf;
    s.soften_scale = accumulated ? loadingStrain(s, 0.0) / cycles_to_sat : ec_over_max * smax;
    s.soften_q = soften_q;
    s.soften_rec_tau_s = soften_tau;
    s.soften_reload_strain = 0.05 * smax;
  }
  if (has(s, "permanent_set")) {
    s.set_form = ratchet ? "shakedown_ratchet" : "recovering";
    s.set_ratio = set;
    s.set_yield_strain = yield_over_max * smax;
    if (ratchet) {
      // The shakedown's e-folds over the test, from a generator of their own so that every
      // other draw stays as it was before the ratchet shook down.
      std::mt19937_64 own(s.seed * 0x9E3779B97F4A7C15ULL + 101);
      const double efolds = uniformDraw(own, 1.0, 3.0);
      s.set_shakedown_strain = std::max(1e-9, loadingStrain(s, s.set_yield_strain)) / efolds;
      // The test ends with a set of r times the largest strain.
      s.set_ratchet_c = set * smax / (-std::expm1(-efolds) * s.set_shakedown_strain);
    } else {
      s.set_q = set_q, s.set_rec_tau_s = set_tau;
    }
  }
}

}  // namespace

std::string TrialSpec::formNames() const {
  if (forms == TrialForms::kOwn) return "own";
  if (forms == TrialForms::kOther) return "other";
  std::string n;
  for (const std::string* f : {&stiff_form, &relax_form, &soften_form, &set_form})
    if (!f->empty()) n += (n.empty() ? "" : "+") + *f;
  return n.empty() ? "none" : n;
}

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
  if (forms == TrialForms::kHarder) harderForms(&s, rng, stiff_ratio, d_inf, ec_over_max, cycles_to_sat, set,
                                                 yield_over_max, fmax);
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
