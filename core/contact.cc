#include "core/contact.h"

#include <algorithm>
#include <cmath>

namespace colosim {

namespace {
// The smallest eigenvalue of a uniform Catmull-Rom mass matrix (eq. 3) over its row sum: the
// alternating mode, which contacts along a colon gathered onto the scope can excite (inverse
// power iteration on 40 interior points; the mass at a control point itself, 1 / (M^-1)_ii,
// is 0.76 of the row sum).
constexpr double kCatmullRomLightestMassFraction = 0.30;
}  // namespace

bool selfNeighbours(const ContactParams& params, const ColonModel& colon, int a, int b) {
  const double ds = std::abs(colon.s_rest_m(b) - colon.s_rest_m(a));
  return ds < params.self_neighbour_radii * std::max(colon.radius_m(a), colon.radius_m(b));
}

double applyWallContacts(const ContactParams& P, const ColonModel& colon, const ColonState& cs,
                         const ScopeModel& scope, const ScopeState& ss, std::vector<WallContact>& contacts,
                         std::vector<SplineLoad>& colon_loads, std::vector<ScopeLoad>& scope_loads,
                         ContactLimitReport* report, double step_s, const CouplingSweep* previous,
                         CouplingStiffness* limit) {
  ContactLimitReport local;
  ContactLimitReport& rep = report ? *report : local;
  rep = ContactLimitReport();
  double max_force = 0;
  const Mat3 I3 = Mat3::Identity();
  // The per-point values are given for a slice of wall_reference_slice_m; this scope's
  // slices carry them in proportion to their length (ContactParams).
  const double length_scale = P.wall_reference_slice_m > 0 ? scope.params.segment_length_m /
                                                                  scope.params.slices_per_segment / P.wall_reference_slice_m
                                                            : 1.0;
  // ... and for wall_reference_points_per_slice points round it (1 exactly at that count).
  const double points_scale = P.wall_reference_points_per_slice > 0 && scope.params.points_per_slice > 0
                                  ? static_cast<double>(P.wall_reference_points_per_slice) / scope.params.points_per_slice
                                  : 1.0;
  const double slice_scale = length_scale * points_scale;
  const size_t slice_points = scope.interaction_points_S.size();
  // A contact's scale of the per-point values: its slice's (the tip face's points: 1).
  auto sliceScale = [&](const WallContact& c) {
    return static_cast<size_t>(c.point) < slice_points ? slice_scale : 1.0;
  };
  // The backing's stiffness of a contact of weight w, where the point is pressed through the
  // wall's thickness (eq. 7 gives the wall's own, w k_wall, at any depth) [N/m].
  auto backingStiffness = [&](const WallContact& c, double w) {
    return c.depth_m - P.wall_thickness_m > 0 ? w * P.wall_backing_stiffness_N_per_m : 0.0;
  };
  const bool limit_prediction = limit && !previous && step_s > 0;
  if (limit_prediction) {  // each contact's stiffness, summed per body
    limit->scope_segment_N_per_m.setZero(scope.segment_count);  // no allocation at the right size
    limit->colon_point_N_per_m.setZero(colon.n);
    for (const WallContact& c : contacts) {
      const double w = sliceScale(c) * c.weight;
      const double k_n = w * P.wall_stiffness_N_per_m + backingStiffness(c, w);  // before the force limit
      limit->scope_segment_N_per_m(c.scope_segment) += k_n;
      const Blend b = blend(colon.n, c.colon_segment, c.p, 0);
      for (int i = 0; i < 4; ++i) limit->colon_point_N_per_m(b.index[i]) += std::abs(b.w[i]) * k_n;
    }
  }
  for (WallContact& c : contacts) {
    const double w_slice = sliceScale(c);
    const double w = w_slice * c.weight;
    const double k_wall = w * P.wall_stiffness_N_per_m, c_wall = w * P.wall_damping_Ns_per_m;
    const double backed_m = c.depth_m - P.wall_thickness_m;  // > 0: pressed through the wall's thickness
    const double k_back = backingStiffness(c, w);
    const double max_force_N = w_slice * P.max_point_force_N;
    const int k = c.scope_segment;
    const Vec3 r = c.p_W_point - ss.p_W[k];
    const Vec3 v_point = ss.v_W[k] + ss.w_W[k].cross(r);
    const Blend b_wall = blend(colon.n, c.colon_segment, c.p, 0);  // the wall point M_j(p)
    const Vec3 v_wall = apply(b_wall, cs.v);
    const Vec3 v_rel = v_point - v_wall;
    const Vec3& n = c.normal_W;
    const double v_n = v_rel.dot(n);  // > 0: moving deeper into the wall
    // Eq. 7: F = k_wall depth + f_wall (v . n), pushing the point back into the lumen, and
    // the backing beyond the wall's thickness.
    const double f_n = k_wall * c.depth_m + k_back * backed_m + c_wall * v_n;
    if (!std::isfinite(f_n)) {  // limit: non-finite geometry or velocity: the contact is dropped
      c.force_N = c.normal_force_N = 0;
      ++rep.non_finite;
      continue;
    }
    if (!(f_n > 0)) {  // separating faster than the spring pushes: no adhesion
      c.force_N = c.normal_force_N = 0;
      continue;
    }
    c.normal_force_N = f_n;
    // Regularised Coulomb friction against the sliding velocity.
    const Vec3 v_t = v_rel - v_n * n;
    const double slip = std::sqrt(v_t.squaredNorm() + P.friction_velocity_m_per_s * P.friction_velocity_m_per_s);
    const double mu_over_slip = P.friction_coefficient * f_n / slip;
    Vec3 f_scope = -f_n * n - mu_over_slip * v_t;
    const double asked = f_scope.norm();
    if (!std::isfinite(asked) || !n.allFinite()) {  // limit: a non-finite force is dropped
      c.force_N = c.normal_force_N = 0;
      ++rep.non_finite;
      continue;
    }
    rep.asked_N = std::max(rep.asked_N, asked);
    const Mat3 nn = n * n.transpose();
    Mat3 K = (k_wall + k_back) * nn;
    Mat3 C = c_wall * nn + mu_over_slip * (I3 - nn);
    if (asked > max_force_N) {  // limit: scaled down to the largest trusted force
      const double scale = max_force_N / asked;
      f_scope *= scale;
      K *= scale;
      C *= scale;
      c.normal_force_N *= scale;
      ++rep.limited;
      if (asked > rep.worst.asked_N) {
        using Kind = ContactLimitReport::Worst::Kind;
        rep.worst = {static_cast<size_t>(c.point) < slice_points ? Kind::kSlicePoint : Kind::kTipFace, asked,
                     c.colon_segment, c.p, c.depth_m, v_n};
      }
    }
    c.force_N = f_scope.norm();
    max_force = std::max(max_force, c.force_N);

    ScopeLoad sl;
    sl.segment = k;
    sl.r_W = r;
    sl.force_N = f_scope;
    // The other body's part of the normal force (ContactParams::coupling_predictor,
    // coupling_sweeps): the wall's move lowers the scope's, the point's raises the colon's.
    double scope_extra_N = 0, colon_extra_N = 0;
    if (previous || step_s > 0) {
      double k_n = n.dot(K * n);
      if (limit_prediction) {
        int nearest = b_wall.index[0];  // the control point of the largest weight
        double w_nearest = b_wall.w[0];
        for (int i = 1; i < 4; ++i)
          if (b_wall.w[i] > w_nearest) w_nearest = b_wall.w[i], nearest = b_wall.index[i];
        // The scope: its segment as a free rigid body pushed at the point along n (a ring at a
        // segment's end: a quarter of its mass). The colon: the lightest mode of its mass
        // matrix, kCatmullRomLightestMassFraction of a control point's row sum.
        const Vec3 rn = ss.R_WS[k].transpose() * r.cross(n);
        const double inverse_mass_scope =
            1.0 / scope.segment_mass_kg + rn.cwiseAbs2().cwiseQuotient(scope.segment_inertia_kgm2).sum();
        const double a_scope = limit->scope_segment_N_per_m(k) * step_s * step_s * inverse_mass_scope;
        const double a_colon = limit->colon_point_N_per_m(nearest) * step_s * step_s /
                               (kCatmullRomLightestMassFraction * colon.mass_rowsum_kg(nearest));
        if (a_scope * a_colon > 1) k_n /= a_scope * a_colon;
      }
      if (previous) {
        const double c_n = n.dot(C * n);
        const ScopeState& se = *previous->scope;
        const Vec3 r_end = se.R_WS[k] * (ss.R_WS[k].transpose() * r);
        scope_extra_N = -k_n * (apply(b_wall, previous->colon->q) - apply(b_wall, cs.q)).dot(n) -
                        c_n * (apply(b_wall, previous->colon->v) - v_wall).dot(n);
        colon_extra_N = k_n * (se.p_W[k] + r_end - c.p_W_point).dot(n) +
                        c_n * (se.v_W[k] + se.w_W[k].cross(r_end) - v_point).dot(n);
      } else {
        scope_extra_N = -step_s * k_n * v_wall.dot(n);
        colon_extra_N = step_s * k_n * v_point.dot(n);
      }
      scope_extra_N = std::max(scope_extra_N, -c.normal_force_N);
      colon_extra_N = std::max(colon_extra_N, -c.normal_force_N);
      sl.force_N -= scope_extra_N * n;
    }
    sl.stiffness_N_per_m = K;
    sl.damping_Ns_per_m = C;
    scope_loads.push_back(sl);

    SplineLoad cl;
    cl.segment = c.colon_segment;
    cl.p = c.p;
    cl.force_N = -f_scope + colon_extra_N * n;
    cl.stiffness_N_per_m = K;
    cl.damping_Ns_per_m = C;
    colon_loads.push_back(cl);
  }
  return max_force;
}

void applySelfContacts(const ContactParams& P, const ColonModel& colon, const ColonState& cs,
                       const std::vector<SelfContact>& contacts, std::vector<SplineLoad>& colon_loads) {
  for (const SelfContact& c : contacts) {
    const Vec3& n = c.normal_W;
    const double v_n = (cs.v.col(c.b) - cs.v.col(c.a)).dot(n);  // < 0: approaching
    const double f = P.self_stiffness_N_per_m * c.depth_m - P.self_damping_Ns_per_m * v_n;
    if (!(f > 0)) continue;
    const Mat3 nn = n * n.transpose();
    for (int side = 0; side < 2; ++side) {
      const int i = side == 0 ? c.a : c.b;
      SplineLoad l;
      controlPointLocation(colon, i, &l.segment, &l.p);
      l.force_N = (side == 0 ? -f : f) * n;
      l.stiffness_N_per_m = P.self_stiffness_N_per_m * nn;
      l.damping_Ns_per_m = P.self_damping_Ns_per_m * nn;
      colon_loads.push_back(l);
    }
  }
}

}  // namespace colosim
