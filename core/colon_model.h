// The colon model (paper sections 2.1-2.4): built once from an anatomy and parameters,
// never changed during a run. What changes lives in ColonState (colon_state.h); the
// step (colon_step.h) takes both.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/banded.h"
#include "core/spline.h"
#include "core/tension_law.h"

namespace colosim {

/// One anatomical region of a centreline, as read from an anatomy file.
struct AnatomyRegion {
  std::string name;            ///< e.g. "sigmoid"
  std::string mesentery;       ///< mesentery class name, a key of ColonParams::mesentery
  double radius_start_m = 0;   ///< lumen radius where the region starts [m]
  double radius_end_m = 0;     ///< lumen radius where it ends [m]
  std::vector<Vec3> points_m;  ///< centreline waypoints [m], continuing the previous region
};

/// A colon centreline from the anus to the caecal pole, in the patient frame:
/// x towards the patient's left, y posterior, z cranial (DICOM's LPS, right-handed);
/// origin at the anus [m].
struct Anatomy {
  std::string name;
  std::vector<AnatomyRegion> regions;
};

/// Mesentery lifter densities of one class (paper eqs. 4-5).
struct MesenteryClass {
  double stiffness_N_per_m2 = 0;  ///< k: stiffness per unit length [N/m per m]
  double damping_Ns_per_m2 = 0;   ///< c: viscosity per unit length [N s/m per m]
};

/// Physical parameters of the colon.
struct ColonParams {
  double mass_per_length_kg_per_m = 0.4;  ///< rho (paper eq. 8) [kg/m]
  double tension_EA_N = 28.9;             ///< axial rigidity of the Voigt law [N]
  double tension_EC_Ns = 0.05;            ///< axial viscosity of the Voigt law [N s]
  std::map<std::string, MesenteryClass> mesentery;  ///< by class name
  double gravity_m_per_s2 = 9.81;         ///< magnitude of g [m/s^2]
  std::string patient_position = "left_lateral";  ///< left_lateral | supine | prone | right_lateral
  double control_point_spacing_m = 0.015; ///< target spacing of the resampled spline [m]
  int control_point_count = 0;            ///< when > 0, overrides the spacing: exactly this many points
  /// Extensions the paper leaves out (issue 7); 0 switches each off (the paper's model).
  double bending_EI_Nm2 = 0;              ///< bending rigidity EI of the colon wall [N m^2]
  double mesentery_stiffening_per_m2 = 0; ///< beta of the stiffening lifters k(d) = k0 (1 + beta d^2) [1/m^2]
  /// Colon compression (not in the paper): the fraction of the tension law's stiffness a
  /// tension element keeps when shortened (a thin-walled tube pleats under axial
  /// compression); 1 is the paper's Voigt element, as stiff shortened as stretched [-].
  double compression_stiffness_fraction = 1.0;
  /// Lifters along the colon (not in the paper): the lifters' stiffness along the colon's
  /// rest tangent as a fraction of their stiffness across it. A mesentery is a sheet along
  /// the colon: it holds the colon from moving away from its root far harder than from
  /// sliding along its own length. 1 is the paper's isotropic lifter (eq. 4) [-], in [0, 1].
  double mesentery_axial_ratio = 1.0;
  /// Haustral folds in the contact wall (not in the paper): the lumen's radius at the
  /// control point nearest each fold (every haustral_fold_period_m of rest arclength from
  /// the anus, outside the rectum) is narrowed by this fraction, so that the wall the scope
  /// and the colon touch has the ridges the renderer draws. 0 is the paper's smooth tube [-].
  double haustral_fold_depth = 0.0;
  double haustral_fold_period_m = 0.03;  ///< rest arclength between two folds [m]
};

/// Gravity vector in the patient frame for a named position [m/s^2]; throws
/// std::invalid_argument for an unknown name.
Vec3 gravityForPosition(const std::string& patient_position, double g_m_per_s2);

/// A scalar symmetric band matrix over control points (half-bandwidth 3), such as the
/// mass matrix M_il of eq. 3; the 3-D matrix is this one times the 3 x 3 identity.
using ScalarBand = BandedSpd;

struct ColonModel {
  int n = 0;                        ///< number of control points
  Points q_rest;                    ///< rest positions q0 (3 x n) [m]
  Eigen::VectorXd s_rest_m;         ///< rest arclength at each control point (n) [m]
  Eigen::VectorXd radius_m;         ///< lumen radius at each control point (n), at the wall the contacts see: narrowed at haustral folds [m]
  Eigen::VectorXd smooth_radius_m;  ///< the anatomy's lumen radius at each control point (n), without the folds (the renderer draws its own) [m]
  Eigen::VectorXd segment_length_m; ///< rest arclength of each spline segment (n-1) [m]
  Eigen::VectorXd rest_length_m;    ///< rest chord length of each tension element (n-1) [m]
  std::vector<int> segment_region;  ///< region index of each spline segment (n-1)
  std::vector<std::string> region_names;     ///< by region index
  std::vector<std::string> region_mesentery; ///< mesentery class by region index
  Eigen::VectorXd segment_k_N_per_m2; ///< mesentery stiffness density per segment (n-1)
  Eigen::VectorXd segment_c_Ns_per_m2;///< mesentery viscosity density per segment (n-1)

