#include "identify/tension/identify.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include "identify/tension/forward.h"

namespace colosim {

namespace {

// ---------------------------------------------------------------------------------------
// Parameter layout: the fitted vector x holds scaled values (x_i = theta_i / scale_i) so
// that every coordinate is of order one for the optimiser and its finite differences.

struct ParamDef {
  std::string name, unit;
  double scale, lo, hi;  // scale and bounds of theta (unscaled units)
  double start = NAN;    // where a fit starts when nothing else says (NAN: at scale)
};

struct Data {
  const TensionTest* test = nullptr;
  std::vector<double> strain, rate;
  double ea_scale_N = 10;       // magnitude of EA for scaling [N]
  double total_loading_strain = 1;  // accumulated loading strain of the protocol [-]
  double max_strain = 1;        // largest strain of the test [-]
};

// The loading strain accumulated above e_y along a strain history [-]: the sum of the
// strain increases beyond max(0, previous strain, e_y), added to `sum`.
double loadingStrainAbove(const std::vector<double>& strain, double e_y, double sum = 0) {
  for (size_t k = 1; k < strain.size(); ++k) sum += std::max(0.0, strain[k] - std::max({0.0, strain[k - 1], e_y}));
  return sum;
}

// A ratchet that leaves a set of a tenth of the largest strain after the protocol's loading
// [-] (the loading strain above zero stands in for the one above the yield strain).
double ratchetScale(const Data& d) { return std::min(0.5, 0.1 * d.max_strain / std::max(1e-3, d.total_loading_strain)); }

// The parameters of a law with `effects`; relaxation with two Maxwell branches when
// two_relax. Stiffening always has its straightening strain (starting beyond reach, the
// plain Fung curve). The set always has its yield strain (0 is the set without a threshold), and
// with `ratchet` its ratchet (starting at 0, the set that grows with the largest strain only).
std::vector<ParamDef> layout(const Data& d, const std::vector<std::string>& effects, bool two_relax = false,
                             bool ratchet = false) {
  auto has = [&](const char* e) { return std::find(effects.begin(), effects.end(), e) != effects.end(); };
  std::vector<ParamDef> p = {{"EA_N", "N", d.ea_scale_N, 1e-3 * d.ea_scale_N, 1e3 * d.ea_scale_N},
                             {"EC_Ns", "N s", 0.1, 0.0, 1e3}};
  if (has("strain_stiffening")) {
    p.push_back({"fung_b", "1", 1.0, 0.0, 20.0});
    // Where the curve turns straight; it starts beyond reach (10: the plain Fung curve).
    p.push_back({"fung_cap_strain", "1", d.max_strain, 0.02 * d.max_strain, 10.0, 10.0});
  }
  if (has("stress_relaxation")) {
    p.push_back({"relax_g1", "1", 0.3, 0.0, 0.95});
    p.push_back({"relax_tau1_s", "s", 10.0, 0.05, 1e4});
    if (two_relax) {
      p.push_back({"relax_g2", "1", 0.3, 0.0, 0.95});
      p.push_back({"relax_tau2_s", "s", 10.0, 0.05, 1e4});
    }
  }
  if (has("cyclic_softening")) {
    p.push_back({"soften_d_inf", "1", 0.2, 0.0, 0.95});
    p.push_back({"soften_a_c", "1", std::max(1e-3, d.total_loading_strain / 5), 1e-4, 1e4});
  }
  if (has("permanent_set")) {
    p.push_back({"set_ratio", "1", 0.1, 0.0, 0.9});
    p.push_back({"set_yield_strain", "1", std::max(1e-3, 0.3 * d.max_strain), 0.0, std::max(1e-3, d.max_strain)});
    if (ratchet) p.push_back({"set_ratchet", "1", ratchetScale(d), 0.0, 0.9, 0.0});
  }
  p.push_back({"offset_N", "N", 0.1, -1e3, 1e3});
  return p;
}

// theta (unscaled, in layout order) -> law parameters and offset.
ExtendedLawParams toLaw(const std::vector<ParamDef>& defs, const std::vector<std::string>& effects,
                        const double* theta, double* offset_N) {
  ExtendedLawParams lp;
  for (const std::string& e : effects) lp.enable(e);
  for (size_t i = 0; i < defs.size(); ++i) {
    if (defs[i].name == "offset_N") *offset_N = theta[i];
    else lp.set(defs[i].name, theta[i]);  // relax_g2 and set_yield_strain select their forms
  }
  return lp;
}

// theta of an existing fit, mapped onto the layout of a model with more effects; the new
// effect's parameters take `extra` (name -> value) or their defaults.
std::vector<double> thetaFrom(const std::vector<ParamDef>& defs, const FittedModel& m,
                              const std::vector<std::pair<std::string, double>>& extra) {
  std::vector<double> th(defs.size());
  for (size_t i = 0; i < defs.size(); ++i) {
    double v = std::isnan(defs[i].start) ? defs[i].scale : defs[i].start;
    for (const ParamEstimate& p : m.params)
      if (p.name == defs[i].name) v = p.value;
    for (const auto& kv : extra)
      if (kv.first == defs[i].name) v = kv.second;
    th[i] = std::clamp(v, defs[i].lo, defs[i].hi);
  }
  return th;
}

// Predicted bench force for theta; false when the parameters make no valid law.
bool predict(const Data& d, const std::vector<ParamDef>& defs, const std::vector<std::string>& effects,
             const double* theta, std::vector<double>* out) {
  double offset = 0;
  try {
    const ExtendedTensionLaw law(toLaw(defs, effects, theta, &offset));
    benchForce(law, offset, d.test->time_s, d.strain, d.rate, out);
  } catch (const std::invalid_argument&) {
    return false;
  }
  return true;
}

struct ResidualFunctor {
  const Data* d;
  const std::vector<ParamDef>* defs;
  const std::vector<std::string>* effects;
  const std::vector<double>* weight;  // 1 for rows in the fit, 0 for held-out rows
  mutable std::vector<double> theta, pred;
  bool operator()(double const* const* x, double* residual) const {
    const size_t np = defs->size();
    theta.resize(np);
    // Finite differences may step just past a bound: evaluate at the bound.
    for (size_t i = 0; i < np; ++i)
      theta[i] = std::clamp(x[0][i] * (*defs)[i].scale, (*defs)[i].lo, (*defs)[i].hi);
    if (!predict(*d, *defs, *effects, theta.data(), &pred)) return false;
    const std::vector<double>& f = d->test->force_N;
    for (size_t k = 0; k < pred.size(); ++k) residual[k] = (*weight)[k] * (pred[k] - f[k]);
    return true;
  }
};

// Least-squares fit from theta0 over the rows with weight 1; returns theta and SSE.
std::vector<double> solve(const Data& d, const std::vector<ParamDef>& defs, const std::vector<std::string>& effects,
                          const std::vector<double>& theta0, const std::vector<double>& weight, int max_iterations,
                          double* sse) {
  const int np = static_cast<int>(defs.size());
  std::vector<double> x(np);
  for (int i = 0; i < np; ++i) x[i] = theta0[i] / defs[i].scale;
  auto* functor = new ResidualFunctor{&d, &defs, &effects, &weight, {}, {}};
  ceres::NumericDiffOptions nd;
  nd.relative_step_size = 1e-6;
  auto* cost = new ceres::DynamicNumericDiffCostFunction<ResidualFunctor>(functor, ceres::TAKE_OWNERSHIP, nd);
  cost->AddParameterBlock(np);
  cost->SetNumResiduals(static_cast<int>(d.test->rows()));
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x.data());
  for (int i = 0; i < np; ++i) {
    problem.SetParameterLowerBound(x.data(), i, defs[i].lo / defs[i].scale);
    problem.SetParameterUpperBound(x.data(), i, defs[i].hi / defs[i].scale);
  }
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::DENSE_QR;
  opt.max_num_iterations = max_iterations;
  opt.function_tolerance = 1e-7;
  opt.parameter_tolerance = 1e-7;
  opt.logging_type = ceres::SILENT;
  opt.minimizer_progress_to_stdout = false;
  opt.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
  std::vector<double> theta(np);
  for (int i = 0; i < np; ++i) theta[i] = x[i] * defs[i].scale;
  *sse = 2.0 * summary.final_cost;
  return theta;
}

// Jacobian of the predicted bench force with respect to the scaled parameters x, by forward
// differences (steps inward at the upper bounds). Empty when a prediction fails.
Eigen::MatrixXd jacobian(const Data& d, const std::vector<ParamDef>& defs, const std::vector<std::string>& effects,
                         const std::vector<double>& theta, const std::vector<double>& pred) {
  const int np = static_cast<int>(defs.size());
  const int n = static_cast<int>(pred.size());
  Eigen::MatrixXd J(n, np);
  std::vector<double> th = theta, p2;
  for (int i = 0; i < np; ++i) {
    double h = 1e-6 * std::max(std::abs(theta[i]), defs[i].scale);
    if (theta[i] + h > defs[i].hi) h = -h;
    th[i] = theta[i] + h;
    if (!predict(d, defs, effects, th.data(), &p2)) return Eigen::MatrixXd();
    for (int k = 0; k < n; ++k) J(k, i) = (p2[k] - pred[k]) / h * defs[i].scale;
    th[i] = theta[i];
  }
  return J;
}

struct Fit {
  FittedModel model;
  std::vector<double> theta;
  bool two_relax = false;  // relaxation with two Maxwell branches
  bool ratchet = false;    // a set that ratchets
};

// Fills the model of a fit: law, prediction, errors, information criteria, parameter
// standard deviations (s^2 (J^T J)^-1), and the held-out error of blocked cross-validation.
//
// Held-out error: for each fold, the fit is refitted on the other folds by one Gauss-Newton
// step from the full fit (J and the residuals are those of the full fit restricted to the
// training rows), then the law is simulated again with the refitted parameters and scored
// on the fold. One step is the usual approximate refit (the model is close to linear in its
// parameters around the optimum) and costs one simulation per fold instead of a full fit.
Fit finishModel(const Data& d, const std::vector<ParamDef>& defs, const std::vector<std::string>& effects,
                const std::vector<double>& theta, double sse, const std::vector<int>& fold, int folds) {
  Fit f;
  f.theta = theta;
  f.two_relax = std::any_of(defs.begin(), defs.end(), [](const ParamDef& p) { return p.name == "relax_g2"; });
  f.ratchet = std::any_of(defs.begin(), defs.end(), [](const ParamDef& p) { return p.name == "set_ratchet"; });
  FittedModel& m = f.model;
  m.effects = effects;
  m.law = toLaw(defs, effects, theta.data(), &m.offset_N);
  predict(d, defs, effects, theta.data(), &m.prediction_N);
  const int n = static_cast<int>(d.test->rows());
  const int np = static_cast<int>(defs.size());
  m.n_params = np;
  scoreFit(sse, n, &m);
  const Eigen::MatrixXd J = jacobian(d, defs, effects, theta, m.prediction_N);
  std::vector<double> sd(np, NAN);
  Eigen::VectorXd r(n);
  for (int k = 0; k < n; ++k) r(k) = m.prediction_N[k] - d.test->force_N[k];
  if (J.size()) {
    const Eigen::MatrixXd cov = (sse / std::max(1, n - np)) *
                                (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse();
    for (int i = 0; i < np; ++i) sd[i] = std::sqrt(std::max(0.0, cov(i, i))) * defs[i].scale;
  }
  for (int i = 0; i < np; ++i) m.params.push_back({defs[i].name, theta[i], sd[i], defs[i].unit});

  double held = 0;
  std::vector<double> th(np), pred;
  for (int fo = 0; fo < folds; ++fo) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(np, np);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(np);
    for (int k = 0; k < n; ++k) {
      if (fold[k] == fo || !J.size()) continue;
      A.selfadjointView<Eigen::Lower>().rankUpdate(J.row(k).transpose());
      g += J.row(k).transpose() * r(k);
    }
    A = A.selfadjointView<Eigen::Lower>();
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(np);
    if (J.size()) {
      A.diagonal() *= 1.0 + 1e-9;  // Levenberg-Marquardt damping against exact null directions
      dx = -A.completeOrthogonalDecomposition().solve(g);
    }
    // The step is kept only when it lowers the error on the training rows (the model is not
    // linear far from the optimum: a full step along a poorly determined direction can
    // overshoot); else it is halved, up to 4 times, and then the full fit is used.
    double train0 = 0;
    for (int k = 0; k < n; ++k)
      if (fold[k] != fo) train0 += r(k) * r(k);
    bool ok = false;
    for (int halving = 0; halving <= 4 && !ok; ++halving, dx *= 0.5) {
      for (int i = 0; i < np; ++i) th[i] = std::clamp(theta[i] + dx(i) * defs[i].scale, defs[i].lo, defs[i].hi);
      if (!predict(d, defs, effects, th.data(), &pred)) continue;
      double train = 0;
      for (int k = 0; k < n; ++k)
        if (fold[k] != fo) train += (pred[k] - d.test->force_N[k]) * (pred[k] - d.test->force_N[k]);
      ok = train <= train0;
    }
    if (!ok) pred = m.prediction_N;
    for (int k = 0; k < n; ++k)
      if (fold[k] == fo) held += (pred[k] - d.test->force_N[k]) * (pred[k] - d.test->force_N[k]);
  }
  m.heldout_rmse_N = std::sqrt(held / n);
  return f;
}

// Fits from each start (a few iterations each), continues the best to convergence.
Fit fitModel(const Data& d, const std::vector<std::string>& effects, const std::vector<std::vector<double>>& starts,
             const std::vector<int>& fold, int folds, bool two_relax = false, bool ratchet = false) {
  const std::vector<ParamDef> defs = layout(d, effects, two_relax, ratchet);
  const std::vector<double> ones(d.test->rows(), 1.0);
  double best_sse = std::numeric_limits<double>::infinity();
  std::vector<double> best;
  for (const std::vector<double>& s : starts) {
    double sse;
    std::vector<double> th = solve(d, defs, effects, s, ones, starts.size() > 1 ? 6 : 40, &sse);
    if (sse < best_sse) best_sse = sse, best = th;
  }
  if (starts.size() > 1) best = solve(d, defs, effects, best, ones, 34, &best_sse);
  return finishModel(d, defs, effects, best, best_sse, fold, folds);
}

// ---------------------------------------------------------------------------------------
// Protocol segmentation: loading / hold / unloading, cycles, folds.

void segment(const Data& d, IdentifyResult* r, int folds) {
  const TensionTest& t = *d.test;
  const size_t n = t.rows();
  // Rate over +-2 rows (robust to a slightly irregular time base).
  std::vector<double> rate(n);
  double max_rate = 0;
  for (size_t k = 0; k < n; ++k) {
    const size_t a = k >= 2 ? k - 2 : 0, b = std::min(n - 1, k + 2);
    rate[k] = (d.strain[b] - d.strain[a]) / (t.time_s[b] - t.time_s[a]);
    max_rate = std::max(max_rate, std::abs(rate[k]));
  }
  const double thr = 0.05 * max_rate;
  r->cycle.assign(n, 0);
  r->time_in_hold_s.assign(n, -1.0);
  int cycle = 0;
  bool unloaded_since_start = false;
  bool started = false;
  double hold_start = -1;
  for (size_t k = 0; k < n; ++k) {
    const int cls = rate[k] > thr ? 1 : (rate[k] < -thr ? -1 : 0);
    if (cls == -1) unloaded_since_start = true;
    if (cls == 1 && (!started || unloaded_since_start)) {
      if (started) ++cycle;
      started = true;
      unloaded_since_start = false;
    }
    r->cycle[k] = cycle;
    if (cls == 0) {
      if (hold_start < 0) hold_start = t.time_s[k];
      r->time_in_hold_s[k] = t.time_s[k] - hold_start;
    } else {
      hold_start = -1;
    }
  }
  r->cycles = cycle + 1;
  r->fold.assign(n, 0);
  if (r->cycles >= 2 * folds) {
    for (size_t k = 0; k < n; ++k) r->fold[k] = r->cycle[k] % folds;
  } else {
    for (size_t k = 0; k < n; ++k) r->fold[k] = static_cast<int>(folds * k / n);
  }
}

// The residual in bins of x between consecutive edges (below the first: the first bin, at
// or above the last: the last), rows with use[k] only; bins without rows are left out and
// each kept bin is named by its centre (by its lower edge when it is unbounded above).
ResidualProfile profile(const std::string& name, const std::vector<double>& x, const std::vector<double>& res,
                        const std::vector<double>& edges, const std::vector<bool>& use) {
  const size_t nb = edges.size() - 1;
  std::vector<int> bin(x.size(), -1);
  for (size_t k = 0; k < x.size(); ++k) {
    if (!use[k]) continue;
    const size_t b = std::upper_bound(edges.begin(), edges.end(), x[k]) - edges.begin();
    bin[k] = static_cast<int>(b == 0 ? 0 : std::min(b - 1, nb - 1));
  }
  const ResidualProfile all = residualProfile(name, res, bin, static_cast<int>(nb));
  ResidualProfile p;
  p.variable = name;
  p.structure_N = all.structure_N;
  for (size_t b = 0; b < nb; ++b) {
    if (all.count[b] == 0) continue;
    p.bin_centre.push_back(std::isfinite(edges[b + 1]) ? 0.5 * (edges[b] + edges[b + 1]) : edges[b]);
    p.mean_residual_N.push_back(all.mean_residual_N[b]);
    p.count.push_back(all.count[b]);
  }
  return p;
}

Diagnostics diagnose(const Data& d, const IdentifyResult& r, const FittedModel& m) {
  const TensionTest& t = *d.test;
  const size_t n = t.rows();
  std::vector<double> res(n);
  for (size_t k = 0; k < n; ++k) res[k] = t.force_N[k] - m.prediction_N[k];
  Diagnostics g = diagnoseResidual(m.rmse_N, res);
  double mean = std::accumulate(res.begin(), res.end(), 0.0) / n, c0 = 0, c1 = 0;
  for (size_t k = 0; k < n; ++k) c0 += (res[k] - mean) * (res[k] - mean);
  for (size_t k = 1; k < n; ++k) c1 += (res[k] - mean) * (res[k - 1] - mean);
  g.lag1_autocorrelation = c0 > 0 ? c1 / c0 : 0;
  // Residual smoothed over +-1 s.
  double s2 = 0;
  size_t a = 0, b = 0;
  double window_sum = 0;
  for (size_t k = 0; k < n; ++k) {
    while (b < n && t.time_s[b] <= t.time_s[k] + 1.0) window_sum += res[b++];
    while (t.time_s[a] < t.time_s[k] - 1.0) window_sum -= res[a++];
    const double sm = window_sum / (b - a);
    s2 += sm * sm;
  }
  g.smooth_structure_N = std::sqrt(s2 / n);

  const std::vector<bool> all(n, true);
  double emin = *std::min_element(d.strain.begin(), d.strain.end());
  double emax = *std::max_element(d.strain.begin(), d.strain.end());
  std::vector<double> edges;
  for (int i = 0; i <= 8; ++i) edges.push_back(emin + (emax - emin) * i / 8.0);
  edges.back() = std::numeric_limits<double>::infinity();
  g.profiles.push_back(profile("strain", d.strain, res, edges, all));
  double rmax = 0;
  for (double x : d.rate) rmax = std::max(rmax, std::abs(x));
  edges.clear();
  for (int i = 0; i <= 8; ++i) edges.push_back(rmax * (-1.0 + 2.0 * i / 8.0));
  edges.front() = -std::numeric_limits<double>::infinity();
  edges.back() = std::numeric_limits<double>::infinity();
  g.profiles.push_back(profile("strain_rate_per_s", d.rate, res, edges, all));
  std::vector<bool> in_hold(n);
  for (size_t k = 0; k < n; ++k) in_hold[k] = r.time_in_hold_s[k] >= 0 && d.strain[k] > 0.25 * emax;
  g.profiles.push_back(profile("time_in_hold_s", r.time_in_hold_s, res,
                               {0, 1, 3, 10, 20, 40, std::numeric_limits<double>::infinity()}, in_hold));
  std::vector<double> cyc(n);
  for (size_t k = 0; k < n; ++k) cyc[k] = r.cycle[k];
  edges.clear();
  for (int c = 0; c <= r.cycles; ++c) edges.push_back(c - 0.5);
  g.profiles.push_back(profile("cycle", cyc, res, edges, all));
  for (ResidualProfile& p : g.profiles)
    if (p.variable == "cycle")
      for (double& c : p.bin_centre) c = std::round(c);
  return g;
}

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

std::string joinOrNone(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : " + ") + x;
  return s.empty() ? "none" : s;
}

