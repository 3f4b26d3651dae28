#include "core/banded.h"

#include <algorithm>
#include <cmath>

namespace colosim {

// Row i of the storage holds A(i, i-b .. i) at offsets 0 .. b (entries left of column 0
// in the first rows are unused zeros), so L(i, k) is row_i[k - i + b].

void BandedSpd::multiply(const double* x, double* y) const {
  const int w = b_ + 1;
  for (int i = 0; i < n_; ++i) y[i] = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double* row = &a_[static_cast<std::size_t>(i) * w];
    y[i] += row[b_] * x[i];
    for (int j = std::max(0, i - b_); j < i; ++j) {
      const double v = row[j - i + b_];
      y[i] += v * x[j];
      y[j] += v * x[i];
    }
  }
}

bool BandedSpd::factorizeLeading(int m) {
  const int w = b_ + 1;
  for (int i = 0; i < m; ++i) {
    double* ri = &a_[static_cast<std::size_t>(i) * w];
    const int j0 = std::max(0, i - b_);
    for (int j = j0; j <= i; ++j) {
      const double* rj = &a_[static_cast<std::size_t>(j) * w];
      // s = A(i, j) - sum_{k = j0 .. j-1} L(i, k) L(j, k): two contiguous runs.
      const double* li = ri + (j0 - i + b_);
      const double* lj = rj + (j0 - j + b_);
      double s = ri[j - i + b_];
      for (int t = 0, len = j - j0; t < len; ++t) s -= li[t] * lj[t];
      if (j == i) {
        if (!(s > 0.0)) return false;
        ri[b_] = std::sqrt(s);
      } else {
        ri[j - i + b_] = s / rj[b_];
      }
    }
  }
  return true;
}

void BandedSpd::solveLeadingInPlace(int m, double* x) const {
  const int w = b_ + 1;
  // Forward: L y = rhs
  for (int i = 0; i < m; ++i) {
    const double* ri = &a_[static_cast<std::size_t>(i) * w];
    const int j0 = std::max(0, i - b_);
    double s = x[i];
    for (int j = j0; j < i; ++j) s -= ri[j - i + b_] * x[j];
    x[i] = s / ri[b_];
  }
  // Backward: L^T x = y
  for (int i = m - 1; i >= 0; --i) {
    const double* ri = &a_[static_cast<std::size_t>(i) * w];
    x[i] /= ri[b_];
    const int j0 = std::max(0, i - b_);
    for (int j = j0; j < i; ++j) x[j] -= ri[j - i + b_] * x[i];
  }
}

}  // namespace colosim
