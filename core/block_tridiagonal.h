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

#include <vector>

#include <Eigen/Cholesky>
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
      Eigen::LLT<Block> llt(s);
      if (llt.info() != Eigen::Success) return false;
      l_[k] = llt.matrixL();
      if (k + 1 < m) {
        // F_k = E_k L_k^{-T}: solve F_k L_k^T = E_k, i.e. L_k F_k^T = E_k^T.
        f_[k] = l_[k].template triangularView<Eigen::Lower>().solve(e_[k].transpose()).transpose();
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
      l_[k].template triangularView<Eigen::Lower>().solveInPlace(xk);
    }
    // Backward: L^T x = y.
    for (int k = m - 1; k >= 0; --k) {
      Eigen::Map<Vec> xk(x + k * B);
      if (k + 1 < m) xk.noalias() -= f_[k].transpose() * Eigen::Map<const Vec>(x + (k + 1) * B);
      l_[k].transpose().template triangularView<Eigen::Upper>().solveInPlace(xk);
    }
  }

 private:
  std::vector<Block> d_, e_, l_, f_;
};

}  // namespace colosim