// Starting points for a model that adds `effect` to the fitted `current` (its relaxation,
// if any, with two branches when two_relax).
std::vector<std::vector<double>> startsFor(const Data& d, const FittedModel& current, const std::string& effect,
                                           bool two_relax = false, bool ratchet = false) {
  const std::vector<std::string> effects = [&] {
    std::vector<std::string> e = current.effects;
    e.push_back(effect);
    return e;
  }();
  const std::vector<ParamDef> defs = layout(d, effects, two_relax, ratchet);
  double ea = current.law.ea_N;
  std::vector<std::vector<double>> s;
  if (effect == "strain_stiffening") {
    s.push_back(thetaFrom(defs, current, {{"EA_N", 0.5 * ea}, {"fung_b", 1.0}}));
    s.push_back(thetaFrom(defs, current, {{"EA_N", 0.2 * ea}, {"fung_b", 3.0}}));
    // A toe that stiffens fast and turns straight within the test.
    s.push_back(thetaFrom(defs, current, {{"EA_N", 0.5 * ea}, {"fung_b", 4.0 / d.max_strain},
                                          {"fung_cap_strain", 0.6 * d.max_strain}}));
  } else if (effect == "stress_relaxation") {
    s.push_back(thetaFrom(defs, current, {{"EA_N", 1.3 * ea}, {"relax_g1", 0.3}, {"relax_tau1_s", 3.0}}));
    s.push_back(thetaFrom(defs, current, {{"EA_N", 1.3 * ea}, {"relax_g1", 0.3}, {"relax_tau1_s", 30.0}}));
  } else if (effect == "cyclic_softening") {
    s.push_back(thetaFrom(defs, current, {{"EA_N", 1.2 * ea}, {"soften_d_inf", 0.2},
                                          {"soften_a_c", d.total_loading_strain / 8}}));
    s.push_back(thetaFrom(defs, current, {{"EA_N", 1.2 * ea}, {"soften_d_inf", 0.2},
                                          {"soften_a_c", d.total_loading_strain / 2}}));
  } else {
    s.push_back(thetaFrom(defs, current, {{"set_ratio", 0.05}, {"set_yield_strain", 0.0}}));
    s.push_back(thetaFrom(defs, current, {{"set_ratio", 0.15}, {"set_yield_strain", 0.3 * d.max_strain}}));
  }
  return s;
}

