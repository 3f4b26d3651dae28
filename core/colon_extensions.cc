#include "core/colon_extensions.h"

#include <algorithm>
#include <cmath>

#include "core/colon_model.h"

namespace colosim {

BendingResponse bendingAtPoint(const Vec3& q_prev, const Vec3& q, const Vec3& q_next, double theta0,
                               double EI, double L) {
  BendingResponse r;
  for (auto& f : r.force_N) f.setZero();
  for (auto& row : r.stiffness_N_per_m)
    for (auto& k : row) k.setZero();
  const Vec3 a = q - q_prev, b = q_next - q;
  const double la = a.norm(), lb = b.norm();
  if (!(la > 0) || !(lb > 0) || !(EI > 0)) return r;
  const Vec3 ta = a / la, tb = b / lb;
  const double theta = turningAngle(a, b);
  const double c = EI / L;  // [N m]
  r.theta_rad = theta;
  r.energy_J = 0.5 * c * (theta - theta0) * (theta - theta0);

  const Vec3 dt = tb - ta;
  const double dt_norm = dt.norm();  // 2 sin(theta / 2)
  const double cos_half = std::max(0.1, std::cos(0.5 * theta));
  // J blocks: d(dt)/dq_{i-1}, d(dt)/dq_i, d(dt)/dq_{i+1} (symmetric 3 x 3 each).
  const Mat3 Ja = (Mat3::Identity() - ta * ta.transpose()) / la;
  const Mat3 Jb = (Mat3::Identity() - tb * tb.transpose()) / lb;
  const std::array<Mat3, 3> J = {Ja, -(Ja + Jb), Jb};

  Mat3 S;
  if (dt_norm > 1e-12) {
    const Vec3 nrm = dt / dt_norm;
    const double fprime = c * (theta - theta0) / cos_half;  // dE/d|dt| [N m]
    for (int j = 0; j < 3; ++j) r.force_N[j] = -fprime * (J[j] * nrm);
    const Mat3 nn = nrm * nrm.transpose();
    S = (c / (cos_half * cos_half)) * nn;
    if (theta >= theta0) S += (fprime / dt_norm) * (Mat3::Identity() - nn);
  } else {
    // Straight: no direction to push in; the tangent's limit for theta0 = 0 (c J^T J)
    // keeps the solve well posed when the point is about to bend.
    S = c * Mat3::Identity();
  }
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) r.stiffness_N_per_m[j][k] = J[j] * S * J[k];
  return r;
}

}  // namespace colosim
