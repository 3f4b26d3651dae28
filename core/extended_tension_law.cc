#include "core/extended_tension_law.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace colosim {

namespace {

// Beyond b x = kMaxExponent the Fung curve continues along its tangent: finite forces for
// any strain a colon element could be pulled to, and a monotone, continuous law.
constexpr double kMaxExponent = 30.0;

// Elastic force Fe(x) of eq. Fe in the header and its derivative [N].
void fung(double ea, bool stiffening, double b, double x, double* f, double* df, double max_exp = kMaxExponent) {
  if (!stiffening || x <= 0 || b <= 0) {
    *f = ea * x;
    *df = ea;
    return;
  }
  const double bx = std::min(b * x, max_exp);
  const double ex = std::exp(bx);
  *f = ea / b * (ex - 1.0) + ea * ex * (x - bx / b);  // second term zero below the cap
  *df = ea * ex;
}

// Energy of Fe per unit rest length, the integral of Fe from 0 to x [N].
double fungEnergy(double ea, bool stiffening, double b, double x, double max_exp = kMaxExponent) {
  if (!stiffening || x <= 0 || b <= 0) return 0.5 * ea * x * x;
  const double xc = std::min(x, max_exp / b);
  const double ec = std::exp(b * xc);
  double w = ea / b * ((ec - 1.0) / b - xc);
  if (x > xc) {
    const double fc = ea / b * (ec - 1.0), kc = ea * ec, d = x - xc;
    w += fc * d + 0.5 * kc * d * d;
  }
  return w;
}

// c = (1 - exp(-x)) / x, with its limit 1 at x -> 0.
double relaxWeight(double x) { return x < 1e-8 ? 1.0 - 0.5 * x : -std::expm1(-x) / x; }
// The same with exp(-x) known (one transcendental per branch and step).
double relaxWeight(double x, double em) { return x < 1e-4 ? 1.0 - 0.5 * x + x * x / 6.0 : (1.0 - em) / x; }

enum Z { kEPrev = 0, kFsPrev = 1, kH1 = 2, kH2 = 3, kAcc = 4, kEMax = 5, kScale = 6, kDFsPrev = 7, kAccYield = 8 };

}  // namespace

const std::vector<std::string>& tensionEffectNames() {
  static const std::vector<std::string> names = {"strain_stiffening", "stress_relaxation",
                                                 "cyclic_softening", "permanent_set"};
  return names;
}

std::vector<std::string> ExtendedLawParams::effects() const {
  std::vector<std::string> out;
  if (strain_stiffening) out.push_back("strain_stiffening");
  if (stress_relaxation) out.push_back("stress_relaxation");
  if (cyclic_softening) out.push_back("cyclic_softening");
  if (permanent_set) out.push_back("permanent_set");
  return out;
}

void ExtendedLawParams::enable(const std::string& effect) {
  if (effect == "strain_stiffening") strain_stiffening = true;
  else if (effect == "stress_relaxation") stress_relaxation = true;
  else if (effect == "cyclic_softening") cyclic_softening = true;
  else if (effect == "permanent_set") permanent_set = true;
  else throw std::invalid_argument("unknown tension effect '" + effect + "'");
}

bool ExtendedLawParams::set(const std::string& name, double v) {
  if (name == "EA_N") ea_N = v;
  else if (name == "EC_Ns") ec_Ns = v;
  else if (name == "fung_b") fung_b = v;
  else if (name == "relax_g1") relax_g1 = v;
  else if (name == "relax_tau1_s") relax_tau1_s = v;
  else if (name == "relax_g2") relax_g2 = v, prony_terms = 2;
  else if (name == "relax_tau2_s") relax_tau2_s = v, prony_terms = 2;
  else if (name == "soften_d_inf") soften_d_inf = v;
  else if (name == "soften_a_c") soften_a_c = v;
  else if (name == "set_ratio") set_ratio = v;
  else if (name == "set_yield_strain") set_yield_strain = v, set_yield = true;
  else if (name == "set_ratchet") set_ratchet = v, set_ratcheting = true;
  else if (name == "fung_cap_strain") fung_cap_strain = v, fung_capped = true;
  else return false;
  return true;
}

