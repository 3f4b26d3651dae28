#include "core/banded.h"

#include <algorithm>
#include <cmath>

namespace colosim {

void BandedSpd::multiply(const double* x, double* y) const {
  for (int i = 0; i < n_; ++i) y[i] = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double* row = &a_[static_cast<size_t>(i) * (b_ + 1)];
    y[i] += row[0] * x[i];
    const int kmax = std::min(b_, i);
    for (int k = 1; k <= kmax; ++k) {
      const int j = i - k;
      y[i] += row[k] * x[j];
      y[j] += row[k] * x[i];
    }
  }
}

bool BandedSpd::factorize() {
  const int w = b_ + 1;
  for (int i = 0; i < n_; ++i) {
    double* ri = &a_[static_cast<size_t>(i) * w];
    const int j0 = std::max(0, i - b_);
    for (int j = j0; j <= i; ++j) {
      const double* rj = &a_[static_cast<size_t>(j) * w];
      // s = A(i, j) - sum_{k = j0 .. j-1} L(i, k) L(j, k)
      double s = ri[i - j];
      const int k0 = std::max(j0, j - b_);
      for (int k = k0; k < j; ++k) s -= ri[i - k] * rj[j - k];
      if (j == i) {
        if (!(s > 0.0)) return false;
        ri[0] = std::sqrt(s);
      } else {
        ri[i - j] = s / rj[0];
      }
    }
  }
  return true;
}

void BandedSpd::solveInPlace(double* x) const {
  const int w = b_ + 1;
  // Forward: L y = rhs
  for (int i = 0; i < n_; ++i) {
    const double* ri = &a_[static_cast<size_t>(i) * w];
    double s = x[i];
    const int j0 = std::max(0, i - b_);
    for (int j = j0; j < i; ++j) s -= ri[i - j] * x[j];
    x[i] = s / ri[0];
  }
  // Backward: L^T x = y
  for (int i = n_ - 1; i >= 0; --i) {
    const double* ri = &a_[static_cast<size_t>(i) * w];
    x[i] /= ri[0];
    const int j0 = std::max(0, i - b_);
    for (int j = j0; j < i; ++j) x[j] -= ri[i - j] * x[i];
  }
}

}  // namespace colosim
