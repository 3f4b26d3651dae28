#include "identify/tension/forward.h"

#include <algorithm>

namespace colosim {

void tensionStrainHistory(const TensionTest& t, std::vector<double>* strain, std::vector<double>* rate) {
  const size_t n = t.rows();
  strain->resize(n);
  rate->resize(n);
  for (size_t k = 0; k < n; ++k) (*strain)[k] = t.elongation_m[k] / t.sample_length_m;
  for (size_t k = 0; k < n; ++k)
    (*rate)[k] = k == 0 ? 0.0 : ((*strain)[k] - (*strain)[k - 1]) / (t.time_s[k] - t.time_s[k - 1]);
}

void simulateLawForce(const TensionLaw& law, const std::vector<double>& time_s,
                      const std::vector<double>& strain, const std::vector<double>& rate,
                      std::vector<double>* force_N) {
  const size_t n = time_s.size();
  force_N->resize(n);
  double z[16];
  const int zs = law.internalSize();
  std::vector<double> zbig;
  double* zp = z;
  if (zs > 16) {
    zbig.resize(zs);
    zp = zbig.data();
  }
  law.initInternal(zp);
  for (size_t k = 0; k < n; ++k) {
    const double dt = k + 1 < n ? time_s[k + 1] - time_s[k] : (n > 1 ? time_s[k] - time_s[k - 1] : 1e-3);
    (*force_N)[k] = law.evaluate(strain[k], rate[k], dt, zs ? zp : nullptr).force_N;
    if (zs && k + 1 < n) law.advance(strain[k + 1], rate[k + 1], dt, zp);
  }
}

void benchForce(const TensionLaw& law, double offset_N, const std::vector<double>& time_s,
                const std::vector<double>& strain, const std::vector<double>& rate,
                std::vector<double>* measured_N) {
  simulateLawForce(law, time_s, strain, rate, measured_N);
  for (double& f : *measured_N) f = offset_N + std::max(0.0, f);
}

}  // namespace colosim
