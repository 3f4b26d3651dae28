#include "identify/tension/synthetic.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "identify/tension/forward.h"

namespace colosim {

namespace {

// Rounds to 1 / per_unit (per_unit a power of ten): the value the file's decimals hold.
double roundTo(double x, double per_unit) { return std::round(x * per_unit) / per_unit; }

// Commanded elongation at time t [m], piecewise linear along the protocol.
struct Command {
  std::vector<double> t, e;  // knots
  double at(double time) const {
    if (time <= t.front()) return e.front();
    if (time >= t.back()) return e.back();
    const size_t i = std::upper_bound(t.begin(), t.end(), time) - t.begin();
    const double a = (time - t[i - 1]) / (t[i] - t[i - 1]);
    return e[i - 1] + a * (e[i] - e[i - 1]);
  }
};

Command command(const SyntheticSpec& s) {
  Command c;
  c.t = {0.0, 2.0};  // 2 s at rest before the first ramp
  c.e = {0.0, 0.0};
  for (const ProtocolStep& p : s.protocol) {
    const double e0 = c.e.back();
    const double dur = p.speed_m_per_s > 0 ? std::abs(p.target_m - e0) / p.speed_m_per_s : p.duration_s;
    c.t.push_back(c.t.back() + std::max(dur, 1e-3));
    c.e.push_back(p.speed_m_per_s > 0 ? p.target_m : e0);
  }
  return c;
}

}  // namespace

double protocolDuration(const SyntheticSpec& s) { return command(s).t.back(); }

double uniformDraw(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

SyntheticSpec drawSyntheticSpec(uint64_t seed, const SyntheticDraw& draw) {
  std::mt19937_64 rng(seed);
  SyntheticSpec s;
  s.seed = seed;
  s.nominal_dt_s = draw.nominal_dt_s;
  s.sample_length_m = uniformDraw(rng, 0.16, 0.20);
  if (draw.sample_length_m > 0) s.sample_length_m = draw.sample_length_m;
  const double emax = draw.max_elongation_m > 0 ? draw.max_elongation_m : uniformDraw(rng, 0.09, 0.12);
  const double fmax = draw.max_force_N > 0 ? draw.max_force_N : uniformDraw(rng, 8.0, 13.0);
  const double smax = emax / s.sample_length_m;

  // Protocol: cycles of growing then varied amplitude, each a ramp up at one of three
  // speeds, a hold at the top, a ramp down into slight slack and a short hold.
  const double speeds[3] = {1.5e-3, 4e-3, 10e-3};  // [m/s]
  for (int c = 0; c < draw.cycles; ++c) {
    double amp = emax;
    if (c == 0) amp = 0.5 * emax;
    else if (c == 1) amp = 0.75 * emax;
    else if (c % 3 == 0) amp = uniformDraw(rng, 0.6, 0.9) * emax;
    const double up = speeds[std::uniform_int_distribution<int>(0, 2)(rng)];
    const double down = speeds[std::uniform_int_distribution<int>(0, 2)(rng)];
    s.protocol.push_back({amp, up, 0});
    s.protocol.push_back({0, 0, uniformDraw(rng, 15.0, 35.0)});
    s.protocol.push_back({-uniformDraw(rng, 0.0, 3e-3), down, 0});
    s.protocol.push_back({0, 0, uniformDraw(rng, 3.0, 8.0)});
  }
  s.actuator_tau_s = uniformDraw(rng, 0.1, 0.3);
  s.jitter = 0.05;
  s.offset_N = uniformDraw(rng, -0.15, 0.15);
  s.white_sd_N = uniformDraw(rng, 0.02, 0.05);
  s.coloured_sd_N = uniformDraw(rng, 0.2, 0.5) * s.white_sd_N;
  s.coloured_phi = 0.9;

  ExtendedLawParams& p = s.truth;
  for (const std::string& e : draw.effects) p.enable(e);
  p.ec_Ns = uniformDraw(rng, 0.02, 0.1);
  // Effect parameters (always drawn, so that the seed gives the same protocol and noise
  // whatever the effects).
  const double b = uniformDraw(rng, 1.5, 3.5);             // Fung exponent (Dou 2006, Terry 2014)
  const double g1 = uniformDraw(rng, 0.4, 0.55);           // relaxing fraction: 20-30 % by 10 s,
  const double tau1 = uniformDraw(rng, 8.0, 15.0);         // ~50 % by 300 s (Yang, Fung 2006)
  const double d_inf = uniformDraw(rng, 0.15, 0.35);       // preconditioning, equilibrium after
  const double cycles_to_eq = uniformDraw(rng, 10.0, 16.0);  // ~13 cycles (Terry 2014)
  const double set = uniformDraw(rng, 0.06, 0.15);
  if (p.strain_stiffening) p.fung_b = b;
  if (p.stress_relaxation) p.relax_g1 = g1, p.relax_tau1_s = tau1;
  if (p.cyclic_softening) p.soften_d_inf = d_inf, p.soften_a_c = cycles_to_eq * 0.9 * smax / 4.0;
  if (p.permanent_set) p.set_ratio = set;
  // EA so that the peak force of a slow first loading to emax is about fmax.
  p.ea_N = p.strain_stiffening ? fmax * b / std::expm1(b * smax) : fmax / smax;
  return s;
}

SyntheticSpec shippedSampleSpec(int sample) {
  SyntheticDraw draw;
  draw.effects = {"strain_stiffening", "stress_relaxation"};
  draw.nominal_dt_s = 0.2;
  draw.cycles = 11;
  draw.max_elongation_m = 0.12;
  draw.max_force_N = sample == 1 ? 14.0 : 13.0;
  draw.sample_length_m = 0.18;
  return drawSyntheticSpec(sample == 1 ? 8011 : 8022, draw);
}

TensionTest generateTensionTest(const SyntheticSpec& s) {
  std::mt19937_64 rng(s.seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Command cmd = command(s);
  const double t_end = cmd.t.back() + 3.0;

  // The true bench on a fine grid: actuator lag (exact first-order update), then the law.
  const double h = 5e-3;
  const size_t nf = static_cast<size_t>(std::ceil(t_end / h)) + 1;
  std::vector<double> tf(nf), ef(nf), strain(nf), rate(nf), force;
  double e_act = 0;
  const double a = std::exp(-h / s.actuator_tau_s);
  for (size_t k = 0; k < nf; ++k) {
    tf[k] = k * h;
    if (k > 0) e_act = a * e_act + (1 - a) * cmd.at(tf[k]);
    ef[k] = e_act;
    strain[k] = e_act / s.sample_length_m;
    rate[k] = k ? (strain[k] - strain[k - 1]) / h : 0.0;
  }
  const ExtendedTensionLaw law(s.truth);
  benchForce(law, 0.0, tf, strain, rate, &force);
  if (s.foreign_friction_N > 0)
    for (size_t k = 0; k < nf; ++k)
      if (force[k] > 0) force[k] += s.foreign_friction_N * std::tanh(rate[k] / 1e-3);

  // Sampling at irregular times, interpolating the fine grid; noise and offset.
  TensionTest t;
  t.sample_length_m = s.sample_length_m;
  t.metadata = {{"source", "synthetic: colosim generator (identify/tension/synthetic.h), seed " + std::to_string(s.seed)}};
  double time = 0, coloured = s.coloured_sd_N * normal(rng);
  const double innov = s.coloured_sd_N * std::sqrt(1 - s.coloured_phi * s.coloured_phi);
  while (time < t_end - h) {
    const double x = time / h;
    const size_t i = std::min(nf - 2, static_cast<size_t>(x));
    const double w = x - i;
    const double e = (1 - w) * ef[i] + w * ef[i + 1];
    const double f = (1 - w) * force[i] + w * force[i + 1];
    coloured = s.coloured_phi * coloured + innov * normal(rng);
    const double meas = s.offset_N + f + coloured + s.white_sd_N * normal(rng);
    t.time_s.push_back(roundTo(time, 1e4));
    t.elongation_m.push_back(roundTo(e, 1e6));
    t.force_N.push_back(roundTo(meas, 1e4));
    time += s.nominal_dt_s * (1 + s.jitter * (2 * uniformDraw(rng, 0, 1) - 1));
  }
  return t;
}

}  // namespace colosim
