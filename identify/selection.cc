#include "identify/selection.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

namespace colosim {

double akaikeCriterion(double sse, int n, int p) { return n * std::log(std::max(sse, 1e-300) / n) + 2 * p; }

double bayesianCriterion(double sse, int n, int p) {
  return n * std::log(std::max(sse, 1e-300) / n) + p * std::log(static_cast<double>(n));
}

void scoreFit(double sse, int n, ModelScore* m) {
  m->rmse_N = std::sqrt(sse / n);
  m->aic = akaikeCriterion(sse, n, m->n_params);
  m->bic = bayesianCriterion(sse, n, m->n_params);
}

bool candidatePays(double heldout_ratio, double delta_bic, const IdentifyOptions& o) {
  return heldout_ratio >= o.min_heldout_ratio && delta_bic <= o.max_delta_bic;
}

int weighRound(int round, const ModelScore& current, const std::vector<Candidate>& candidates,
               const IdentifyOptions& o, std::vector<CandidateEvidence>* evidence) {
  int best = -1;
  const size_t first = evidence->size();
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Candidate& c = candidates[i];
    CandidateEvidence e;
    e.round = round;
    e.effect = c.effect;
    e.model = c.score.effects;
    e.value = c.value;
    e.rmse_N = c.score.rmse_N;
    e.heldout_rmse_N = c.score.heldout_rmse_N;
    e.heldout_ratio = current.heldout_rmse_N / std::max(c.score.heldout_rmse_N, 1e-300);
    e.delta_aic = c.score.aic - current.aic;
    e.delta_bic = c.score.bic - current.bic;
    e.pays = c.admissible && e.heldout_ratio >= c.min_heldout_ratio && candidatePays(e.heldout_ratio, e.delta_bic, o);
    e.simulations = c.simulations;
    evidence->push_back(e);
    if (e.pays && (best < 0 || e.heldout_ratio > (*evidence)[first + best].heldout_ratio))
      best = static_cast<int>(i);
  }
  if (best >= 0) (*evidence)[first + best].chosen = true;
  return best;
}

bool gainConfirmed(double heldout_rmse_ratio) { return heldout_rmse_ratio > 1.0; }

bool noCandidateCanPay(double heldout_rmse_N, double noise_sd_N, const IdentifyOptions& o) {
  return heldout_rmse_N < o.min_heldout_ratio * noise_sd_N;
}

void runInParallel(size_t n, int threads, const std::function<void(size_t)>& job) {
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < n; i = next++) job(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

ResidualProfile residualProfile(const std::string& variable, const std::vector<double>& residual_N,
                                const std::vector<int>& bin, int nbins) {
  ResidualProfile p;
  p.variable = variable;
  p.mean_residual_N.assign(nbins, 0.0);
  p.count.assign(nbins, 0);
  for (size_t k = 0; k < residual_N.size(); ++k) {
    if (bin[k] < 0) continue;
    p.mean_residual_N[bin[k]] += residual_N[k];
    ++p.count[bin[k]];
  }
  double s2 = 0;
  int total = 0;
  for (int b = 0; b < nbins; ++b) {
    if (p.count[b]) p.mean_residual_N[b] /= p.count[b];
    s2 += p.count[b] * p.mean_residual_N[b] * p.mean_residual_N[b];
    total += p.count[b];
  }
  p.structure_N = total ? std::sqrt(s2 / total) : 0;
  return p;
}

double upperMedian(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double whiteNoiseSd(const std::vector<double>& residual_N) {
  std::vector<double> diff;
  for (size_t k = 1; k < residual_N.size(); ++k) diff.push_back(residual_N[k] - residual_N[k - 1]);
  const double md = upperMedian(diff);
  for (double& x : diff) x = std::abs(x - md);
  return 1.4826 * upperMedian(diff) / std::sqrt(2.0);
}

Diagnostics diagnoseResidual(double rmse_N, const std::vector<double>& residual_N) {
  Diagnostics d;
  d.rmse_N = rmse_N;
  d.noise_sd_N = whiteNoiseSd(residual_N);
  d.rmse_over_noise = d.noise_sd_N > 0 ? d.rmse_N / d.noise_sd_N : 0;
  return d;
}

bool isUnexplained(const Diagnostics& d, const IdentifyOptions& o) {
  return d.rmse_over_noise > o.unexplained_rmse_over_noise;
}

}  // namespace colosim
