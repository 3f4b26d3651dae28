#include "core/colon_extensions.h"

#include <algorithm>
#include <cmath>

#include "core/colon_model.h"

namespace colosim {

BendingResponse bendingAtPoint(const Vec3& q_prev, const Vec3& q, const Vec3& q_next, double theta0,
                               double EI, double L) {
  BendingResponse r;
  for (auto& f : r.force_N) f.setZero();
  const Vec3 a = q - q_prev, b = q_next - q;
  const double la = a.norm(), lb = b.norm();
  if (!(la > 0) || !(lb > 0) || !(EI > 0)) {
    for (auto& row : r.stiffness_N_per_m)
      for (auto& k : row) k.setZero();
    return r;
  }
  const Vec3 ta = a / la, tb = b / lb;
  const double theta = turningAngle(a, b);
  const double c = EI / L;  // [N m]
  r.theta_rad = theta;
  r.energy_J = 0.5 * c * (theta - theta0) * (theta - theta0);

  const Vec3 dt = tb - ta;
  const double dt_norm = dt.norm();  // 2 sin(theta / 2)
  const double cos_half = std::max(0.1, std::cos(0.5 * theta));
  // d(dt)/dq_{i-1}, d(dt)/dq_i, d(dt)/dq_{i+1} are Ja, -(Ja + Jb), Jb with the symmetric
  // Ja = Pa / la, Jb = Pb / lb (Pa, Pb: projectors off ta, tb), and the tangent on |dt| is
  // S = alpha n n^T + beta (I - n n^T). Each block J_j S J_k is then a combination of
  //   A = Ja S Ja = beta Pa / la^2 + (alpha - beta) ua ua^T,   (ua = Ja n, ub = Jb n)
  //   B = Ja S Jb = beta Pa Pb / (la lb) + (alpha - beta) ua ub^T,
  //   C = Jb S Jb = beta Pb / lb^2 + (alpha - beta) ub ub^T.
  const Mat3 Pa = Mat3::Identity() - ta * ta.transpose();
  const Mat3 Pb = Mat3::Identity() - tb * tb.transpose();
  double alpha = c, beta = c;  // straight: the tangent's limit for theta0 = 0 (c J^T J)
  Vec3 ua = Vec3::Zero(), ub = Vec3::Zero();
  if (dt_norm > 1e-12) {
    const Vec3 nrm = dt / dt_norm;
    ua = (Pa * nrm) / la;
    ub = (Pb * nrm) / lb;
    const double fprime = c * (theta - theta0) / cos_half;  // dE/d|dt| [N m]
    r.force_N[0] = -fprime * ua;
    r.force_N[1] = fprime * (ua + ub);
    r.force_N[2] = -fprime * ub;
    alpha = c / (cos_half * cos_half);
    beta = theta >= theta0 ? fprime / dt_norm : 0.0;
  }
  // (Straight: no direction to push in; the limit keeps the solve well posed when the
  // point is about to bend.)
  const double g = alpha - beta;
  const Mat3 A = (beta / (la * la)) * Pa + g * ua * ua.transpose();
  const Mat3 B = (beta / (la * lb)) * (Pa * Pb) + g * ua * ub.transpose();
  const Mat3 C = (beta / (lb * lb)) * Pb + g * ub * ub.transpose();
  auto& K = r.stiffness_N_per_m;
  K[0][0] = A;
  K[0][2] = B;
  K[2][0] = B.transpose();
  K[2][2] = C;
  K[0][1] = -(A + B);
  K[1][0] = K[0][1].transpose();
  K[2][1] = -(K[2][0] + C);
  K[1][2] = K[2][1].transpose();
  K[1][1] = A + B + K[2][0] + C;
  return r;
}

}  // namespace colosim
