#include "core/banded.h"

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

}  // namespace
}  // namespace colosim