// The fitted `current` with `effect` added at the value that switches it off (Fung b, the
// relaxation weights, the softening's d_inf and the set ratio at 0): the same law, so a fit
// started there ends no worse than `current`. The effect's shape (where stiffening turns
// straight, the relaxation times, the softening's scale, the set's yield strain) is taken from
// its own single fit `alone`: switched off, the shape does not act, so the fit cannot learn
// it from its gradient, and a set switched off at zero yield, the first choice, sat in a
// stationary point beside relaxation where the same set with its own yield strain paid
// (harder forms, recovering sets: docs/identification-trials.md, session 37).
std::vector<double> switchedOff(const Data& d, const FittedModel& current, const std::string& effect,
                                const FittedModel& alone, bool two_relax, bool ratchet) {
  std::vector<std::string> effects = current.effects;
  effects.push_back(effect);
  const std::vector<ParamDef> defs = layout(d, effects, two_relax, ratchet);
  auto shape = [&](const char* name, double fallback) {
    for (const ParamEstimate& p : alone.params)
      if (p.name == name) return p.value;
    return fallback;
  };
  if (effect == "strain_stiffening")
    return thetaFrom(defs, current, {{"fung_b", 0.0}, {"fung_cap_strain", shape("fung_cap_strain", 10.0)}});
  if (effect == "stress_relaxation")
    return thetaFrom(defs, current, {{"relax_g1", 0.0}, {"relax_tau1_s", shape("relax_tau1_s", 3.0)}, {"relax_g2", 0.0},
                                     {"relax_tau2_s", shape("relax_tau2_s", 30.0)}});
  if (effect == "cyclic_softening")
    return thetaFrom(defs, current, {{"soften_d_inf", 0.0}, {"soften_a_c", shape("soften_a_c", d.total_loading_strain / 5)}});
  return thetaFrom(defs, current, {{"set_ratio", 0.0}, {"set_yield_strain", shape("set_yield_strain", 0.0)}, {"set_ratchet", 0.0}});
}

