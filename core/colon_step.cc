#include "core/colon_step.h"

#include <algorithm>
#include <cmath>

#include "core/colon_extensions.h"

namespace colosim {

namespace {

// Adds the 3 x 3 block B at block position (I, J) of the symmetric system, and its
// transpose at (J, I): only the lower triangle is stored, so a diagonal block adds its
// lower part and an off-diagonal block is stored once, below the diagonal.
inline void addBlock(BandedSpd& a, int I, int J, const Mat3& B, double scale = 1.0) {
  // In the band's rows, entry (i + r, j + c) lies r * b + c after entry (i, j).
  const int b = a.halfBandwidth();
  if (I == J) {
    double* p = &a.lower(3 * I, 3 * I);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c <= r; ++c) p[r * b + c] += scale * B(r, c);
  } else if (I > J) {
    double* p = &a.lower(3 * I, 3 * J);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) p[r * b + c] += scale * B(r, c);
  } else {
    double* p = &a.lower(3 * J, 3 * I);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) p[c * b + r] += scale * B(r, c);
  }
}

// y.col(i) += s * sum_l A(i, l) x.col(l) for a scalar band matrix A over control points.
void addScalarBandTimes(const ScalarBand& A, const double* x, double s, double* y) {
  const int n = A.size(), b = A.halfBandwidth();
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k <= std::min(b, i); ++k) {
      const int l = i - k;
      const double a = s * A.lower(i, l);
      for (int d = 0; d < 3; ++d) y[3 * i + d] += a * x[3 * l + d];
      if (k > 0)
        for (int d = 0; d < 3; ++d) y[3 * l + d] += a * x[3 * i + d];
    }
  }
}

double scalarBandQuadratic(const ScalarBand& A, const double* x) {
  double e = 0;
  const int n = A.size(), b = A.halfBandwidth();
  for (int i = 0; i < n; ++i)
    for (int k = 0; k <= std::min(b, i); ++k) {
      const int l = i - k;
      double dot = 0;
      for (int d = 0; d < 3; ++d) dot += x[3 * i + d] * x[3 * l + d];
      e += (k == 0 ? 1.0 : 2.0) * A.lower(i, l) * dot;
    }
  return e;
}

// (Re)builds M + dt C + dt^2 K of the mesentery, expanded to 3-D, for this dt.
void buildConstantSystem(const ColonModel& m, ColonState& s, double dt) {
  BandedSpd& a = s.constant_system;
  a.setZero();
  for (int i = 0; i < m.n; ++i)
    for (int l = std::max(0, i - 3); l <= i; ++l) {
      const double v = m.mass.lower(i, l) + dt * m.mesentery_C.lower(i, l) +
                       dt * dt * m.mesentery_K.lower(i, l);
      for (int d = 0; d < 3; ++d) a.lower(3 * i + d, 3 * l + d) = v;
    }
  s.constant_system_dt_s = dt;
  s.gauss_blend.clear();
  s.gauss_rest_m.clear();
  s.gauss_rest_tangent.clear();
  for (int j = 0; j + 1 < m.n; ++j)
    for (int g = 0; g < Gauss4::kCount; ++g) {
      s.gauss_blend.push_back(blend(m.n, j, Gauss4::node[g], 0));
      s.gauss_rest_m.push_back(apply(s.gauss_blend.back(), m.q_rest));
      const Vec3 tangent = apply(blend(m.n, j, Gauss4::node[g], 1), m.q_rest);
      s.gauss_rest_tangent.push_back(tangent.norm() > 0 ? Vec3(tangent.normalized()) : Vec3::Zero());
    }
}

