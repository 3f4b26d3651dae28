// The extended tension law: the paper's Voigt law (eq. 6) with up to four effects that
// its linear spring-damper leaves out, each switched on by its options. With every
// effect off it is the Voigt law F = EA e + EC de/dt exactly.
//
// Strains e [-] and rates de/dt [1/s] are those of core/tension_law.h. The force is
//
//   F = g_inf Fs(e) + sum_i h_i + EC de/dt                                     [N]
//
// with the elastic force of the (softened, shifted) sample
//
//   Fs(e) = (1 - d(a)) Fe(e - e_p),                                            [N]
//   Fe(x) = EA x                         (linear, or x <= 0)
//   Fe(x) = EA / b (exp(b x) - 1)        (strain_stiffening, x > 0; Fung-type:
//                                         dFe/dx = EA exp(b x), EA the tangent at x = 0;
//                                         optionally straight beyond x_c, fung_cap_strain:
//                                         dFe/dx = EA exp(b x_c) there, a toe that stiffens
//                                         and then a linear region)
//
// and the effects
//   strain_stiffening  b [-]: exponential stiffening (Fung), see Fe.
//   stress_relaxation  g_i [-], tau_i [s], i = 1..2 (short Prony series, quasi-linear
//                      viscoelasticity): G(t) = g_inf + sum g_i exp(-t / tau_i),
//                      g_inf = 1 - sum g_i; h_i is the Maxwell branch force, the
//                      convolution of g_i exp(-t/tau_i) with dFs/dt, updated exactly for
//                      Fs linear in time within a step:
//                        h_i <- exp(-dt/tau_i) h_i + g_i c_i dFs,
//                        c_i = (1 - exp(-dt/tau_i)) / (dt/tau_i).
//                      One term is the standard linear solid.
//   cyclic_softening   d_inf [-], a_c [-] (preconditioning): d(a) = d_inf (1 - exp(-a/a_c)),
//                      a = accumulated loading strain (sum of the strain increases while in
//                      tension), so the sample softens over the first cycles and settles
//                      after about 4 a_c / (strain amplitude) cycles.
//   permanent_set      r [-]: e_p = r e_max, e_max the largest strain reached so far: after a
//                      large stretch the sample is longer and slack at lengths it used to resist.
//                      Optionally with a yield strain e_y [-] (set_yield): e_p = r max(0, e_max - e_y),
//                      no set until the sample has been stretched beyond e_y; e_y = 0 is the
//                      law without a threshold.
//                      Optionally ratcheting (set_ratchet c [-]): e_p gains c a_y, a_y the loading
//                      strain accumulated above e_y (the sum of the strain increases beyond
//                      max(e_prev, e_y)), so every cycle past the yield strain adds set, not only
//                      a new largest strain: e_p = r max(0, e_max - e_y) + c a_y.
//
// Internal variables per element (internalSize() = 9 when any effect is on, 0 otherwise):
//   z = [e_prev, Fs_prev [N], h_1 [N], h_2 [N], a [-], e_max [-], 1 - d(a) [-], dFs/de at e_prev [N],
//        a_y [-]]
// (the last two are caches of the last advance(), so that evaluate() at the same strain
// costs no transcendental function).
// evaluate() gives the force of a step that ends at e with z frozen except for the relaxation
// branches, which take the trial increment g_i c_i (Fs(e) - Fs_prev): its tangent is the
// algorithmic tangent (g_inf + sum g_i c_i) dFs/de of that update, so the implicit step sees
// the stiffness the update produces. When e equals the e_prev of the last advance() (as in the
// colon step), evaluate() returns g_inf Fs(e) + sum h_i + EC de/dt.
#pragma once

#include <string>
#include <vector>

#include "core/tension_law.h"