// The toe of the reloadings: rows loading again (after the first loading) at strains up to
// 30 % of the largest strain reached before, where a permanent set moves the strain at
// which force starts.
std::vector<bool> toeRows(const Data& d, const IdentifyResult& seg) {
  const size_t n = d.test->rows();
  std::vector<bool> toe(n, false);
  double e_max = 0;
  for (size_t k = 0; k < n; ++k) {
    toe[k] = seg.cycle[k] > 0 && seg.time_in_hold_s[k] < 0 && d.rate[k] > 0 && d.strain[k] <= 0.3 * e_max;
    e_max = std::max(e_max, d.strain[k]);
  }
  return toe;
}

// The force's decay at held strain (HoldDecay), from a model's residual: each hold at
// positive strain, from kHoldSettleS after it began, with at least kHoldMinS left, gives the
// mean of its first third minus the mean of its last third; the noise per row is estimated
// from successive differences within the hold.
constexpr double kHoldSettleS = 1.0;
constexpr double kHoldMinS = 2.0;
// Holds are flat when their summed decay is within kFlatHoldZ standard deviations of zero.
// Calibrated on hidden-effect trials (harder forms, seeds 10001-10030, 330 cases): without
// relaxation hidden, |z| <= 3.5 (stiffening, a set, none) or z <= -11.6 (softening that
// recovers at rest: the force rises); with relaxation, z >= 15.3, or below -5 when recovering
// softening outweighs it.
constexpr double kFlatHoldZ = 6.0;
constexpr int kFlatHoldMinHolds = 2;

bool hasEffect(const std::vector<std::string>& effects, const char* name) {
  return std::find(effects.begin(), effects.end(), name) != effects.end();
}

bool holdsAreFlat(const HoldDecay& h) { return h.holds >= kFlatHoldMinHolds && std::abs(h.z()) < kFlatHoldZ; }
bool forceRecovers(const HoldDecay& h) { return h.holds >= kFlatHoldMinHolds && h.z() <= -kFlatHoldZ; }

// Softening's signature (IdentifyResult::reload_slope_ratio): the reloadings' slope at a
// given force over the virgin loadings'. Loading rows outside holds are virgin at the
// largest strain so far, reloading below 0.95 of it; each run of rows of one kind gives a
// least-squares slope of force against strain over its rows whose force lies in the window
// (a wider one, 0.3-0.8, separated sets from softening less); the median of each kind is
// taken. -1 when either kind has no run of kSlopeMinRows rows in the window.
constexpr double kSlopeWindowLo = 0.15, kSlopeWindowHi = 0.4;  // x the largest reloading force
constexpr int kSlopeMinRows = 6;
double reloadSlopeRatio(const Data& d, const IdentifyResult& seg) {
  enum Kind : char { kOther, kVirgin, kReload };
  const TensionTest& t = *d.test;
  const size_t n = t.rows();
  std::vector<char> kind(n, kOther);
  double e_max = 0, f_reload_N = 0;
  for (size_t k = 0; k < n; ++k) {
    if (seg.time_in_hold_s[k] < 0 && d.rate[k] > 0) {
      if (d.strain[k] >= e_max) {
        kind[k] = kVirgin;
      } else if (d.strain[k] < 0.95 * e_max) {
        kind[k] = kReload;
        f_reload_N = std::max(f_reload_N, t.force_N[k]);
      }
    }
    e_max = std::max(e_max, d.strain[k]);
  }
  if (f_reload_N <= 0) return -1;
  const double lo_N = kSlopeWindowLo * f_reload_N, hi_N = kSlopeWindowHi * f_reload_N;
  auto medianSlope = [&](char which) {
    std::vector<double> slopes;
    for (size_t k = 0; k < n;) {
      if (kind[k] != which) {
        ++k;
        continue;
      }
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      int m = 0;
      for (; k < n && kind[k] == which; ++k) {
        if (t.force_N[k] < lo_N || t.force_N[k] > hi_N) continue;
        const double x = d.strain[k], y = t.force_N[k];
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++m;
      }
      const double den = m * sxx - sx * sx;
      if (m >= kSlopeMinRows && den > 0) slopes.push_back((m * sxy - sx * sy) / den);
    }
    if (slopes.empty()) return -1.0;
    std::nth_element(slopes.begin(), slopes.begin() + slopes.size() / 2, slopes.end());
    return slopes[slopes.size() / 2];
  };
  const double virgin = medianSlope(kVirgin), reload = medianSlope(kReload);
  return (virgin > 0 && reload > 0) ? reload / virgin : -1;
}

