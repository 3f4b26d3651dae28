#include "core/colon_model.h"

#include <cmath>
#include <stdexcept>

namespace colosim {

Vec3 gravityForPosition(const std::string& position, double g) {
  // Patient frame (LPS): x towards the patient's left, y posterior, z cranial.
  if (position == "left_lateral") return Vec3(g, 0, 0);    // lying on the left side
  if (position == "right_lateral") return Vec3(-g, 0, 0);
  if (position == "supine") return Vec3(0, g, 0);          // on the back: towards posterior
  if (position == "prone") return Vec3(0, -g, 0);
  throw std::invalid_argument("unknown patient_position '" + position +
                              "' (expected left_lateral, right_lateral, supine or prone)");
}

namespace {

// Integrates the three constant band matrices of eqs. 3-5 with 4-point Gauss quadrature
// (exact: the integrands b_l b_i are degree-6 polynomials in p), scaling the parameter
// integral by each segment's rest arclength so that densities are per metre.
void integrateMatrices(ColonModel& m) {
  const int n = m.n;
  m.mass.resize(n, 3);
  m.mesentery_K.resize(n, 3);
  m.mesentery_C.resize(n, 3);
  for (int j = 0; j + 1 < n; ++j) {
    const double len = m.segment_length_m(j);
    for (int g = 0; g < Gauss4::kCount; ++g) {
      const Blend b = blend(n, j, Gauss4::node[g], 0);
      const double w = Gauss4::weight[g] * len;
      for (int a = 0; a < 4; ++a) {
        for (int c = 0; c < 4; ++c) {
          const int i = b.index[a], l = b.index[c];
          if (i < l) continue;  // lower triangle only; (i, l) and (l, i) both visited
          const double bb = b.w[a] * b.w[c] * w;
          m.mass.lower(i, l) += m.mass_per_length_kg_per_m * bb;
          m.mesentery_K.lower(i, l) += m.segment_k_N_per_m2(j) * bb;
          m.mesentery_C.lower(i, l) += m.segment_c_Ns_per_m2(j) * bb;
        }
      }
    }
  }
  m.mass_rowsum_kg = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  m.mass.multiply(ones.data(), m.mass_rowsum_kg.data());
}

// Fills the geometric fields that follow from q_rest: arclengths and rest lengths.
void fillGeometry(ColonModel& m) {
  const int n = m.n;
  m.segment_length_m.resize(n - 1);
  m.rest_length_m.resize(n - 1);
  m.s_rest_m.resize(n);
  m.s_rest_m(0) = 0.0;
  for (int j = 0; j + 1 < n; ++j) {
    m.segment_length_m(j) = segmentArclength(m.q_rest, j);
    m.rest_length_m(j) = (m.q_rest.col(j + 1) - m.q_rest.col(j)).norm();
    if (!(m.rest_length_m(j) > 0)) {
      throw std::invalid_argument("control points " + std::to_string(j) + " and " +
                                  std::to_string(j + 1) + " coincide");
    }
    m.s_rest_m(j + 1) = m.s_rest_m(j) + m.segment_length_m(j);
  }
  // Rest turning angles and Voronoi lengths of the bending energy (used only when EI > 0).
  m.bend_rest_angle_rad = Eigen::VectorXd::Zero(n);
  m.bend_length_m = Eigen::VectorXd::Zero(n);
  for (int i = 1; i + 1 < n; ++i) {
    m.bend_rest_angle_rad(i) = turningAngle(m.q_rest.col(i) - m.q_rest.col(i - 1),
                                            m.q_rest.col(i + 1) - m.q_rest.col(i));
    m.bend_length_m(i) = 0.5 * (m.rest_length_m(i - 1) + m.rest_length_m(i));
  }
}

}  // namespace

ColonModel buildColonModel(const Anatomy& anatomy, const ColonParams& params,
                           std::shared_ptr<const TensionLaw> law) {
  if (anatomy.regions.empty()) throw std::invalid_argument("anatomy has no regions");
  if (!(params.control_point_spacing_m > 0))
    throw std::invalid_argument("control_point_spacing_m must be positive");
  if (!(params.mass_per_length_kg_per_m > 0))
    throw std::invalid_argument("mass_per_length_kg_per_m must be positive");

  // Waypoints of the whole centreline and the waypoint index where each region ends.
  std::vector<Vec3> way;
  std::vector<int> region_end;  // index into `way` of each region's last waypoint
  for (const AnatomyRegion& r : anatomy.regions) {
    if (r.points_m.empty()) throw std::invalid_argument("region '" + r.name + "' has no points");
    if (!(r.radius_start_m > 0) || !(r.radius_end_m > 0))
      throw std::invalid_argument("region '" + r.name + "' needs positive radii");
    if (!params.mesentery.count(r.mesentery))
      throw std::invalid_argument("region '" + r.name + "' names unknown mesentery class '" +
                                  r.mesentery + "'");
    for (const Vec3& p : r.points_m) way.push_back(p);
    region_end.push_back(static_cast<int>(way.size()) - 1);
  }
  if (way.size() < 2) throw std::invalid_argument("anatomy needs at least two waypoints");
  Points w(3, static_cast<int>(way.size()));
  for (size_t i = 0; i < way.size(); ++i) w.col(static_cast<int>(i)) = way[i];

  // Arclength along the waypoint spline.
  std::vector<double> s_way(way.size(), 0.0);
  for (size_t i = 0; i + 1 < way.size(); ++i) {
    const double len = segmentArclength(w, static_cast<int>(i));
    if (!(len > 0)) throw std::invalid_argument("anatomy has repeated waypoints");
    s_way[i + 1] = s_way[i] + len;
  }
  const double total = s_way.back();
  std::vector<double> region_s_end, region_s_start;
  for (size_t r = 0; r < anatomy.regions.size(); ++r) {
    region_s_start.push_back(r == 0 ? 0.0 : region_s_end.back());
    region_s_end.push_back(s_way[region_end[r]]);
  }
  auto regionOf = [&](double s) {
    for (size_t r = 0; r < region_s_end.size(); ++r)
      if (s <= region_s_end[r]) return static_cast<int>(r);
    return static_cast<int>(region_s_end.size()) - 1;
  };

  // Resample uniformly in arclength.
  const int intervals = params.control_point_count > 1
                            ? params.control_point_count - 1
                            : std::max(1, static_cast<int>(std::lround(total / params.control_point_spacing_m)));
  ColonModel m;
  m.n = intervals + 1;
  m.q_rest.resize(3, m.n);
  m.radius_m.resize(m.n);
  size_t seg = 0;
  for (int k = 0; k < m.n; ++k) {
    const double s = total * k / intervals;
    while (seg + 2 < way.size() && s > s_way[seg + 1]) ++seg;
    const double p = parameterAtArclength(w, static_cast<int>(seg), s - s_way[seg]);
    m.q_rest.col(k) = splinePoint(w, static_cast<int>(seg), p);
    const int r = regionOf(s);
    const AnatomyRegion& reg = anatomy.regions[r];
    const double span = region_s_end[r] - region_s_start[r];
    const double t = span > 0 ? std::clamp((s - region_s_start[r]) / span, 0.0, 1.0) : 0.0;
    m.radius_m(k) = (1 - t) * reg.radius_start_m + t * reg.radius_end_m;
  }
  fillGeometry(m);

  // Regions and mesentery densities per spline segment, by the segment's midpoint.
  for (const AnatomyRegion& r : anatomy.regions) {
    m.region_names.push_back(r.name);
    m.region_mesentery.push_back(r.mesentery);
  }
  m.segment_region.resize(m.n - 1);
  m.segment_k_N_per_m2.resize(m.n - 1);
  m.segment_c_Ns_per_m2.resize(m.n - 1);
  for (int j = 0; j + 1 < m.n; ++j) {
    const double mid = m.s_rest_m(j) + 0.5 * m.segment_length_m(j);
    // Map the resampled arclength onto the waypoint arclength (they differ by round-off).
    const int r = regionOf(mid * total / m.length_m());
    m.segment_region[j] = r;
    const MesenteryClass& mc = params.mesentery.at(anatomy.regions[r].mesentery);
    m.segment_k_N_per_m2(j) = mc.stiffness_N_per_m2;
    m.segment_c_Ns_per_m2(j) = mc.damping_Ns_per_m2;
  }

  // Haustral folds: the control point nearest each fold, outside the rectum and not next to it.
  m.smooth_radius_m = m.radius_m;
  if (!(params.haustral_fold_depth >= 0) || !(params.haustral_fold_depth < 1) || !(params.haustral_fold_period_m > 0))
    throw std::invalid_argument("haustral_fold_depth must be in [0, 1) and haustral_fold_period_m > 0");
  if (params.haustral_fold_depth > 0) {
    auto in_rectum = [&m](int j) {
      return j >= 0 && j + 1 < m.n && m.region_names[m.segment_region[j]] == "rectum";
    };
    const double spacing = m.length_m() / (m.n - 1);
    for (int f = 1; f * params.haustral_fold_period_m < m.length_m(); ++f) {
      const int k = static_cast<int>(std::lround(f * params.haustral_fold_period_m / spacing));
      if (k <= 0 || k >= m.n - 1 || in_rectum(k - 1) || in_rectum(k)) continue;
      m.radius_m(k) = (1 - params.haustral_fold_depth) * m.smooth_radius_m(k);
    }
  }

  m.mass_per_length_kg_per_m = params.mass_per_length_kg_per_m;
  if (!(params.bending_EI_Nm2 >= 0) || !(params.mesentery_stiffening_per_m2 >= 0))
    throw std::invalid_argument("bending_EI_Nm2 and mesentery_stiffening_per_m2 must be >= 0");
  m.bending_EI_Nm2 = params.bending_EI_Nm2;
  m.mesentery_stiffening_per_m2 = params.mesentery_stiffening_per_m2;
  if (!(params.compression_stiffness_fraction > 0) || !(params.compression_stiffness_fraction <= 1))
    throw std::invalid_argument("compression_stiffness_fraction must be in (0, 1]");
  m.compression_stiffness_fraction = params.compression_stiffness_fraction;
  if (!(params.mesentery_axial_ratio >= 0) || !(params.mesentery_axial_ratio <= 1))
    throw std::invalid_argument("mesentery_axial_ratio must be in [0, 1]");
  m.mesentery_axial_ratio = params.mesentery_axial_ratio;
  m.gravity_m_per_s2 = gravityForPosition(params.patient_position, params.gravity_m_per_s2);
  m.tension_law = law ? law : std::make_shared<VoigtLaw>(params.tension_EA_N, params.tension_EC_Ns);
  integrateMatrices(m);
  return m;
}

ColonModel buildColonModelFromPoints(const Points& q_rest, const Eigen::VectorXd& radius_m,
                                     double mass_per_length, double k, double c,
                                     const Vec3& gravity, std::shared_ptr<const TensionLaw> law) {
  if (q_rest.cols() < 2) throw std::invalid_argument("a colon needs at least two control points");
  if (radius_m.size() != q_rest.cols()) throw std::invalid_argument("one radius per control point");
  if (!law) throw std::invalid_argument("a tension law is required");
  ColonModel m;
  m.n = static_cast<int>(q_rest.cols());
  m.q_rest = q_rest;
  m.radius_m = radius_m;
  m.smooth_radius_m = radius_m;  // no haustral folds
  fillGeometry(m);
  m.region_names = {"colon"};
  m.region_mesentery = {"uniform"};
  m.segment_region.assign(m.n - 1, 0);
  m.segment_k_N_per_m2 = Eigen::VectorXd::Constant(m.n - 1, k);
  m.segment_c_Ns_per_m2 = Eigen::VectorXd::Constant(m.n - 1, c);
  m.mass_per_length_kg_per_m = mass_per_length;
  m.gravity_m_per_s2 = gravity;
  m.tension_law = std::move(law);
  integrateMatrices(m);
  return m;
}

}  // namespace colosim
