// A symmetric positive definite block-tridiagonal matrix with fixed-size blocks, and its
// block Cholesky factorisation: the colonoscope's implicit system (6 unknowns per
// segment; a joint couples two consecutive segments).
//
//   A = [D0 E0^T          ]      L = [L0              ]
//       [E0 D1   E1^T     ]          [F0 L1           ]     A = L L^T
//       [   E1   D2   ... ]          [   F1 L2        ]
//
// with L_k = chol(D_k - F_{k-1} F_{k-1}^T) and F_k = E_k L_k^{-T}. Fixed work per block,
// no allocation after resize(), the same operations in the same order every time.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace colosim {

template <int B>
class BlockTridiagonal {
 public:
  using Block = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;

  /// Room for up to `blocks` diagonal blocks.
  void resize(int blocks) {
    d_.assign(blocks, Block::Zero());
    e_.assign(blocks, Block::Zero());
    l_.assign(blocks, Block::Zero());
    f_.assign(blocks, Block::Zero());
    inv_diag_.assign(blocks, Vec::Zero());
  }
  /// Zeroes the first m diagonal blocks and the m - 1 blocks below them.
  void setZero(int m) {
    for (int k = 0; k < m; ++k) d_[k].setZero(), e_[k].setZero();
  }
  /// Diagonal block k, and the block below it, E_k = A(k+1, k).
  Block& diag(int k) { return d_[k]; }
  Block& below(int k) { return e_[k]; }

  /// Factorises the leading m x m blocks. False when a pivot block is not positive definite.
  bool factorize(int m) {
    for (int k = 0; k < m; ++k) {
      Block s = d_[k];
      if (k > 0) s.noalias() -= f_[k - 1] * f_[k - 1].transpose();
      // L_k by Cholesky-Crout, written out (the lower triangle; the upper stays 0 from
      // resize()), keeping the pivots' reciprocals for the substitutions.
      Block& l = l_[k];
      Vec& inv = inv_diag_[k];
#pragma GCC unroll 8
      for (int j = 0; j < B; ++j) {
        double v = s(j, j);
        for (int p = 0; p < j; ++p) v -= l(j, p) * l(j, p);
        if (!(v > 0)) return false;  // not positive definite (or not finite)
        l(j, j) = std::sqrt(v);
        inv(j) = 1.0 / l(j, j);
        for (int i = j + 1; i < B; ++i) {
          double w = s(i, j);
          for (int p = 0; p < j; ++p) w -= l(i, p) * l(j, p);
          l(i, j) = w * inv(j);
        }
      }
      if (k + 1 < m) {
        // F_k = E_k L_k^{-T}: solve F_k L_k^T = E_k, i.e. L_k F_k^T = E_k^T, by forward
        // substitution.
        Block& f = f_[k];
#pragma GCC unroll 8
        for (int c = 0; c < B; ++c)
#pragma GCC unroll 8
          for (int i = 0; i < B; ++i) {
            double v = e_[k](c, i);
            for (int j = 0; j < i; ++j) v -= l(i, j) * f(c, j);
            f(c, i) = v * inv(i);
          }
      }
    }
    return true;
  }

  /// Solves A x = rhs in place for the leading m blocks (rhs: m * B values).
  void solveInPlace(int m, double* x) const {
    // Forward: L y = b.
    for (int k = 0; k < m; ++k) {
      Eigen::Map<Vec> xk(x + k * B);
      if (k > 0) xk.noalias() -= f_[k - 1] * Eigen::Map<const Vec>(x + (k - 1) * B);
      const Block& l = l_[k];
      for (int i = 0; i < B; ++i) {
        double v = xk(i);
        for (int j = 0; j < i; ++j) v -= l(i, j) * xk(j);
        xk(i) = v * inv_diag_[k](i);
      }
    }
    // Backward: L^T x = y.
    for (int k = m - 1; k >= 0; --k) {
      Eigen::Map<Vec> xk(x + k * B);
      if (k + 1 < m) xk.noalias() -= f_[k].transpose() * Eigen::Map<const Vec>(x + (k + 1) * B);
      const Block& l = l_[k];
      for (int i = B - 1; i >= 0; --i) {
        double v = xk(i);
        for (int j = i + 1; j < B; ++j) v -= l(j, i) * xk(j);
        xk(i) = v * inv_diag_[k](i);
      }
    }
  }

 private:
  std::vector<Block> d_, e_, l_, f_;
  std::vector<Vec> inv_diag_;  // 1 / diag(L_k)
};

}  // namespace colosim