// Spreads a load at a spline point (blending b) over its 4 control points: f_i += w_a F,
// rhs_i -= dt^2 w_a K v_point, and (w_a w_c) H into the system's block (i, l) for l <= i,
// with F the force [N], Kv = K v_point its stiffness times the point's velocity [N/s]
// and H = dt C + dt^2 K its implicit part.
void spreadPointLoad(const Blend& b, const Vec3& force_N, const Vec3& Kv, const Mat3& H, double dt, double* f,
                     double* rhs, BandedSpd& system) {
  for (int a = 0; a < 4; ++a) {
    const int i = b.index[a];
    for (int c = 0; c < 3; ++c) {
      f[3 * i + c] += b.w[a] * force_N(c);
      rhs[3 * i + c] -= dt * dt * b.w[a] * Kv(c);
    }
    for (int c2 = 0; c2 < 4; ++c2) {
      const int l = b.index[c2];
      if (i >= l) addBlock(system, i, l, H, b.w[a] * b.w[c2]);
    }
  }
}

// ---------------------------------------------------------------------------------------
// The stages of stepColon(), in order. Each adds its forces to s.force, its -dt^2 K v to
// s.rhs and its dt C + dt^2 K to s.system.

// Constant part of the system (mass and mesentery), rebuilt only when dt changes.
void startSystem(const ColonModel& m, ColonState& s, double dt) {
  if (s.constant_system_dt_s != dt) buildConstantSystem(m, s, dt);
  s.system.copyFrom(s.constant_system);
}

// Gravity, f = (M 1) g (sets the forces).
void setGravity(const ColonModel& m, ColonState& s) {
  double* f = s.force.data();
  for (int i = 0; i < m.n; ++i)
    for (int d = 0; d < 3; ++d) f[3 * i + d] = m.mass_rowsum_kg(i) * m.gravity_m_per_s2(d);
}

// Mesentery lifters (eqs. 4-5): f -= K (q - q0) + C v; rhs = -dt^2 K v (sets the rhs).
void addMesentery(const ColonModel& m, ColonState& s, double dt) {
  const int n = m.n;
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  const double* q = s.q.data();
  const double* v = s.v.data();
  double* dq = s.scratch.data();
  for (int k = 0; k < 3 * n; ++k) dq[k] = q[k] - m.q_rest.data()[k];
  addScalarBandTimes(m.mesentery_K, dq, -1.0, f);
  addScalarBandTimes(m.mesentery_C, v, -1.0, f);
  for (int k = 0; k < 3 * n; ++k) rhs[k] = 0.0;
  addScalarBandTimes(m.mesentery_K, v, -dt * dt, rhs);
}

// Tension elements (eq. 6) between consecutive control points; records each element's
// force in s.tension_force_N.
void addTensionElements(const ColonModel& m, ColonState& s, double dt) {
  const int n = m.n;
  const int zs = m.tension_law->internalSize();
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  for (int e = 0; e + 1 < n; ++e) {
    const Vec3 d = s.q.col(e + 1) - s.q.col(e);
    const double l = d.norm();
    const double l0 = m.rest_length_m(e);
    const Vec3 u = d / l;
    const Vec3 dv = s.v.col(e + 1) - s.v.col(e);
    const double strain = (l - l0) / l0;
    const double strain_rate = u.dot(dv) / l0;
    TensionResponse r =
        m.tension_law->evaluate(m.lawStrain(strain), strain_rate, dt, zs ? &s.tension_internal[e * zs] : nullptr);
    if (strain < 0) r.dforce_dstrain_N *= m.compression_stiffness_fraction;  // dF/de = c dF/d(c e)
    s.tension_force_N(e) = r.force_N;
    const Vec3 fe = r.force_N * u;  // pulls e+1 towards e and e towards e+1 in tension
    for (int c = 0; c < 3; ++c) {
      f[3 * e + c] += fe(c);
      f[3 * (e + 1) + c] -= fe(c);
    }
    // Tangent stiffness: material part along u, geometric part across u (kept only in
    // tension, so that the matrix stays positive definite); damping along u.
    const Mat3 uu = u * u.transpose();
    Mat3 K = (r.dforce_dstrain_N / l0) * uu;
    if (r.force_N > 0) K += (r.force_N / l) * (Mat3::Identity() - uu);
    const Mat3 C = (r.dforce_dstrainrate_Ns / l0) * uu;
    const Vec3 Kdv = K * dv;  // K (v_{e+1} - v_e): the rhs term -dt^2 K v
    for (int c = 0; c < 3; ++c) {
      rhs[3 * e + c] += dt * dt * Kdv(c);
      rhs[3 * (e + 1) + c] -= dt * dt * Kdv(c);
    }
    const Mat3 H = dt * C + dt * dt * K;
    addBlock(s.system, e, e, H);
    addBlock(s.system, e + 1, e + 1, H);
    addBlock(s.system, e + 1, e, -H);
  }
}