namespace colosim {

/// The names of the effects, in the order used everywhere (files, output).
const std::vector<std::string>& tensionEffectNames();

/// Parameters of the extended law; an effect is on when its flag is set.
struct ExtendedLawParams {
  double ea_N = 28.9;      ///< EA: axial rigidity (tangent at zero strain) [N]
  double ec_Ns = 0.05;     ///< EC: axial viscosity [N s]

  bool strain_stiffening = false;
  double fung_b = 0.0;     ///< b: exponential stiffening rate [-]
  bool fung_capped = false;   ///< the curve turns straight at fung_cap_strain (a parameter)
  double fung_cap_strain = 10.0;  ///< x_c: strain beyond which Fe continues along its tangent [-]

  bool stress_relaxation = false;
  int prony_terms = 1;     ///< 1 (standard linear solid) or 2
  double relax_g1 = 0.0;   ///< g_1: relaxing fraction of branch 1 [-]
  double relax_tau1_s = 1.0;  ///< tau_1 [s]
  double relax_g2 = 0.0;   ///< g_2 [-] (prony_terms == 2)
  double relax_tau2_s = 100.0;  ///< tau_2 [s]

  bool cyclic_softening = false;
  double soften_d_inf = 0.0;  ///< d_inf: stiffness fraction lost at equilibrium [-]
  double soften_a_c = 1.0;    ///< a_c: characteristic accumulated loading strain [-]

  bool permanent_set = false;
  double set_ratio = 0.0;     ///< r: permanent set per unit of the largest strain reached [-]
  bool set_yield = false;     ///< the set has a yield strain (set_yield_strain is a parameter)
  double set_yield_strain = 0.0;  ///< e_y: largest strain without a set (set_yield) [-]
  bool set_ratcheting = false;  ///< the set grows with every loading past e_y (set_ratchet is a parameter)
  double set_ratchet = 0.0;   ///< c: set per unit of loading strain accumulated above e_y [-]

  /// Names of the effects that are on, in tensionEffectNames() order.
  std::vector<std::string> effects() const;
  /// Switches an effect on by name; throws std::invalid_argument for an unknown name.
  void enable(const std::string& effect);
  /// Sets a parameter by its name in parameters() (relax_g2 / relax_tau2_s select the
  /// two-term Prony series, set_yield_strain the set with a yield strain, set_ratchet the
  /// ratcheting set, fung_cap_strain the stiffening curve that turns straight); false for an
  /// unknown name.
  bool set(const std::string& name, double value);
  /// Throws std::invalid_argument naming the first parameter out of its range.
  void validate() const;
};

class ExtendedTensionLaw final : public TensionLaw {
 public:
  /// Throws std::invalid_argument when the parameters are out of range.
  explicit ExtendedTensionLaw(const ExtendedLawParams& p);

  /// "voigt" when no effect is on, else "extended".
  std::string name() const override;
  /// EA_N, EC_Ns, then the parameters of the effects that are on.
  std::vector<LawParameter> parameters() const override;

  static constexpr int kInternal = 9;
  int internalSize() const override { return any_ ? kInternal : 0; }
  void initInternal(double* z) const override;
  TensionResponse evaluate(double strain, double strain_rate, double dt_s,
                           const double* z) const override;
  void advance(double strain, double strain_rate, double dt_s, double* z) const override;
  double storedEnergy(double strain, const double* z) const override;

  const ExtendedLawParams& params() const { return p_; }

 private:
  // Fs(e) and dFs/de with the internal variables z (softening, set) [N].
  void elastic(double strain, const double* z, double* force_N, double* dforce_N) const;
  // The permanent set e_p [-] after a largest strain e_max [-] and a loading strain a_y [-]
  // accumulated above the yield strain.
  double setStrain(double e_max, double a_y) const;

  // The largest exponent b x of the Fung curve, beyond which it continues along its tangent.
  double maxExp() const;
  ExtendedLawParams p_;
  bool any_ = false;
  double g_inf_ = 1.0;
};

}  // namespace colosim