void ExtendedLawParams::validate() const {
  auto check = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("tension law parameter out of range: ") + what);
  };
  check(std::isfinite(ea_N) && ea_N > 0, "EA_N must be positive");
  check(std::isfinite(ec_Ns) && ec_Ns >= 0, "EC_Ns must be non-negative");
  if (strain_stiffening) check(std::isfinite(fung_b) && fung_b >= 0 && fung_b <= 50, "fung_b in [0, 50]");
  if (strain_stiffening && fung_capped)
    check(std::isfinite(fung_cap_strain) && fung_cap_strain > 0 && fung_cap_strain <= 100, "fung_cap_strain in (0, 100]");
  if (stress_relaxation) {
    check(prony_terms == 1 || prony_terms == 2, "prony_terms is 1 or 2");
    check(std::isfinite(relax_g1) && relax_g1 >= 0 && relax_g1 < 1, "relax_g1 in [0, 1)");
    check(std::isfinite(relax_tau1_s) && relax_tau1_s > 0, "relax_tau1_s must be positive");
    if (prony_terms == 2) {
      check(std::isfinite(relax_g2) && relax_g2 >= 0 && relax_g1 + relax_g2 < 1,
            "relax_g2 >= 0 and relax_g1 + relax_g2 < 1");
      check(std::isfinite(relax_tau2_s) && relax_tau2_s > 0, "relax_tau2_s must be positive");
    }
  }
  if (cyclic_softening) {
    check(std::isfinite(soften_d_inf) && soften_d_inf >= 0 && soften_d_inf < 1, "soften_d_inf in [0, 1)");
    check(std::isfinite(soften_a_c) && soften_a_c > 0, "soften_a_c must be positive");
  }
  if (permanent_set) {
    check(std::isfinite(set_ratio) && set_ratio >= 0 && set_ratio < 1, "set_ratio in [0, 1)");
    if (set_yield)
      check(std::isfinite(set_yield_strain) && set_yield_strain >= 0 && set_yield_strain <= 10,
            "set_yield_strain in [0, 10]");
    if (set_ratcheting) check(std::isfinite(set_ratchet) && set_ratchet >= 0 && set_ratchet < 1, "set_ratchet in [0, 1)");
  }
}

ExtendedTensionLaw::ExtendedTensionLaw(const ExtendedLawParams& p) : p_(p) {
  p_.validate();
  any_ = p_.strain_stiffening || p_.stress_relaxation || p_.cyclic_softening || p_.permanent_set;
  if (p_.stress_relaxation) g_inf_ = 1.0 - p_.relax_g1 - (p_.prony_terms == 2 ? p_.relax_g2 : 0.0);
}

std::string ExtendedTensionLaw::name() const { return any_ ? "extended" : "voigt"; }

std::vector<LawParameter> ExtendedTensionLaw::parameters() const {
  std::vector<LawParameter> out = {{"EA_N", p_.ea_N, "N"}, {"EC_Ns", p_.ec_Ns, "N s"}};
  if (p_.strain_stiffening) out.push_back({"fung_b", p_.fung_b, "1"});
  if (p_.strain_stiffening && p_.fung_capped) out.push_back({"fung_cap_strain", p_.fung_cap_strain, "1"});
  if (p_.stress_relaxation) {
    out.push_back({"relax_g1", p_.relax_g1, "1"});
    out.push_back({"relax_tau1_s", p_.relax_tau1_s, "s"});
    if (p_.prony_terms == 2) {
      out.push_back({"relax_g2", p_.relax_g2, "1"});
      out.push_back({"relax_tau2_s", p_.relax_tau2_s, "s"});
    }
  }
  if (p_.cyclic_softening) {
    out.push_back({"soften_d_inf", p_.soften_d_inf, "1"});
    out.push_back({"soften_a_c", p_.soften_a_c, "1"});
  }
  if (p_.permanent_set) {
    out.push_back({"set_ratio", p_.set_ratio, "1"});
    if (p_.set_yield) out.push_back({"set_yield_strain", p_.set_yield_strain, "1"});
    if (p_.set_ratcheting) out.push_back({"set_ratchet", p_.set_ratchet, "1"});
  }
  return out;
}

void ExtendedTensionLaw::initInternal(double* z) const {
  if (!any_) return;
  std::fill(z, z + kInternal, 0.0);
  z[kScale] = 1.0;
  z[kDFsPrev] = p_.ea_N;  // dFs/de of the virgin sample at zero strain
}

double ExtendedTensionLaw::maxExp() const {
  return p_.fung_capped ? std::min(kMaxExponent, p_.fung_b * p_.fung_cap_strain) : kMaxExponent;
}