// Stiffening lifters (mesentery_stiffening, colon_extensions.h): the part beyond the
// linear K of eq. 4, by 4-point Gauss quadrature over each segment, each node's force
// spread like a load.
void addLifterStiffening(const ColonModel& m, ColonState& s, double dt) {
  const int n = m.n;
  const double beta = m.mesentery_stiffening_per_m2;
  for (int j = 0; j + 1 < n; ++j) {
    const double k0 = m.segment_k_N_per_m2(j);
    if (!(k0 > 0)) continue;
    for (int g = 0; g < Gauss4::kCount; ++g) {
      const Blend& b = s.gauss_blend[j * Gauss4::kCount + g];
      const double w = Gauss4::weight[g] * m.segment_length_m(j);  // [m]
      const Vec3 u = apply(b, s.q) - s.gauss_rest_m[j * Gauss4::kCount + g];
      const Vec3 fd = w * lifterStiffeningForceDensity(u, k0, beta);  // [N]
      const Mat3 T = w * lifterStiffeningTangent(u, k0, beta);        // [N/m]
      const Vec3 Tv = T * apply(b, s.v);
      const Mat3 H = dt * dt * T;
      spreadPointLoad(b, fd, Tv, H, dt, s.force.data(), s.rhs.data(), s.system);
    }
  }
}

// Lifters along the colon (ColonModel::mesentery_axial_ratio a < 1): the part of eq. 4's
// isotropic lifter along the rest tangent t taken back, (1 - a) k0 (u . t) t, by the same
// 4-point Gauss quadrature (exact for the cubic blends' products), each node's force spread
// like a load with its (negative) stiffness -(1 - a) k0 t t^T; the sum with eq. 4's K stays
// positive semi-definite. The lifters' damping (eq. 5) stays isotropic.
void addLifterAxialRelief(const ColonModel& m, ColonState& s, double dt) {
  const double relief = 1.0 - m.mesentery_axial_ratio;
  for (int j = 0; j + 1 < m.n; ++j) {
    const double k0 = m.segment_k_N_per_m2(j);
    if (!(k0 > 0)) continue;
    for (int g = 0; g < Gauss4::kCount; ++g) {
      const int node = j * Gauss4::kCount + g;
      const Blend& b = s.gauss_blend[node];
      const Vec3& t = s.gauss_rest_tangent[node];
      const double kw = relief * k0 * Gauss4::weight[g] * m.segment_length_m(j);  // [N/m]
      const Vec3 u = apply(b, s.q) - s.gauss_rest_m[node];
      const Vec3 fd = kw * u.dot(t) * t;         // [N]
      const Mat3 T = -kw * (t * t.transpose());  // [N/m]
      const Vec3 Tv = T * apply(b, s.v);
      spreadPointLoad(b, fd, Tv, dt * dt * T, dt, s.force.data(), s.rhs.data(), s.system);
    }
  }
}