// Softening or a set without its signature is not a candidate (CandidateEvidence::
// without_signature):
// - softening alone, where the data's reloading slope ratio is at least
//   kSoftSingleSlopeRatio and the set alone fits the toe of the reloadings (toeRows) better
//   than softening alone;
// - softening and a set together, where the pair fits the toe no better than the set alone
//   (softening adds nothing there), or no better than kSetBesideSofteningToeRatio of
//   softening alone (nor does the set).
// On hidden-effect trials (calibration seeds 10001-10060) the ratio was 0.98-1.09 for sets
// that recover in slack (harder forms), 0.72-0.94 for softening by accumulated strain, but
// up to 1.01 for softening by the largest strain, which damages the virgin loading as it
// goes; the toe keeps that one. Where both were hidden, the pair's toe error was 0.11-0.97
// of the set's alone (harder forms; 0.03-0.55 other forms) and 0.04-0.84 of softening's
// alone (0.01-0.16); a shakedown ratchet named with softening raised the set's to 1.07-2.53,
// and a set fitted beside hidden softening left softening's at 0.96-1.12 (0.80-3.2)
// (docs/identification-trials.md, session 36).
constexpr double kSoftSingleSlopeRatio = 0.99;
constexpr double kSetBesideSofteningToeRatio = 0.9;

HoldDecay holdDecay(const Data& d, const IdentifyResult& seg, const FittedModel& m) {
  const TensionTest& t = *d.test;
  const size_t n = t.rows();
  HoldDecay h;
  double var = 0, force = 0;
  auto measure = [&](size_t a, size_t b) {  // rows [a, b) of one hold, settled
    if (b <= a || t.time_s[b - 1] - t.time_s[a] < kHoldMinS) return;
    double strain = 0;
    for (size_t k = a; k < b; ++k) strain += d.strain[k];
    if (strain / (b - a) <= 0.1 * d.max_strain) return;
    const size_t third = (b - a) / 3;
    if (third < 2) return;
    double first = 0, last = 0, f = 0, diff2 = 0;
    for (size_t k = a; k < a + third; ++k) first += t.force_N[k] - m.prediction_N[k];
    for (size_t k = b - third; k < b; ++k) last += t.force_N[k] - m.prediction_N[k];
    for (size_t k = a; k < b; ++k) f += t.force_N[k];
    for (size_t k = a + 1; k < b; ++k) {
      const double r1 = t.force_N[k] - m.prediction_N[k], r0 = t.force_N[k - 1] - m.prediction_N[k - 1];
      diff2 += (r1 - r0) * (r1 - r0);
    }
    const double row_var = diff2 / (2.0 * (b - a - 1));
    h.decay_N += (first - last) / third;
    var += 2.0 * row_var / third;
    force += f / (b - a);
    ++h.holds;
  };
  size_t a = n;
  for (size_t k = 0; k <= n; ++k) {
    const bool held = k < n && seg.time_in_hold_s[k] >= kHoldSettleS;
    if (held && a == n) a = k;
    if (!held && a != n) measure(a, k), a = n;
  }
  h.sd_N = std::sqrt(var);
  h.relative = force > 0 ? h.decay_N / force : 0.0;
  return h;
}

// RMS residual of a fitted model over the rows with mask[k] (0 without rows) [N].
double maskedRmse(const Data& d, const std::vector<bool>& mask, const FittedModel& m) {
  double s = 0;
  int count = 0;
  for (size_t k = 0; k < mask.size(); ++k)
    if (mask[k]) s += std::pow(m.prediction_N[k] - d.test->force_N[k], 2), ++count;
  return count ? std::sqrt(s / count) : 0.0;
}

// Two fitted Maxwell branches are resolved when they are two: their times apart by at least
// kBranchTimeRatio, the longer within the test (a longer time acts as elasticity over the
// test), and each branch at least kBranchWeightShare of their summed weight. Calibrated on
// own-form trials (seeds 10001-10030, one branch hidden): the second branch that paid there
// had times 1.0-1.3 apart (the branches are one, g split between them), a weight of
// 0.000-0.013 beside 0.28-0.44, or a time at the bound of 1e4 s; hidden two-branch data
// (--forms other) have times 7.5-120 apart and shares of at least 0.25.
constexpr double kBranchTimeRatio = 3.0;
constexpr double kBranchWeightShare = 0.1;

bool branchesResolved(const ExtendedLawParams& law, double duration_s) {
  const double lo = std::min(law.relax_tau1_s, law.relax_tau2_s), hi = std::max(law.relax_tau1_s, law.relax_tau2_s);
  const double g = law.relax_g1 + law.relax_g2;
  return hi >= kBranchTimeRatio * lo && hi <= duration_s &&
         std::min(law.relax_g1, law.relax_g2) >= kBranchWeightShare * g;
}

// Two unresolved Maxwell branches are one: a fit with two is fitted again with one branch,
// started from it (the weights summed, the time of the heavier branch).
Fit mergedBranches(const Data& d, const std::vector<int>& fold, const IdentifyOptions& o, const Fit& two) {
  const ExtendedLawParams& l = two.model.law;
  const std::vector<std::string>& e = two.model.effects;
  const double g_sum = std::min(0.95, l.relax_g1 + l.relax_g2);
  const double tau_heavy = l.relax_g1 >= l.relax_g2 ? l.relax_tau1_s : l.relax_tau2_s;
  return fitModel(d, e,
                  {thetaFrom(layout(d, e, false, two.ratchet), two.model, {{"relax_g1", g_sum}, {"relax_tau1_s", tau_heavy}})},
                  fold, o.folds, false, two.ratchet);
}

double duration(const Data& d) { return d.test->time_s.back() - d.test->time_s.front(); }

// Relaxation with a second Maxwell branch: a fit with relaxation and one branch is fitted
// again with two, started from the first (its g split in half, tau split fivefold either
// way); the second branch is kept when it pays for itself by the selection rule and the two
// branches are resolved. Unresolved, the two-branch fit may still have found a better
// optimum for the other parameters: one branch is fitted again from it and kept when it
// fits better than the first.
void secondBranch(const Data& d, const std::vector<int>& fold, const IdentifyOptions& o, Fit* fit) {
  const FittedModel& one = fit->model;
  const std::vector<std::string>& e = one.effects;
  if (fit->two_relax || std::find(e.begin(), e.end(), "stress_relaxation") == e.end()) return;
  const double g = one.law.relax_g1, tau = one.law.relax_tau1_s;
  const std::vector<ParamDef> defs = layout(d, e, true, fit->ratchet);
  Fit two = fitModel(d, e,
                     {thetaFrom(defs, one, {{"relax_g1", 0.5 * g}, {"relax_tau1_s", tau / 5},
                                            {"relax_g2", 0.5 * g}, {"relax_tau2_s", 5 * tau}})},
                     fold, o.folds, true, fit->ratchet);
  if (!candidatePays(one.heldout_rmse_N / std::max(two.model.heldout_rmse_N, 1e-300), two.model.bic - one.bic, o))
    return;
  if (branchesResolved(two.model.law, duration(d))) {
    *fit = std::move(two);
    return;
  }
  Fit merged = mergedBranches(d, fold, o, two);
  if (merged.model.rmse_N < one.rmse_N) *fit = std::move(merged);
}

// The set a fitted law leaves after the test [-]: r max(0, e_max - e_y) + c a_y.
double finalSet(const Data& d, const ExtendedLawParams& l) {
  return l.set_ratio * std::max(0.0, d.max_strain - l.set_yield_strain) +
         l.set_ratchet * loadingStrainAbove(d.strain, l.set_yield_strain);
}

