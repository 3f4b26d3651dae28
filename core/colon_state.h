// Everything that changes while the colon moves, plus the step's scratch space.
#pragma once

#include <cstdint>
#include <vector>

#include "core/banded.h"
#include "core/spline.h"

namespace colosim {

struct ColonModel;

/// An external load applied at a point of the spline (a contact, a grasp): the force is
/// distributed to the control points by the blending functions b_i(p), and its
/// stiffness and damping (derivatives of the force with respect to the displacement
/// and velocity of that spline point, negated) enter the implicit solve.
struct SplineLoad {
  int segment = 0;
  double p = 0.0;
  Vec3 force_N = Vec3::Zero();
  Mat3 stiffness_N_per_m = Mat3::Zero();  ///< -dF/dx, symmetric positive semi-definite
  Mat3 damping_Ns_per_m = Mat3::Zero();   ///< -dF/dv, symmetric positive semi-definite
};

struct ColonState {
  Points q;                 ///< control points (3 x n) [m]
  Points v;                 ///< control point velocities (3 x n) [m/s]
  double time_s = 0.0;      ///< simulated time [s]
  std::vector<double> tension_internal;  ///< law internal variables ((n-1) x internalSize)
  std::vector<SplineLoad> loads;         ///< external loads for the next step (cleared by the caller)

  // Outputs of the last step.
  Eigen::VectorXd tension_force_N;  ///< axial force of each element (n-1) [N]
  bool solver_ok = true;            ///< false when the last implicit solve failed (or gave non-finite values)
  int limited_points = 0;           ///< control points slowed to ColonModel::max_speed_m_per_s in the last step
  double asked_speed_m_per_s = 0;   ///< the largest speed the last solve asked for, before limiting [m/s]

  // Scratch, sized by makeColonState() so that the step allocates nothing.
  BandedSpd system;                 ///< M + dt C + dt^2 K (3n, half-bandwidth 11)
  BandedSpd constant_system;        ///< the constant part M + dt C_mes + dt^2 K_mes
  double constant_system_dt_s = -1; ///< the dt that constant_system was built for
  Eigen::VectorXd rhs;              ///< right-hand side, then dv (3n)
  Eigen::VectorXd force;            ///< total force f (3n) [N]
  Eigen::VectorXd scratch;          ///< (3n)
  /// The stiffening lifters' quadrature nodes (Gauss4 per segment, segment-major): their
  /// blends and rest points [m], constant for a model; filled with constant_system.
  std::vector<Blend> gauss_blend;
  std::vector<Vec3> gauss_rest_m;
  std::vector<Vec3> gauss_rest_tangent;  ///< unit rest tangent at each node (lifters along the colon)
};

/// A state at rest in the model's rest configuration, with scratch sized for the model
/// and room for `load_capacity` loads.
ColonState makeColonState(const ColonModel& model, int load_capacity = 1024);

/// Flat snapshot of the physical state (q, v, time, internal variables), for replay.
std::vector<double> getColonState(const ColonState& state);
/// Restores a snapshot made by getColonState for the same model; throws
/// std::invalid_argument when the size does not match.
void setColonState(const std::vector<double>& snapshot, ColonState& state);

/// 64-bit FNV-1a hash of the physical state's bytes: equal hashes mean bit-identical states.
uint64_t hashColonState(const ColonState& state);

}  // namespace colosim
