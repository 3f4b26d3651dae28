// The forward model of the fit runs the colon's own tension laws (identify/tension/forward.h).
#include "identify/tension/forward.h"

#include <cmath>
#include <functional>
#include <memory>

#include <gtest/gtest.h>

#include "core/colon_step.h"
#include "core/extended_tension_law.h"
#include "identify/tension/synthetic.h"

namespace colosim {
namespace {

// A colon of two control points l0 [m] apart, on the x axis, with `law` as its tension
// element and the given mass per length [kg/m].
ColonModel twoPointColon(double l0, double mass_per_length_kg_per_m, std::shared_ptr<const TensionLaw> law) {
  Points q(3, 2);
  q.col(0) = Vec3::Zero();
  q.col(1) = Vec3(l0, 0, 0);
  return buildColonModelFromPoints(q, Eigen::VectorXd::Constant(2, 0.02), mass_per_length_kg_per_m, 0, 0,
                                   Vec3::Zero(), std::move(law));
}

// A tension test of `rows` samples dt [s] apart with the elongation elongation_m(time) [m],
// and the fitter's force of `law` along it [N].
TensionTest historyOf(double l0, double dt, int rows, const std::function<double(double)>& elongation_m) {
  TensionTest t;
  t.sample_length_m = l0;
  for (int k = 0; k < rows; ++k) {
    t.time_s.push_back(k * dt);
    t.elongation_m.push_back(elongation_m(k * dt));
    t.force_N.push_back(0);
  }
  return t;
}
std::vector<double> fitterForce(const TensionLaw& law, const TensionTest& t) {
  std::vector<double> strain, rate, force;
  tensionStrainHistory(t, &strain, &rate);
  simulateLawForce(law, t.time_s, strain, rate, &force);
  return force;
}

TEST(Forward, VoigtLawInTheFitterAndInTheColonGiveTheSameForce) {
  // One elongation history, two drivers: the fitter's forward model, and a 2-control-point
  // colon whose end point is moved through the same positions (with the backward-Euler
  // velocity v_k = (x_k - x_{k-1}) / dt) before each step. The step reports the force of
  // its tension element at the start of the step.
  const double l0 = 0.18, dt = 1e-3;
  auto law = std::make_shared<VoigtLaw>(28.9, 0.05);
  const ColonModel m = twoPointColon(l0, 0.4, law);
  ColonState s = makeColonState(m);
  const TensionTest t =
      historyOf(l0, dt, 3000, [](double time) { return 0.05 * std::sin(2.0 * time) + 0.02 * time; });
  const std::vector<double> fitter = fitterForce(*law, t);
  double max_diff = 0, max_force = 0;
  for (size_t k = 0; k < t.rows(); ++k) {
    s.q.col(0) = Vec3::Zero();
    s.v.col(0) = Vec3::Zero();
    s.q.col(1) = Vec3(l0 + t.elongation_m[k], 0, 0);
    s.v.col(1) = Vec3(k ? (t.elongation_m[k] - t.elongation_m[k - 1]) / dt : 0.0, 0, 0);
    stepColon(m, s, dt);
    max_diff = std::max(max_diff, std::abs(s.tension_force_N(0) - fitter[k]));
    max_force = std::max(max_force, std::abs(fitter[k]));
  }
  EXPECT_GT(max_force, 5.0);
  EXPECT_LT(max_diff, 1e-9 * max_force);
}

TEST(Forward, ExtendedLawInTheFitterAndInTheColonGiveTheSameForce) {
  // History-dependent laws too: the colon calls evaluate() at the start of a step and
  // advance() with the strain at its end, as the fitter does. The end point gets a huge
  // mass and the velocity that carries it to the next prescribed position, so that the
  // step moves it exactly along the history (EC = 0: that velocity is a forward
  // difference, the fitter's rate a backward one, and only EC sees the rate).
  const double l0 = 0.18, dt = 1e-3;
  ExtendedLawParams p;
  for (const std::string& e : tensionEffectNames()) p.enable(e);
  p.ea_N = 8, p.ec_Ns = 0.0, p.fung_b = 2.5, p.relax_g1 = 0.4, p.relax_tau1_s = 0.5;
  p.soften_d_inf = 0.3, p.soften_a_c = 0.5, p.set_ratio = 0.1;
  auto law = std::make_shared<ExtendedTensionLaw>(p);
  const ColonModel m = twoPointColon(l0, 1e9, law);
  ColonState s = makeColonState(m);
  const TensionTest t =
      historyOf(l0, dt, 4001, [](double time) { return 0.06 * std::sin(3.0 * time) * std::sin(3.0 * time); });
  const std::vector<double> fitter = fitterForce(*law, t);
  double max_diff = 0, max_force = 0;
  for (size_t k = 0; k + 1 < t.rows(); ++k) {
    if (k == 0) s.q.col(1) = Vec3(l0 + t.elongation_m[0], 0, 0);
    s.v.col(0) = Vec3::Zero();
    s.v.col(1) = Vec3((t.elongation_m[k + 1] - t.elongation_m[k]) / dt, 0, 0);
    stepColon(m, s, dt);
    max_diff = std::max(max_diff, std::abs(s.tension_force_N(0) - fitter[k]));
    max_force = std::max(max_force, std::abs(fitter[k]));
  }
  EXPECT_GT(max_force, 2.0);
  EXPECT_LT(max_diff, 1e-6 * max_force);
}

TEST(Forward, TheBenchCannotPush) {
  const VoigtLaw law(20, 0.0);
  std::vector<double> t = {0, 1, 2}, e = {0.0, -0.1, 0.1}, r = {0, -0.1, 0.2}, f;
  benchForce(law, 0.05, t, e, r, &f);
  EXPECT_DOUBLE_EQ(f[1], 0.05);           // slack: the offset only
  EXPECT_DOUBLE_EQ(f[2], 0.05 + 20 * 0.1);
}

}  // namespace
}  // namespace colosim
