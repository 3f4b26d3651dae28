// A symmetric positive definite banded matrix with an in-place Cholesky factorisation.
//
// Eigen has no banded solver, and its sparse Cholesky allocates on every numeric
// factorisation; the colon's implicit system is a block band of fixed width (the
// Catmull-Rom blending couples control points at most 3 apart), so a dense band
// Cholesky is both simpler and allocation-free after resize(): O(N b^2) per factorisation
// for N unknowns and half-bandwidth b.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <vector>

namespace colosim {

class BandedSpd {
 public:
  BandedSpd() = default;
  BandedSpd(int size, int half_bandwidth) { resize(size, half_bandwidth); }

  /// Allocates an N x N matrix of half-bandwidth b (entries with |i - j| <= b), all zero.
  void resize(int size, int half_bandwidth) {
    n_ = size;
    b_ = half_bandwidth;
    a_.assign(static_cast<std::size_t>(n_) * (b_ + 1), 0.0);
  }
  void setZero() { std::fill(a_.begin(), a_.end(), 0.0); }

  int size() const { return n_; }
  int halfBandwidth() const { return b_; }

  /// Lower-triangle entry (i, j), i >= j, i - j <= b.
  double& lower(int i, int j) {
    assert(i >= j && i - j <= b_ && i < n_ && j >= 0);
    return a_[static_cast<std::size_t>(i) * (b_ + 1) + (j - i + b_)];
  }
  double lower(int i, int j) const {
    assert(i >= j && i - j <= b_ && i < n_ && j >= 0);
    return a_[static_cast<std::size_t>(i) * (b_ + 1) + (j - i + b_)];
  }
  /// Adds v to the symmetric entry pair (i, j) and (j, i).
  void add(int i, int j, double v) {
    if (i >= j) lower(i, j) += v; else lower(j, i) += v;
  }
  /// Symmetric entry (i, j), zero outside the band.
  double at(int i, int j) const {
    if (i < j) std::swap(i, j);
    return (i - j <= b_) ? lower(i, j) : 0.0;
  }

  /// y = A x (x and y of length N, distinct).
  void multiply(const double* x, double* y) const;

  /// Replaces the matrix by its Cholesky factor L (A = L L^T). Returns false, leaving
  /// the matrix in an undefined state, when a pivot is not positive (not SPD).
  bool factorize() { return factorizeLeading(n_); }
  /// Solves L L^T x = rhs in place, after factorize().
  void solveInPlace(double* x) const { solveLeadingInPlace(n_, x); }
  /// The same on the leading m x m block only (rows and columns 0 .. m-1), for systems
  /// whose size changes during a run inside storage sized once for the largest.
  bool factorizeLeading(int m);
  void solveLeadingInPlace(int m, double* x) const;

  /// Raw band storage (N x (b + 1)), for copying a precomputed matrix.
  const std::vector<double>& data() const { return a_; }
  void copyFrom(const BandedSpd& other) {
    assert(other.n_ == n_ && other.b_ == b_);
    std::copy(other.a_.begin(), other.a_.end(), a_.begin());
  }

 private:
  int n_ = 0;
  int b_ = 0;
  std::vector<double> a_;  // row i holds A(i, i-b), ..., A(i, i-1), A(i, i): contiguous dot products
};

}  // namespace colosim