// Bending of the colon wall (colon_bending, colon_extensions.h) at interior control points.
void addWallBending(const ColonModel& m, ColonState& s, double dt) {
  const int n = m.n;
  const double dt2 = dt * dt;
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  for (int i = 1; i + 1 < n; ++i) {
    const BendingResponse r = bendingAtPoint(s.q.col(i - 1), s.q.col(i), s.q.col(i + 1),
                                             m.bend_rest_angle_rad(i), m.bending_EI_Nm2, m.bend_length_m(i));
    const Vec3 v0 = s.v.col(i - 1), v1 = s.v.col(i), v2 = s.v.col(i + 1);
    for (int j = 0; j < 3; ++j) {
      const auto& K = r.stiffness_N_per_m[j];
      const Vec3 Kv = K[0] * v0 + K[1] * v1 + K[2] * v2;
      double* fj = f + 3 * (i - 1 + j);
      double* rj = rhs + 3 * (i - 1 + j);
      for (int c = 0; c < 3; ++c) {
        fj[c] += r.force_N[j](c);
        rj[c] -= dt2 * Kv(c);
      }
      for (int k = 0; k <= j; ++k) addBlock(s.system, i - 1 + j, i - 1 + k, K[k], dt2);
    }
  }
}

// External loads (contacts, abdominal pressure) at spline points.
void addSplineLoads(const ColonModel& m, ColonState& s, double dt) {
  for (const SplineLoad& load : s.loads) {
    const Blend b = blend(m.n, load.segment, load.p, 0);
    const Vec3 v_point = apply(b, s.v);
    const Vec3 Kv = load.stiffness_N_per_m * v_point;
    const Mat3 H = dt * load.damping_Ns_per_m + dt * dt * load.stiffness_N_per_m;
    spreadPointLoad(b, load.force_N, Kv, H, dt, s.force.data(), s.rhs.data(), s.system);
  }
}

// Solve (M + dt C + dt^2 K) dv = dt f - dt^2 K v, dv left in s.rhs. Returns s.solver_ok:
// false when the factorisation failed or the solve gave a non-finite value.
bool solveVelocityChange(const ColonModel& m, ColonState& s, double dt) {
  const int n = m.n;
  const double* f = s.force.data();
  double* rhs = s.rhs.data();
  for (int k = 0; k < 3 * n; ++k) rhs[k] += dt * f[k];
  s.limited_points = 0;
  s.asked_speed_m_per_s = 0;
  s.solver_ok = s.system.factorize();
  if (s.solver_ok) {
    s.system.solveInPlace(rhs);
    for (int k = 0; k < 3 * n; ++k) s.solver_ok = s.solver_ok && std::isfinite(rhs[k]);
  }
  return s.solver_ok;
}

// Integrate: v += dv, q += dt v. Limit: a control point faster than the solve is trusted
// with is slowed to that speed.
void integratePoints(const ColonModel& m, ColonState& s, double dt) {
  const int n = m.n;
  const double* rhs = s.rhs.data();
  double* vw = s.v.data();
  for (int i = 0; i < n; ++i) {
    Eigen::Map<Vec3> vi(vw + 3 * i);
    vi += Eigen::Map<const Vec3>(rhs + 3 * i);
    const double speed = vi.norm();
    s.asked_speed_m_per_s = std::max(s.asked_speed_m_per_s, speed);
    if (speed > m.max_speed_m_per_s) {
      vi *= m.max_speed_m_per_s / speed;
      ++s.limited_points;
    }
  }
  double* qw = s.q.data();
  for (int k = 0; k < 3 * n; ++k) qw[k] += dt * vw[k];
}

// Internal variables of history-dependent tension laws, at the end of the step.
void advanceTensionInternals(const ColonModel& m, ColonState& s, double dt) {
  const int zs = m.tension_law->internalSize();
  for (int e = 0; e + 1 < m.n; ++e) {
    double strain, strain_rate;
    elementStrain(m, s, e, &strain, &strain_rate);
    m.tension_law->advance(m.lawStrain(strain), strain_rate, dt, &s.tension_internal[e * zs]);
  }
}

}  // namespace

void elementStrain(const ColonModel& m, const ColonState& s, int e, double* strain,
                   double* strain_rate) {
  const Vec3 d = s.q.col(e + 1) - s.q.col(e);
  const double l = d.norm();
  const double l0 = m.rest_length_m(e);
  *strain = (l - l0) / l0;
  *strain_rate = (l > 0) ? d.dot(s.v.col(e + 1) - s.v.col(e)) / (l * l0) : 0.0;
}