// A ratcheting set is kept only when the set it leaves after the test is at least this
// fraction of the largest strain, with the ratchet inside its bounds. Calibrated on
// hidden-effect trials (harder forms, seeds 10001-10020): hidden sets leave 0.08-0.2 of the
// largest strain, and the ratchets fitted to them 0.095-0.29; on relaxation alone, a
// spectrum the law's one or two branches do not follow, a ratchet paid with a set of 0.003
// (its ratchet at the bound) and 0.022.
constexpr double kMinRatchetSetOverMaxStrain = 0.05;

// A set that ratchets: a fit with a set that grows with the largest strain only is fitted
// again with the ratchet (every loading past the yield strain adds set), started from it
// with the ratchet off and at ratchetScale; the ratchet is kept when it pays for itself
// against the plain set by the rule of a second effect (min_pair_heldout_ratio): it is one
// more parameter of the set, and with it the set can take over part of what softening does.
void ratchetVariant(const Data& d, const std::vector<int>& fold, const IdentifyOptions& o, Fit* fit) {
  const FittedModel& plain = fit->model;
  const std::vector<std::string>& e = plain.effects;
  if (fit->ratchet || !hasEffect(e, "permanent_set")) return;
  const std::vector<ParamDef> defs = layout(d, e, fit->two_relax, true);
  Fit r = fitModel(d, e,
                   {thetaFrom(defs, plain, {{"set_ratchet", 0.0}}),
                    thetaFrom(defs, plain, {{"set_ratchet", ratchetScale(d)}, {"set_ratio", 0.5 * plain.law.set_ratio}})},
                   fold, o.folds, fit->two_relax, true);
  const double ratio = plain.heldout_rmse_N / std::max(r.model.heldout_rmse_N, 1e-300);
  const auto bound = std::find_if(defs.begin(), defs.end(), [](const ParamDef& p) { return p.name == "set_ratchet"; });
  const bool resolved = finalSet(d, r.model.law) >= kMinRatchetSetOverMaxStrain * d.max_strain &&
                        r.model.law.set_ratchet < 0.999 * bound->hi;
  if (resolved && ratio >= o.min_pair_heldout_ratio && r.model.bic - plain.bic <= o.max_delta_bic) *fit = std::move(r);
}

}  // namespace

FittedModel fitTensionLaw(const TensionTest& test, const std::vector<std::string>& effects, const FittedModel* start) {
  Data d;
  d.test = &test;
  tensionStrainHistory(test, &d.strain, &d.rate);
  FittedModel base;
  if (start) base = *start;
  else {
    base.law.ea_N = 10;
    base.law.ec_Ns = 0.05;
    base.params = {{"EA_N", 10, 0, "N"}, {"EC_Ns", 0.05, 0, "N s"}, {"offset_N", 0, 0, "N"}};
  }
  d.max_strain = std::max(1e-3, *std::max_element(d.strain.begin(), d.strain.end()));
  auto hasParam = [&](const char* name) {
    return std::any_of(base.params.begin(), base.params.end(), [&](const ParamEstimate& p) { return p.name == name; });
  };
  const bool two_relax = hasParam("relax_g2"), ratchet = hasParam("set_ratchet");
  std::vector<double> th = thetaFrom(layout(d, effects, two_relax, ratchet), base, {});
  const std::vector<int> fold(test.rows(), 0);
  return fitModel(d, effects, {th}, fold, 1, two_relax, ratchet).model;
}

namespace {

// Averages consecutive rows in blocks of `block` (time, elongation and force alike).
TensionTest blockAverage(const TensionTest& t, size_t block) {
  TensionTest w;
  w.file = t.file;
  w.sample_length_m = t.sample_length_m;
  for (size_t a = 0; a < t.rows(); a += block) {
    const size_t b = std::min(t.rows(), a + block);
    double ts = 0, es = 0, fs = 0;
    for (size_t k = a; k < b; ++k) ts += t.time_s[k], es += t.elongation_m[k], fs += t.force_N[k];
    w.time_s.push_back(ts / (b - a));
    w.elongation_m.push_back(es / (b - a));
    w.force_N.push_back(fs / (b - a));
  }
  return w;
}

void prepare(const TensionTest& t, Data* d) {
  d->test = &t;
  tensionStrainHistory(t, &d->strain, &d->rate);
  d->max_strain = std::max(1e-3, *std::max_element(d->strain.begin(), d->strain.end()));
  d->total_loading_strain = loadingStrainAbove(d->strain, 0.0, 1e-3);
}

// Baseline start: linear least squares F = off + EA e + EC edot on the taut rows.
FittedModel linearStart(const Data& d) {
  const size_t n = d.test->rows();
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd y(n);
  int m = 0;
  for (size_t k = 0; k < n; ++k) {
    if (d.strain[k] <= 0) continue;
    A.row(m) << 1.0, d.strain[k], d.rate[k];
    y(m++) = d.test->force_N[k];
  }
  double ea = 10, ec = 0.05, off = 0;
  if (m >= 3) {
    const Eigen::Vector3d c = A.topRows(m).colPivHouseholderQr().solve(y.head(m));
    if (c.allFinite() && c(1) > 0) off = c(0), ea = c(1), ec = std::max(0.0, c(2));
  }
  FittedModel s;
  s.law.ea_N = ea;
  s.params = {{"EA_N", ea, 0, "N"}, {"EC_Ns", ec, 0, "N s"}, {"offset_N", off, 0, "N"}};
  return s;
}

// The diagnosis, for people: the baseline and where it fails, every candidate's evidence,
// the cause, the extended law and the gain, the remaining structure.
std::string diagnosisText(const IdentifyResult& r, const IdentifyOptions& o) {
  const Diagnostics& ed = r.extended_diagnostics;
  const Diagnostics& bd = r.baseline_diagnostics;
  std::string s = "Baseline: the paper's Voigt law (eq. 6), F = EA e + EC de/dt, fitted with Ceres: " +
                  fmt("EA = %.3g N, EC = %.3g N s, offset %.3g N.\n", r.baseline.law.ea_N, r.baseline.law.ec_Ns,
                      r.baseline.offset_N);
  s += fmt("  RMSE %.4f N (held-out %.4f N) against a white-noise level of %.4f N.\n", r.baseline.rmse_N,
           r.baseline.heldout_rmse_N, bd.noise_sd_N);
  s += "  Where it fails (RMS of the binned mean residual):";
  for (const ResidualProfile& p : bd.profiles) s += " " + p.variable + fmt(" %.4f N;", p.structure_N);
  s += "\n";
  const HoldDecay& h = r.hold_decay;
  if (h.holds > 0)
    s += fmt("At held strain (%.0f holds), the force decays by %.4f N in all (%.1f standard deviations", h.holds, h.decay_N,
             h.z()) +
         fmt(", %.2f %% of the force): ", 100 * h.relative) +
         (holdsAreFlat(h) ? "flat holds, so relaxation is not a candidate.\n"
          : h.z() > 0    ? "the signature of relaxation.\n"
                         : "the force recovers at rest.\n");
  if (r.reload_slope_ratio >= 0)
    s += fmt("On reloading, the slope at a given force is %.3f of the virgin loading's (softening lowers it, a set "
             "does not).\n",
             r.reload_slope_ratio);
  int round = 0;
  for (const CandidateEvidence& e : r.evidence) {
    if (e.round != round) {
      round = e.round;
      if (round == 2) {
        const auto first = std::find_if(r.evidence.begin(), r.evidence.end(),
                                        [](const CandidateEvidence& c) { return c.round == 1 && c.chosen; });
        s += "Round 2: every pair of effects, against " + (first != r.evidence.end() ? first->effect : "none") + "\n";
      } else
        s += fmt("Round %.0f: candidates added to ", round) +
             joinOrNone(std::vector<std::string>(e.model.begin(), e.model.end() - 1)) + "\n";
    }
    s += "  " + (e.round == 2 ? joinOrNone(e.model) : e.effect) + fmt(": held-out RMSE %.4f N (ratio %.3f), ", e.heldout_rmse_N, e.heldout_ratio) +
         fmt("dBIC %.1f, dAIC %.1f", e.delta_bic, e.delta_aic) +
         (e.signature_rmse_N >= 0 ? fmt(", toe of the reloadings %.4f N", e.signature_rmse_N) : "") +
         (holdsAreFlat(h) && hasEffect(e.model, "stress_relaxation") ? "  (no decay at held strain)" : "") +
         (e.without_signature ? "  (without its signature)" : "") +
         (e.chosen ? "  <- chosen" : e.pays ? "  (pays, not best)" : "") + "\n";
  }
  if (!r.refuted_effects.empty()) {
    s += "Cause: none. The selection chose " + joinOrNone(r.refuted_effects) +
         fmt(" on its working set, but refitted on every row its held-out gain is %.3f (<= 1): ",
             r.refuted_heldout_rmse_ratio) +
         "not a cause. No effect is named; the Voigt law is reported.\n";
  } else if (r.effects.empty()) {
    s += "Cause: none needed. No candidate pays for itself (held-out error cut by " +
         fmt("%.0f %% and BIC lowered by %.0f): ", 100 * (o.min_heldout_ratio - 1), -o.max_delta_bic) +
         "the Voigt law explains the data to the noise.\n";
  } else {
    s += "Cause: " + joinOrNone(r.effects) + ".\n";
    s += "Extended law:";
    for (const ParamEstimate& p : r.extended.params) s += " " + p.name + fmt(" = %.4g +- %.2g", p.value, p.sd) + " " + p.unit + ";";
    s += "\n" + fmt("Gain: held-out RMSE %.4f N -> %.4f N, ratio %.2f.\n", r.baseline.heldout_rmse_N,
                    r.extended.heldout_rmse_N, r.heldout_rmse_ratio);
  }
  s += fmt("Remaining structure: RMSE %.4f N = %.2f x the white-noise level", ed.rmse_N, ed.rmse_N / std::max(1e-12, ed.noise_sd_N)) +
       fmt(" (lag-1 autocorrelation %.2f); ", ed.lag1_autocorrelation) +
       (!r.refuted_effects.empty() ? "UNEXPLAINED: the selection found structure that no candidate confirms.\n"
        : r.unexplained ? "UNEXPLAINED: structure remains that no candidate effect explains.\n"
                      : "explained to the noise.\n");
  return s;
}

}  // namespace

