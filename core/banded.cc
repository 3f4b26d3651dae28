#include "core/banded.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

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

namespace {

// The factorisation and the solves for a half-bandwidth B known at compile time (the
// colon's 11): the same operations in the same order as the general loops below, so the
// same bits, but with fixed trip counts in the rows past the first B the compiler
// unrolls them (the general loop spent ~10 instructions per multiply-add on bounds).
template <int B>
bool factorizeFixed(double* a, int m) {
  constexpr int w = B + 1;
  for (int i = 0; i < m; ++i) {
    double* ri = a + static_cast<std::size_t>(i) * w;
    if (i < B) {  // first rows: fewer than B entries left of the diagonal
      for (int j = 0; j <= i; ++j) {
        const double* rj = a + static_cast<std::size_t>(j) * w;
        const double* li = ri + (B - i);
        const double* lj = rj + (B - j);
        double s = ri[j - i + B];
        for (int t = 0; t < j; ++t) s -= li[t] * lj[t];
        if (j == i) {
          if (!(s > 0.0)) return false;
          ri[B] = std::sqrt(s);
        } else {
          ri[j - i + B] = s / rj[B];
        }
      }
      continue;
    }
    // Row i >= B: column j = i - B + jj sits at offset jj of row i and at offset B of
    // row j; the dot product runs over columns i - B .. j - 1 (jj terms).
#pragma GCC unroll 12
    for (int jj = 0; jj < B; ++jj) {
      const double* rj = ri - static_cast<std::ptrdiff_t>(B - jj) * w;
      const double* lj = rj + (B - jj);
      double s = ri[jj];
      for (int t = 0; t < jj; ++t) s -= ri[t] * lj[t];
      ri[jj] = s / rj[B];
    }
    double s = ri[B];
    for (int t = 0; t < B; ++t) s -= ri[t] * ri[t];
    if (!(s > 0.0)) return false;
    ri[B] = std::sqrt(s);
  }
  return true;
}

template <int B>
void solveFixed(const double* a, int m, double* x) {
  constexpr int w = B + 1;
  for (int i = 0; i < m; ++i) {
    const double* ri = a + static_cast<std::size_t>(i) * w;
    double s = x[i];
    if (i < B) {
      for (int j = 0; j < i; ++j) s -= ri[j - i + B] * x[j];
    } else {
      const double* xj = x + (i - B);
      for (int t = 0; t < B; ++t) s -= ri[t] * xj[t];
    }
    x[i] = s / ri[B];
  }
  for (int i = m - 1; i >= 0; --i) {
    const double* ri = a + static_cast<std::size_t>(i) * w;
    x[i] /= ri[B];
    const double xi = x[i];
    if (i < B) {
      for (int j = 0; j < i; ++j) x[j] -= ri[j - i + B] * xi;
    } else {
      double* xj = x + (i - B);
      for (int t = 0; t < B; ++t) xj[t] -= ri[t] * xi;
    }
  }
}

}  // namespace

bool BandedSpd::factorizeLeading(int m) {
  if (b_ == 11) return factorizeFixed<11>(a_.data(), m);
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
  if (b_ == 11) return solveFixed<11>(a_.data(), m, x);
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