  // Colon bending (colon_bending, not in the paper; docs/organ-identification.md): at each
  // interior control point i a discrete bending energy EI / (2 L_i) (theta_i - theta0_i)^2
  // on the turning angle theta_i between elements i-1 and i; off when EI = 0.
  double bending_EI_Nm2 = 0;             ///< bending rigidity EI [N m^2]
  Eigen::VectorXd bend_rest_angle_rad;   ///< theta0_i, rest turning angle at each control point (n; 0 at the ends) [rad]
  Eigen::VectorXd bend_length_m;         ///< L_i = (l0_{i-1} + l0_i) / 2 (n; 0 at the ends) [m]
  // Mesentery stiffening (mesentery_stiffening, not in the paper): the lifter density at a
  // spline point displaced by d = |M(s) - M0(s)| from rest is k(d) = k0 (1 + beta d^2);
  // off (the paper's linear lifters, eqs. 4-5) when beta = 0.
  double mesentery_stiffening_per_m2 = 0; ///< beta [1/m^2]

  // Colon compression (not in the paper): a shortened element (strain e < 0) gives the
  // tension law's force at the strain c e, the rate term unchanged: F = EA c e + EC de/dt
  // for the Voigt law, continuous at e = 0. c = 1 is the paper's element.
  double compression_stiffness_fraction = 1.0;  ///< c [-], in (0, 1]

  // Lifters along the colon (not in the paper): at a spline point with rest tangent t, the
  // lifter force density is -k0 (u - (1 - a) (u . t) t) for the displacement u from rest,
  // a the ratio below: k0 across the colon, a k0 along it. 1: the paper's lifters.
  double mesentery_axial_ratio = 1.0;  ///< a [-], in [0, 1]
  /// The strain the tension law is evaluated at: e in tension, c e shortened.
  double lawStrain(double strain) const { return strain < 0 ? compression_stiffness_fraction * strain : strain; }

  ScalarBand mass;            ///< M (eq. 3), n x n [kg]
  ScalarBand mesentery_K;     ///< K (eq. 4), n x n [N/m]
  ScalarBand mesentery_C;     ///< C (eq. 5), n x n [N s/m]
  Eigen::VectorXd mass_rowsum_kg; ///< M 1 (n): the gravity load is this times g [kg]
  Vec3 gravity_m_per_s2 = Vec3::Zero();
  double mass_per_length_kg_per_m = 0;
  std::shared_ptr<const TensionLaw> tension_law;

  /// Solver limit (docs/hardening.md): the largest speed of a control point the one-step
  /// implicit solve is trusted with [m/s]. 5 m/s is 5 mm per 1 ms step, a third of the
  /// 1.5 cm control-point spacing: beyond it the step's linearisation of the tension
  /// elements and contacts no longer holds. Faster points are slowed to it and counted
  /// (ColonState::limited_points). Not a tissue property: no parameter file sets it.
  double max_speed_m_per_s = 5.0;

  double length_m() const { return s_rest_m(n - 1); }
  /// Lumen radius at (segment, p), linear between control points [m].
  double radiusAt(int segment, double p) const {
    return (1 - p) * radius_m(segment) + p * radius_m(segment + 1);
  }
  /// The anatomy's lumen radius at (segment, p) without the haustral folds, linear [m].
  double smoothRadiusAt(int segment, double p) const {
    return (1 - p) * smooth_radius_m(segment) + p * smooth_radius_m(segment + 1);
  }
  /// Rest arclength at (segment, p), linear in p within the segment [m].
  double arclengthAt(int segment, double p) const {
    return s_rest_m(segment) + p * segment_length_m(segment);
  }
};

/// Turning angle between consecutive element vectors a and b [rad] in [0, pi]:
/// atan2(|a x b|, a . b), accurate near 0 and pi.
inline double turningAngle(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Builds a model: resamples the anatomy centreline to control points at the spacing
/// of the parameters (uniform in arclength), integrates M, K, C by Gauss quadrature.
/// Throws std::invalid_argument naming the problem when the inputs are inconsistent
/// (unknown mesentery class, fewer than two waypoints, non-positive radius, ...).
ColonModel buildColonModel(const Anatomy& anatomy, const ColonParams& params,
                           std::shared_ptr<const TensionLaw> law = nullptr);

/// Builds a model directly from control points (no resampling): used by tests and by
/// tools that make small colons inline. k and c are uniform densities.
ColonModel buildColonModelFromPoints(const Points& q_rest, const Eigen::VectorXd& radius_m,
                                     double mass_per_length_kg_per_m, double k_N_per_m2,
                                     double c_N_s_per_m2, const Vec3& gravity_m_per_s2,
                                     std::shared_ptr<const TensionLaw> law);

}  // namespace colosim