IdentifyResult identifyTension(const TensionTest& test, const IdentifyOptions& o) {
  IdentifyResult r;
  Data d;
  prepare(test, &d);
  r.strain = d.strain;
  r.strain_rate_per_s = d.rate;
  segment(d, &r, o.folds);

  // Model selection runs on a working set of at most ~kWorkingRows rows: consecutive rows
  // averaged in blocks. The force varies slowly against the sampling interval of a long
  // test, so averaging keeps its information (and lowers the noise) at a fraction of the
  // cost. The two models reported are then refitted on every row.
  constexpr size_t kWorkingRows = 1000;
  const size_t block = test.rows() > 3 * kWorkingRows / 2 ? (test.rows() + kWorkingRows - 1) / kWorkingRows : 1;
  const TensionTest work = block > 1 ? blockAverage(test, block) : test;
  Data w;
  prepare(work, &w);
  IdentifyResult wr;
  segment(w, &wr, o.folds);
  // The reported models are scored on the selection's split: row k lies in block k / block
  // of the working set and takes its fold (one held-out measure, issue 17).
  for (size_t k = 0; k < test.rows(); ++k) r.fold[k] = wr.fold[std::min(k / block, wr.fold.size() - 1)];
  const FittedModel start = linearStart(w);
  w.ea_scale_N = d.ea_scale_N = std::max(1e-3, start.law.ea_N);

  // Progress in fits: the base, the single effects, relaxation's second branch and the set's
  // ratchet, every pair and the chosen pair's second branch, the two refits.
  const size_t n_effects = tensionEffectNames().size();
  const long n_pairs = static_cast<long>(n_effects * (n_effects - 1) / 2);
  const long planned = 1 + static_cast<long>(n_effects) + 2 + (o.max_effects >= 2 ? n_pairs + 1 : 0) + 2;
  std::atomic<long> fits_done{0};
  auto fitted = [&] {
    const long done = ++fits_done;
    if (o.on_progress) o.on_progress(done, planned);
  };
  const Fit base = fitModel(w, {}, {thetaFrom(layout(w, {}), start, {})}, wr.fold, o.folds);
  fitted();
  r.hold_decay = holdDecay(w, wr, base.model);
  r.reload_slope_ratio = reloadSlopeRatio(w, wr);

  // Round 1: each effect alone. Relaxation is fitted with one Maxwell branch, then with a
  // second started from the first (tau split fivefold either way); the second branch is
  // kept when it pays for itself against the first by the selection rule and the two are
  // resolved (branchesResolved). The candidates
  // are independent fits: two threads (this machine has two cores).
  const std::vector<std::string>& names = tensionEffectNames();
  std::vector<Fit> singles(n_effects);
  runInParallel(n_effects, o.threads, [&](size_t i) {
    singles[i] = fitModel(w, {names[i]}, startsFor(w, base.model, names[i]), wr.fold, o.folds);
    fitted();
    if (names[i] == "permanent_set") {
      ratchetVariant(w, wr.fold, o, &singles[i]);
      fitted();
    }
    if (names[i] != "stress_relaxation") return;
    secondBranch(w, wr.fold, o, &singles[i]);
    fitted();
  });
  std::vector<Candidate> round1(n_effects);
  // Relaxation without decay at held strain is not relaxation (HoldDecay): with flat holds,
  // no model with it is a candidate.
  const bool flat_holds = holdsAreFlat(r.hold_decay);
  // Softening's signature (kSoftSingleSlopeRatio): the reloadings' slope, and the toe.
  auto effectIndex = [&](const char* name) -> size_t { return std::find(names.begin(), names.end(), name) - names.begin(); };
  const std::vector<bool> toe = toeRows(w, wr);
  std::vector<double> toe_rmse_N(n_effects);
  for (size_t i = 0; i < n_effects; ++i) toe_rmse_N[i] = maskedRmse(w, toe, singles[i].model);
  const double set_toe_rmse_N = toe_rmse_N[effectIndex("permanent_set")];
  const double soft_toe_rmse_N = toe_rmse_N[effectIndex("cyclic_softening")];
  const bool toe_measured = std::find(toe.begin(), toe.end(), true) != toe.end();
  const bool soft_single_without_signature =
      toe_measured && r.reload_slope_ratio >= kSoftSingleSlopeRatio && set_toe_rmse_N < soft_toe_rmse_N;
  std::vector<bool> no_signature(n_effects);
  for (size_t i = 0; i < n_effects; ++i) {
    const std::vector<std::string>& m = singles[i].model.effects;
    no_signature[i] = soft_single_without_signature && hasEffect(m, "cyclic_softening");
    round1[i].effect = names[i], round1[i].score = singles[i].model;
    round1[i].admissible = !(flat_holds && hasEffect(m, "stress_relaxation")) && !no_signature[i];
  }
  const size_t ev1 = r.evidence.size();
  const int first = weighRound(1, base.model, round1, o, &r.evidence);
  for (size_t i = 0; i < n_effects; ++i) {
    r.evidence[ev1 + i].signature_rmse_N = toe_rmse_N[i];
    r.evidence[ev1 + i].without_signature = no_signature[i];
  }
  Fit current = first >= 0 ? singles[first] : base;
  if (first >= 0) r.effects = {names[first]};

  // Round 2: every pair of effects (six with four effects), each started from both of its
  // single fits, weighed against the first effect by the same rule with the held-out ratio
  // of a second effect (min_pair_heldout_ratio). Greedy forward
  // selection would only try pairs with the first effect, and a first effect chosen because
  // it mimics part of two others would stay in a wrong pair. A pair is ordered by its
  // members' single held-out errors (the better first): the candidate is the second member
  // added to the first.
  if (first >= 0 && o.max_effects >= 2) {
    auto single = [&](const char* name) -> const Fit& { return singles[effectIndex(name)]; };
    const bool two_relax = single("stress_relaxation").two_relax, ratchet = single("permanent_set").ratchet;
    std::vector<std::pair<size_t, size_t>> pairs;
    for (size_t a = 0; a < n_effects; ++a)
      for (size_t b = a + 1; b < n_effects; ++b)
        pairs.push_back(singles[a].model.heldout_rmse_N <= singles[b].model.heldout_rmse_N ? std::make_pair(a, b)
                                                                                           : std::make_pair(b, a));
    std::vector<Fit> cands(pairs.size());
    runInParallel(pairs.size(), o.threads, [&](size_t i) {
      const auto [a, b] = pairs[i];
      // The parameter layout does not depend on the order of the effects.
      // A third start: the better single with the other effect switched off, the single fit
      // itself, so that a pair never ends worse than the model it contains (from the two
      // starts above alone, 10 % of the pairs containing the first effect fitted worse than it
      // on hidden-effect trials, dBIC > 20).
      const std::vector<std::vector<double>> starts = {startsFor(w, singles[a].model, names[b], two_relax, ratchet).front(),
                                                       startsFor(w, singles[b].model, names[a], two_relax, ratchet).front(),
                                                       switchedOff(w, singles[a].model, names[b], singles[b].model, two_relax, ratchet)};
      cands[i] = fitModel(w, {names[a], names[b]}, starts, wr.fold, o.folds, two_relax, ratchet);
      // The set's ratchet, decided alone, is tried again beside the other effect (whose
      // misfit can hide it, or mimic it).
      ratchetVariant(w, wr.fold, o, &cands[i]);
      fitted();
    });
    // A second effect pays by min_pair_heldout_ratio. Force that recovers at held strain
    // (HoldDecay z below -kFlatHoldZ) is the signature of softening that heals at rest, which
    // the softening law has not: its misfit is the size of the first effect's, so a pair with
    // softening then pays by the rule of a single effect.
    const bool heals = forceRecovers(r.hold_decay);
    std::vector<Candidate> round2(pairs.size());
    std::vector<double> pair_toe_rmse_N(pairs.size());
    std::vector<bool> pair_no_signature(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) {
      const std::vector<std::string>& m = cands[i].model.effects;
      pair_toe_rmse_N[i] = maskedRmse(w, toe, cands[i].model);
      pair_no_signature[i] = toe_measured && hasEffect(m, "cyclic_softening") && hasEffect(m, "permanent_set") &&
                             (pair_toe_rmse_N[i] >= set_toe_rmse_N ||
                              pair_toe_rmse_N[i] >= kSetBesideSofteningToeRatio * soft_toe_rmse_N);
      round2[i].effect = names[pairs[i].second], round2[i].score = cands[i].model;
      round2[i].admissible = !(flat_holds && hasEffect(m, "stress_relaxation")) && !pair_no_signature[i];
      if (!(heals && hasEffect(m, "cyclic_softening"))) round2[i].min_heldout_ratio = o.min_pair_heldout_ratio;
    }
    const size_t ev0 = r.evidence.size();
    int best = weighRound(2, current.model, round2, o, &r.evidence);
    // Signatures: a set with a stiffening curve can mimic softening (a shifted exponential is
    // a scaled one) and relaxation can mimic a set, everywhere but at the toe of the
    // reloadings, where force starts. Among the paying pairs whose held-out ratio is within
    // signature_ratio_window of the best one, the pair with the smallest toe error is named.
    for (size_t i = 0; i < pairs.size(); ++i) {
      r.evidence[ev0 + i].signature_rmse_N = pair_toe_rmse_N[i];
      r.evidence[ev0 + i].without_signature = pair_no_signature[i];
    }
    if (best >= 0) {
      const double best_ratio = r.evidence[ev0 + best].heldout_ratio;
      r.evidence[ev0 + best].chosen = false;
      for (size_t i = 0; i < pairs.size(); ++i) {
        const CandidateEvidence& e = r.evidence[ev0 + i];
        if (e.pays && e.heldout_ratio * o.signature_ratio_window >= best_ratio &&
            e.signature_rmse_N < r.evidence[ev0 + best].signature_rmse_N)
          best = static_cast<int>(i);
      }
      r.evidence[ev0 + best].chosen = true;
    }
    if (best >= 0) {
      current = std::move(cands[best]);
      r.effects = {names[pairs[best].first], names[pairs[best].second]};
      // The pairs took the relaxation form of the single fit, decided without the other
      // effect (whose misfit can hide the second branch): the chosen pair tries it again.
      // A pair that took two branches from the single fit keeps them only when they are
      // still resolved with its other effect (which can take over what the second branch did).
      if (!current.two_relax) secondBranch(w, wr.fold, o, &current);
      else if (!branchesResolved(current.model.law, duration(w))) current = mergedBranches(w, wr.fold, o, current);
    }
  }

  // The reported models, on every row.
  if (block > 1) {
    r.baseline = fitModel(d, {}, {base.theta}, r.fold, o.folds).model;
    r.extended = current.model.effects.empty()
                     ? r.baseline
                     : fitModel(d, current.model.effects, {current.theta}, r.fold, o.folds, current.two_relax,
                                current.ratchet).model;
  } else {
    r.baseline = base.model;
    r.extended = current.model;
  }
  r.working_rows = static_cast<int>(work.rows());
  r.heldout_rmse_ratio = r.baseline.heldout_rmse_N / r.extended.heldout_rmse_N;
  r.baseline_diagnostics = diagnose(d, r, r.baseline);
  // One held-out measure: an effect whose reported gain is not above 1 is not a cause.
  const bool refuted = !r.effects.empty() && !gainConfirmed(r.heldout_rmse_ratio);
  if (refuted) {
    r.refuted_effects = r.effects;
    r.refuted_heldout_rmse_ratio = r.heldout_rmse_ratio;
    r.effects.clear();
    r.extended = r.baseline;
    r.heldout_rmse_ratio = 1;
  }
  r.extended_diagnostics = diagnose(d, r, r.extended);
  r.unexplained = refuted || isUnexplained(r.extended_diagnostics, o);

  r.diagnosis = diagnosisText(r, o);
  if (o.on_progress) o.on_progress(planned, planned);
  return r;
}

}  // namespace colosim