void stepColon(const ColonModel& m, ColonState& s, double dt) {
  // Forces and the system: the constant part (mass, mesentery), gravity, the mesentery's
  // forces, the tension elements, the extensions the model switches on, the loads.
  startSystem(m, s, dt);
  setGravity(m, s);
  addMesentery(m, s, dt);
  addTensionElements(m, s, dt);
  if (m.mesentery_stiffening_per_m2 > 0) addLifterStiffening(m, s, dt);
  if (m.mesentery_axial_ratio < 1) addLifterAxialRelief(m, s, dt);
  if (m.bending_EI_Nm2 > 0) addWallBending(m, s, dt);
  addSplineLoads(m, s, dt);
  // Solve. Limit: the colon stops for this step rather than carry NaN on.
  if (!solveVelocityChange(m, s, dt)) {
    s.v.setZero();
    s.time_s += dt;
    return;
  }
  // Integrate (with the speed limit), then the tension laws' history.
  integratePoints(m, s, dt);
  s.time_s += dt;
  if (m.tension_law->internalSize() > 0) advanceTensionInternals(m, s, dt);
}

ColonEnergy colonEnergy(const ColonModel& m, const ColonState& s) {
  ColonEnergy en;
  en.kinetic_J = 0.5 * scalarBandQuadratic(m.mass, s.v.data());
  Points dq = s.q - m.q_rest;
  en.mesentery_J = 0.5 * scalarBandQuadratic(m.mesentery_K, dq.data());
  const int zs = m.tension_law->internalSize();
  for (int e = 0; e + 1 < m.n; ++e) {
    double strain, rate;
    elementStrain(m, s, e, &strain, &rate);
    // Shortened: the integral of F(c e) over e is (1/c) times the law's energy at c e.
    const double scale = strain < 0 ? 1.0 / m.compression_stiffness_fraction : 1.0;
    en.tension_J += scale * m.rest_length_m(e) *
                    m.tension_law->storedEnergy(m.lawStrain(strain), zs ? &s.tension_internal[e * zs] : nullptr);
  }
  if (m.mesentery_stiffening_per_m2 > 0) {
    for (int j = 0; j + 1 < m.n; ++j)
      for (int g = 0; g < Gauss4::kCount; ++g) {
        const Blend b = blend(m.n, j, Gauss4::node[g], 0);
        const Vec3 u = apply(b, s.q) - apply(b, m.q_rest);
        en.mesentery_J += Gauss4::weight[g] * m.segment_length_m(j) *
                          lifterStiffeningEnergyDensity(u, m.segment_k_N_per_m2(j), m.mesentery_stiffening_per_m2);
      }
  }
  if (m.mesentery_axial_ratio < 1) {
    for (int j = 0; j + 1 < m.n; ++j)
      for (int g = 0; g < Gauss4::kCount; ++g) {
        const Blend b = blend(m.n, j, Gauss4::node[g], 0);
        const Vec3 u = apply(b, s.q) - apply(b, m.q_rest);
        Vec3 t = apply(blend(m.n, j, Gauss4::node[g], 1), m.q_rest);
        if (t.norm() > 0) t.normalize();
        const double ut = u.dot(t);
        en.mesentery_J -= 0.5 * (1.0 - m.mesentery_axial_ratio) * m.segment_k_N_per_m2(j) * Gauss4::weight[g] *
                          m.segment_length_m(j) * ut * ut;
      }
  }
  if (m.bending_EI_Nm2 > 0) {
    for (int i = 1; i + 1 < m.n; ++i)
      en.bending_J += bendingAtPoint(s.q.col(i - 1), s.q.col(i), s.q.col(i + 1), m.bend_rest_angle_rad(i),
                                     m.bending_EI_Nm2, m.bend_length_m(i)).energy_J;
  }
  for (int i = 0; i < m.n; ++i) en.gravity_J -= m.mass_rowsum_kg(i) * m.gravity_m_per_s2.dot(s.q.col(i));
  return en;
}

}  // namespace colosim
