// Colon model extensions that the paper (Kuehl & Dumont) leaves out, used by the colon step
// when switched on (issue 7; docs/organ-identification.md). Both are off by default, and
// then the step is bit-identical to the paper's model.
//
// colon_bending: the paper's colon resists only stretching (eq. 6) and the lifters
// (eqs. 4-5); a real colon wall also resists bending. At each interior control point i the
// discrete bending energy of an elastic rod is
//   E_i = EI / (2 L_i) (theta_i - theta0_i)^2                                   [J]
// with theta_i the turning angle between elements a = q_i - q_{i-1} and b = q_{i+1} - q_i
// (theta0_i at rest), L_i = (l0_{i-1} + l0_i) / 2 the length the point stands for and EI
// the bending rigidity [N m^2]. Discrete curvature kappa = theta / L, so the restoring
// moment is EI (kappa - kappa0), the continuum rod's. The angle depends only on the shape,
// so rigid motions of the colon cost nothing (the sigmoid may swing freely).
// Gradient: with t_a = a/|a|, t_b = b/|b|, dt = t_b - t_a, |dt| = 2 sin(theta/2) and
// J = d(dt)/dx (J_{i-1} = P_a/|a|, J_{i+1} = P_b/|b|, J_i = -(J_{i-1} + J_{i+1}),
// P_x = I - t_x t_x^T), d theta = n^T J dx / cos(theta/2), n = dt / |dt|. Hence
//   f_j = -c (theta - theta0) / cos(theta/2) J_j^T n,   c = EI / L_i.
// Tangent (Gauss-Newton, positive semi-definite): J^T S J with
//   S = c / cos^2(theta/2) n n^T + [theta >= theta0] c (theta - theta0) / (cos(theta/2) |dt|) (I - n n^T)
// (the second, geometric part is kept only while the angle exceeds its rest value, as the
// tension element keeps its geometric stiffness only in tension). For theta0 = 0 it tends
// to c J^T J as theta -> 0: smooth through the straight configuration. cos(theta/2) is
// floored at 0.1 (theta < 169 degrees) so a point folded back on itself stays finite.
//
// mesentery_stiffening: the paper's lifters are linear springs of density k0 [N/m per m]
// (eq. 4). Stiffening lifters have the secant stiffness k(d) = k0 (1 + beta d^2) at a spline
// point displaced by u = M(s) - M0(s), d = |u|, i.e. the energy density
//   w(u) = k0 (d^2 / 2 + beta d^4 / 4)                                          [J/m]
// and force density -k0 (1 + beta d^2) u [N/m], whose tangent is
//   -d f / d u = k0 ((1 + beta d^2) I + 2 beta u u^T)  (symmetric positive definite).
// beta [1/m^2] = 1 / d0^2 with d0 the displacement at which the lifters are twice as stiff.
// The linear part stays in the constant matrix K of eq. 4; the step adds the rest by Gauss
// quadrature over each segment (4 points, as K).
#pragma once

#include <array>

#include "core/spline.h"

namespace colosim {

/// Bending of one interior control point (the energy above).
struct BendingResponse {
  double theta_rad = 0;               ///< turning angle theta [rad]
  double energy_J = 0;                ///< E_i [J]
  std::array<Vec3, 3> force_N;        ///< on q_{i-1}, q_i, q_{i+1} [N]
  std::array<std::array<Mat3, 3>, 3> stiffness_N_per_m;  ///< Gauss-Newton -df_j/dq_k [N/m]
};

/// Bending energy, forces and tangent at a control point q between q_prev and q_next with
/// rest angle theta0_rad, rigidity EI_Nm2 [N m^2] and length L_m [m].
BendingResponse bendingAtPoint(const Vec3& q_prev, const Vec3& q, const Vec3& q_next, double theta0_rad,
                               double EI_Nm2, double L_m);

/// Force density of a stiffening lifter at displacement u [m]: -k0 (1 + beta d^2) u [N/m].
inline Vec3 lifterForceDensity(const Vec3& u_m, double k0_N_per_m2, double beta_per_m2) {
  return -k0_N_per_m2 * (1.0 + beta_per_m2 * u_m.squaredNorm()) * u_m;
}
/// Its part beyond the linear lifter, -k0 beta d^2 u [N/m], and that part's tangent
/// k0 beta (d^2 I + 2 u u^T) [N/m per m].
inline Vec3 lifterStiffeningForceDensity(const Vec3& u_m, double k0_N_per_m2, double beta_per_m2) {
  return -k0_N_per_m2 * beta_per_m2 * u_m.squaredNorm() * u_m;
}
inline Mat3 lifterStiffeningTangent(const Vec3& u_m, double k0_N_per_m2, double beta_per_m2) {
  return k0_N_per_m2 * beta_per_m2 * (u_m.squaredNorm() * Mat3::Identity() + 2.0 * u_m * u_m.transpose());
}
/// Energy density of the stiffening beyond the linear lifter, k0 beta d^4 / 4 [J/m].
inline double lifterStiffeningEnergyDensity(const Vec3& u_m, double k0_N_per_m2, double beta_per_m2) {
  const double d2 = u_m.squaredNorm();
  return 0.25 * k0_N_per_m2 * beta_per_m2 * d2 * d2;
}

}  // namespace colosim