double ExtendedTensionLaw::setStrain(double e_max, double a_y) const {
  const double ep = p_.set_yield ? p_.set_ratio * std::max(0.0, e_max - p_.set_yield_strain) : p_.set_ratio * e_max;
  return p_.set_ratcheting ? ep + p_.set_ratchet * a_y : ep;
}

void ExtendedTensionLaw::elastic(double strain, const double* z, double* f, double* df) const {
  double x = strain;
  double scale = 1.0;
  if (z) {
    if (p_.permanent_set) x -= setStrain(z[kEMax], z[kAccYield]);
    scale = z[kScale];
  }
  fung(p_.ea_N, p_.strain_stiffening, p_.fung_b, x, f, df, maxExp());
  *f *= scale;
  *df *= scale;
}

TensionResponse ExtendedTensionLaw::evaluate(double strain, double strain_rate, double dt_s,
                                             const double* z) const {
  double fs, dfs;
  if (any_ && strain == z[kEPrev]) {
    fs = z[kFsPrev];  // the state of the last advance(): its elastic force, already computed
    dfs = z[kDFsPrev];
  } else {
    elastic(strain, any_ ? z : nullptr, &fs, &dfs);
  }
  TensionResponse r;
  if (!p_.stress_relaxation) {
    r.force_N = fs + p_.ec_Ns * strain_rate;
    r.dforce_dstrain_N = dfs;
  } else {
    // Trial update of the branches over a step ending at `strain` (see the header).
    const double dfs_trial = fs - z[kFsPrev];
    const double c1 = relaxWeight(dt_s / p_.relax_tau1_s);
    double force = g_inf_ * fs + z[kH1] + p_.relax_g1 * c1 * dfs_trial;
    double tangent = (g_inf_ + p_.relax_g1 * c1) * dfs;
    if (p_.prony_terms == 2) {
      const double c2 = relaxWeight(dt_s / p_.relax_tau2_s);
      force += z[kH2] + p_.relax_g2 * c2 * dfs_trial;
      tangent += p_.relax_g2 * c2 * dfs;
    }
    r.force_N = force + p_.ec_Ns * strain_rate;
    r.dforce_dstrain_N = tangent;
  }
  r.dforce_dstrainrate_Ns = p_.ec_Ns;
  return r;
}

void ExtendedTensionLaw::advance(double strain, double /*strain_rate*/, double dt_s, double* z) const {
  if (!any_) return;
  // History variables first (they set the elastic curve at the end of the step).
  const double loading = strain > 0 ? std::max(0.0, strain - std::max(0.0, z[kEPrev])) : 0.0;
  z[kAcc] += loading;
  if (p_.set_ratcheting) {
    const double from = std::max(std::max(0.0, z[kEPrev]), p_.set_yield ? p_.set_yield_strain : 0.0);
    z[kAccYield] += std::max(0.0, strain - from);
  }
  z[kEMax] = std::max(z[kEMax], strain);
  if (p_.cyclic_softening && loading > 0)  // d(a) changes only while loading
    z[kScale] = 1.0 - p_.soften_d_inf * -std::expm1(-z[kAcc] / p_.soften_a_c);
  double fs, dfs;
  elastic(strain, z, &fs, &dfs);
  if (p_.stress_relaxation) {
    const double dfs_step = fs - z[kFsPrev];
    const double x1 = dt_s / p_.relax_tau1_s;
    const double em1 = std::exp(-x1);
    z[kH1] = em1 * z[kH1] + p_.relax_g1 * relaxWeight(x1, em1) * dfs_step;
    if (p_.prony_terms == 2) {
      const double x2 = dt_s / p_.relax_tau2_s;
      const double em2 = std::exp(-x2);
      z[kH2] = em2 * z[kH2] + p_.relax_g2 * relaxWeight(x2, em2) * dfs_step;
    }
  }
  z[kFsPrev] = fs;
  z[kDFsPrev] = dfs;
  z[kEPrev] = strain;
}

double ExtendedTensionLaw::storedEnergy(double strain, const double* z) const {
  double x = strain, scale = 1.0;
  if (any_ && z) {
    if (p_.permanent_set) x -= setStrain(z[kEMax], z[kAccYield]);
    scale = z[kScale];
  }
  return scale * fungEnergy(p_.ea_N, p_.strain_stiffening, p_.fung_b, x, maxExp());
}

}  // namespace colosim
