// Tension laws: the force of one tension element of the colon (paper section 2.4, eq. 6)
// as a function of its strain, strain rate and internal variables.
//
// One element joins consecutive control points q_i, q_{i+1}; its strain is
// e = (l - l0) / l0 with l = |q_{i+1} - q_i| and l0 the rest length, and its strain rate
// is de/dt = (dl/dt) / l0. The law gives the axial force F [N] (positive in tension).
//
// A law is immutable (its parameters are fixed at construction); what changes during a
// run lives in the element's internal variables z (internalSize() doubles per element),
// owned by the simulation state. The same law object is used by the colon step and by
// the identification fitter: one implementation, not two.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace colosim {

/// Force of a tension element and its partial derivatives, for the implicit solve.
struct TensionResponse {
  double force_N = 0.0;               ///< axial force F, positive in tension [N]
  double dforce_dstrain_N = 0.0;      ///< dF/de [N] (tangent axial rigidity)
  double dforce_dstrainrate_Ns = 0.0; ///< dF/d(de/dt) [N s]
};

/// A named scalar parameter of a law, with its unit.
struct LawParameter {
  std::string name;  ///< e.g. "EA_N"
  double value = 0.0;
  std::string unit;  ///< e.g. "N"
};

class TensionLaw {
 public:
  virtual ~TensionLaw() = default;

  /// Short identifier written in files, e.g. "voigt".
  virtual std::string name() const = 0;
  /// Parameters with their units, in a fixed order.
  virtual std::vector<LawParameter> parameters() const = 0;

  /// Number of internal variables per element (0 for the Voigt law).
  virtual int internalSize() const { return 0; }
  /// Sets the internal variables of an unloaded, virgin element.
  virtual void initInternal(double* /*z*/) const {}

  /// Force at strain e [-] and strain rate edot [1/s] with internal variables z.
  /// dt_s is the time step the caller integrates with: laws with internal
  /// dynamics return the algorithmic tangent of their update over dt_s.
  virtual TensionResponse evaluate(double strain, double strain_rate, double dt_s,
                                   const double* z) const = 0;

  /// Advances the internal variables z over one step of dt_s [s] that ends at strain e
  /// with rate edot. Called once per step, after the positions have been updated.
  virtual void advance(double /*strain*/, double /*strain_rate*/, double /*dt_s*/,
                       double* /*z*/) const {}

  /// Elastic energy stored per metre of rest length at strain e [J/m = N]
  /// (the potential of the rate-independent part; used for energy checks).
  virtual double storedEnergy(double strain, const double* z) const = 0;
};

/// The paper's Voigt law (eq. 6): F = EA e + EC de/dt.
class VoigtLaw final : public TensionLaw {
 public:
  /// ea_N: axial rigidity EA [N per unit strain]; ec_Ns: axial viscosity [N s per unit strain].
  VoigtLaw(double ea_N, double ec_Ns) : ea_N_(ea_N), ec_Ns_(ec_Ns) {}

  std::string name() const override { return "voigt"; }
  std::vector<LawParameter> parameters() const override {
    return {{"EA_N", ea_N_, "N"}, {"EC_Ns", ec_Ns_, "N s"}};
  }
  TensionResponse evaluate(double strain, double strain_rate, double /*dt_s*/,
                           const double* /*z*/) const override {
    return {ea_N_ * strain + ec_Ns_ * strain_rate, ea_N_, ec_Ns_};
  }
  double storedEnergy(double strain, const double* /*z*/) const override {
    return 0.5 * ea_N_ * strain * strain;
  }

  double ea_N() const { return ea_N_; }
  double ec_Ns() const { return ec_Ns_; }

 private:
  double ea_N_;
  double ec_Ns_;
};

}  // namespace colosim
