#include "core/banded.h"
#include "core/block_tridiagonal.h"

#include <limits>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace colosim {
namespace {

TEST(BandedSpd, SolveMatchesDenseCholesky) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 60, b = 11;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - b); j < i; ++j) dense(i, j) = dense(j, i) = u(rng);
  for (int i = 0; i < n; ++i) dense(i, i) = 2.0 * b + 1.0;  // diagonally dominant: SPD
  BandedSpd band(n, b);
  for (int i = 0; i < n; ++i)
    for (int j = std::max(0, i - b); j <= i; ++j) band.lower(i, j) = dense(i, j);

  Eigen::VectorXd x = Eigen::VectorXd::Random(n), y(n);
  band.multiply(x.data(), y.data());
  EXPECT_LT((y - dense * x).norm(), 1e-12);

  Eigen::VectorXd rhs = Eigen::VectorXd::Random(n);
  Eigen::VectorXd sol = rhs;
  ASSERT_TRUE(band.factorize());
  band.solveInPlace(sol.data());
  const Eigen::VectorXd ref = dense.llt().solve(rhs);
  EXPECT_LT((sol - ref).norm(), 1e-12 * ref.norm());
}

TEST(BandedSpd, RefusesAnIndefiniteMatrix) {
  BandedSpd band(3, 1);
  band.lower(0, 0) = 1;
  band.lower(1, 1) = 1;
  band.lower(2, 2) = 1;
  band.lower(1, 0) = 2;  // eigenvalues of [[1,2],[2,1]] include -1
  EXPECT_FALSE(band.factorize());
}


// The scope's block-tridiagonal Cholesky against a dense factorisation of the same matrix,
// on the leading blocks of storage sized for more (as the scope uses it).
TEST(BlockTridiagonal, SolvesAsTheDenseCholeskyOnTheLeadingBlocks) {
  constexpr int B = 6;
  const int blocks = 9, used = 7, n = used * B;
  BlockTridiagonal<B> a;
  a.resize(blocks);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < used; ++k) {
    Eigen::Matrix<double, B, B> g;
    for (int i = 0; i < B; ++i)
      for (int j = 0; j < B; ++j) g(i, j) = u(rng);
    a.diag(k) = g * g.transpose() + 8.0 * Eigen::Matrix<double, B, B>::Identity();
    dense.block<B, B>(k * B, k * B) = a.diag(k);
    if (k + 1 < used) {
      for (int i = 0; i < B; ++i)
        for (int j = 0; j < B; ++j) a.below(k)(i, j) = u(rng);
      dense.block<B, B>((k + 1) * B, k * B) = a.below(k);
      dense.block<B, B>(k * B, (k + 1) * B) = a.below(k).transpose();
    }
  }
  ASSERT_TRUE(a.factorize(used));
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) rhs(i) = u(rng);
  Eigen::VectorXd x = rhs;
  a.solveInPlace(used, x.data());
  const Eigen::VectorXd want = dense.llt().solve(rhs);
  EXPECT_LT((x - want).norm(), 1e-12 * want.norm());
  EXPECT_LT((dense * x - rhs).norm(), 1e-12 * rhs.norm());
}

TEST(BlockTridiagonal, RefusesAMatrixThatIsNotPositiveDefinite) {
  BlockTridiagonal<6> a;
  a.resize(3);
  for (int k = 0; k < 3; ++k) a.diag(k) = Eigen::Matrix<double, 6, 6>::Identity();
  a.below(0) = 2.0 * Eigen::Matrix<double, 6, 6>::Identity();  // |E| > D: indefinite
  EXPECT_FALSE(a.factorize(3));
  a.below(0).setZero();
  EXPECT_TRUE(a.factorize(3));
  a.diag(1)(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(a.factorize(3));
}

}  // namespace
}  // namespace colosim
