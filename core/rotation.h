// Rotation math on SO(3) as small free functions.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/spline.h"

namespace colosim {

/// [w]x: the skew-symmetric matrix with [w]x v = w x v.
inline Mat3 skew(const Vec3& w) {
  Mat3 s;
  s << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return s;
}

/// exp([w]x): rotation by |w| [rad] about w / |w| (Rodrigues' formula).
inline Mat3 expSO3(const Vec3& w) {
  const double t = w.norm();
  const Mat3 W = skew(w);
  if (t < 1e-8) return Mat3::Identity() + W + 0.5 * W * W;
  return Mat3::Identity() + (std::sin(t) / t) * W + ((1 - std::cos(t)) / (t * t)) * W * W;
}

/// log(R): the rotation vector w with exp([w]x) = R, |w| <= pi [rad].
inline Vec3 logSO3(const Mat3& R) {
  const double c = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  const double t = std::acos(c);
  const Vec3 v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  if (t < 1e-6) return 0.5 * v;  // sin t ~ t
  if (t > M_PI - 1e-6) {
    // Near pi: axis from the symmetric part, sign from v.
    const Mat3 B = 0.5 * (R + Mat3::Identity());
    int k;
    B.diagonal().maxCoeff(&k);
    Vec3 axis = B.col(k) / std::sqrt(std::max(B(k, k), 1e-300));
    if (axis.dot(v) < 0) axis = -axis;
    return t * axis.normalized();
  }
  return (t / (2 * std::sin(t))) * v;
}

/// Inverse of the right Jacobian of SO(3) at w: a right perturbation exp(w) exp(d) equals
/// exp(w + Jr^{-1}(w) d) to first order.
inline Mat3 rightJacobianInverse(const Vec3& w) {
  const double t = w.norm();
  const Mat3 W = skew(w);
  double a;  // (1/t^2) - (1 + cos t) / (2 t sin t), -> 1/12 as t -> 0
  if (t < 1e-4) a = 1.0 / 12.0 + t * t / 720.0;
  else a = 1.0 / (t * t) - (1 + std::cos(t)) / (2 * t * std::sin(t));
  return Mat3::Identity() + 0.5 * W + a * W * W;
}

/// log(R), as logSO3(R), and the inverse of the right Jacobian at it, as
/// rightJacobianInverse(log(R)), sharing the trigonometry of the two.
inline Vec3 logSO3WithJacobian(const Mat3& R, Mat3* jr_inverse) {
  const double c = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  const double t = std::acos(c);
  // Near 0 and near pi (where 1 + cos t cancels) the separate functions' forms.
  if (t < 1e-4 || t > 3.0) {
    const Vec3 w = logSO3(R);
    *jr_inverse = rightJacobianInverse(w);
    return w;
  }
  const Vec3 v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const double s = std::sin(t);
  const Vec3 w = (t / (2 * s)) * v;
  // I + W / 2 + a W^2 with W^2 = w w^T - |w|^2 I and |w| = t: (1 - a t^2) I + W / 2 + a w w^T,
  // where 1 - a t^2 = t (1 + cos t) / (2 sin t).
  const double b = t * (1 + c) / (2 * s);
  const double a = 1.0 / (t * t) - b / (t * t);
  *jr_inverse = b * Mat3::Identity() + 0.5 * skew(w) + a * (w * w.transpose());
  return w;
}

/// Makes R orthonormal again (Gram-Schmidt on its columns, keeping the third column's
/// direction: the scope's axis).
inline void orthonormalize(Mat3& R) {
  Vec3 z = R.col(2).normalized();
  Vec3 x = (R.col(0) - R.col(0).dot(z) * z).normalized();
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
}

}  // namespace colosim
