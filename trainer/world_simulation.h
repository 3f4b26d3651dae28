// The simulation colosim runs: colon, colonoscope and their contacts (core/world.h) with
// FCL queries (collision/), behind the trainer's Simulation interface, plus the
// measurements scoring needs (telemetry).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "collision/contact_query.h"
#include "core/step_lanes.h"
#include "core/world.h"
#include "trainer/simulation.h"
#include "trainer/start_state.h"

namespace colosim {

struct Scenario;
struct Parameters;

class WorldSimulation : public Simulation {
 public:
  /// Loads the scenario's anatomy and parameters with its overrides, applies its start
  /// state (a first keyframe with the scope already in is threaded along the colon), and
  /// queries contacts in `query_mode` ("fcl" or "scan"). InputError for unusable files.
  /// `law` replaces the parameters' Voigt tension law when given (colosim identify --law-out).
  explicit WorldSimulation(const Scenario& scenario, std::shared_ptr<const TensionLaw> law = nullptr,
                           const std::string& query_mode = "fcl");
  /// The same with the parameters given instead of scenarioParameters(scenario) (e.g. the
  /// model an identification fitted, identify/insertion/replay.h organParameters).
  WorldSimulation(const Scenario& scenario, const Parameters& params, std::shared_ptr<const TensionLaw> law = nullptr,
                  const std::string& query_mode = "fcl");
  /// The same from a world model built elsewhere (identification) and a start
  /// specification (trainer/start_state.h).
  WorldSimulation(WorldModel model, const StartSpec& start, const std::string& query_mode = "fcl");
  /// Back to a start state: the state, time step and pressures `start` gives (the model,
  /// the contact query and the solver-limit events carry on).
  void restart(const StartSpec& start);

  void step(const HandleInput& in) override;
  double dt_s() const override { return dt_s_; }
  double time_s() const override { return state_.colon.time_s; }
  uint64_t stateHash() const override { return hashWorldState(state_); }
  Telemetry telemetry() const override { return telemetry_; }
  /// "solver_limited" at the first step of a run of steps in which a solver limit engaged
  /// (detail: what was limited, asked against the limit), "solver_limited_end" after the
  /// run's last step (detail: its length and the largest values asked); the old
  /// "solver_failed_colon"/"solver_failed_scope" at every failed solve. docs/hardening.md.
  std::vector<SimulationEvent> events() const override { return events_; }
  /// The colon's control points, the scope's centreline, radius and tip frame.
  bool scene(SceneView& out) const override;
  /// Abdominal pressure: the assistant's hand presses the regions the scenario's
  /// abdominal_pressure names (with its densities), or without one the sigmoid and the
  /// transverse colon (kAssistPressure_N_per_m2), anchored where they lie when the pressing
  /// begins, ramped in and out over 1 s. Patient position: gravity turns about the body's
  /// long axis to the new position over kTurnDuration_s (a lateral-to-lateral turn rolls
  /// the patient over the back).
  void assist(const AssistInput& a) override;

  static constexpr double kTurnDuration_s = 3.0;       ///< [s] (tuning: a patient turned with help)
  static constexpr double kAssistPressure_N_per_m2 = 5000.0;  ///< [N/m per m], free_insertion's hand (docs/parameters.md)
  static constexpr double kAssistDamping_Ns_per_m2 = 50.0;    ///< [N s/m per m]

  const WorldModel& model() const { return model_; }
  const WorldState& state() const { return state_; }
  WorldState& mutableState() { return state_; }

  /// The scope's centreline from just outside the anus to the tip [m] (for drawing).
  std::vector<Vec3> scopeCentreline() const;

  /// Wall patches used for "% mucosa visualised": kPatchSectors around each colon segment.
  static constexpr int kPatchSectors = 8;

  /// With `on`, the telemetry after each step keeps only what a replay of a recording
  /// compares: time, input, handle force and torque, tip position and the coronal loop
  /// (loop_turns). The scores' measures (lumen check, wall force, stretch, region lengths,
  /// writhe, the view) keep their defaults and cost nothing. The state is the same bit for
  /// bit either way. Off by default.
  void measureHandleAndLoopOnly(bool on) { handle_and_loop_only_ = on; }

  /// With `on`, each step runs its independent halves on two lanes (core/step_lanes.h: a
  /// worker thread beside the caller's), for a run that has a second core to itself. The
  /// states are the same bit for bit either way. Off by default.
  void useTwoLanes(bool on);

 private:
  void measure();
  // The coronal loop's turning number (crossingLoopTurns) of the scope from the anus to the
  // end of the descending colon; leaves that line in loop_line_.
  double coronalLoopTurns(const Vec3& tip);

  WorldModel model_;
  WorldState state_;
  std::unique_ptr<ContactQuery> query_;
  std::unique_ptr<StepLanes> lanes_;  // null: one lane
  double dt_s_ = 1e-3;
  Telemetry telemetry_;
  bool handle_and_loop_only_ = false;
  int sigmoid_first_ = -1, sigmoid_last_ = -1;  ///< control points of the sigmoid (rest arclength order)
  void updateLimitEvents();
  std::vector<SimulationEvent> events_;  ///< events of the last step
  // The current run of limited steps: its length and the largest values asked in it.
  long limited_run_steps_ = 0;
  double run_force_N_ = 0, run_scope_speed_ = 0, run_scope_spin_ = 0, run_colon_speed_ = 0;
  double run_handle_force_N_ = 0, run_handle_torque_Nm_ = 0;  // largest |handle force, torque| asked in the run
  /// The scenario's abdominal pressure, resolved to spline segments (core/abdominal_pressure.h).
  std::vector<PressureSchedule> pressure_;
  void setSupport(double t_s);
  // Assistance (assist()): the assistant's pressure schedules (indices into pressure_ and
  // state_.support, made at the first pressing), its regions and densities, the patient's
  // position and the gravity turn in progress.
  std::vector<PressureSchedule> assist_regions_;
  std::vector<size_t> assist_pressure_;
  AssistInput assist_;
  std::string position_;            ///< the patient's position (the target during a turn)
  std::string start_position_;      ///< the position the run started in
  Vec3 start_gravity_ = Vec3::Zero();  ///< its gravity [m/s^2]
  double turn_from_rad_ = 0, turn_by_rad_ = 0, turn_start_s_ = -1;  ///< gravity's angle about +z
  double gravity_norm_ = 0;         ///< |g| [m/s^2]
  void turnGravity(double t_s);
  /// Starts turning the patient to `target` (a patientPositions() name) now.
  void startTurn(const std::string& target);
  std::vector<PatientTurn> turns_;  ///< the scenario's patient_turns
  size_t next_turn_ = 0;            ///< the first of turns_ not yet begun
  int loop_last_ = -1;  ///< the loop measure follows the scope up to this control point (end of the descending colon)
  std::vector<Vec3> loop_line_;  ///< scratch: the scope polyline of the loop measure [m]
  /// The loop's writhe is measured every kWritheEverySteps steps (10 ms at 1 ms: loops form
  /// and go over seconds) and held in between; it took 15 % of a run at every step.
  static constexpr long kWritheEverySteps = 10;
  long writhe_step_ = -1;     ///< step (time / dt) at which loop_writhe_ was measured, -1: none
  double loop_writhe_ = 0.0;  ///< the last measured writhe [turns]
  std::vector<double> region_ratio_;  ///< scratch: storage of Telemetry::region_length_ratio [-]
  /// The resting colon (restingColon) under resting_gravity_, against which the mesentery's
  /// stretch is measured: made at the first measure and again once a turn of the patient
  /// has ended (during a turn the one before it stays) [m].
  Eigen::Matrix3Xd resting_q_;
  Vec3 resting_gravity_ = Vec3::Zero();  ///< [m/s^2]
  std::vector<double> lumen_arc_;  ///< scratch of checkLumen: present arclength at each control point [m]
};

/// A SimulationFactory building WorldSimulation (FCL queries).
std::unique_ptr<Simulation> makeWorldSimulation(const Scenario& scenario);

/// Red-out (Telemetry::tip_against_wall): the point 4 mm ahead of the lens at `tip_W` [m],
/// looking along `forward_W` (unit), lies beyond the wall the camera sees, the anatomy's
/// radius (ColonModel::smooth_radius_m; the renderer draws thin folds of its own), at its
/// nearest colon location within 3 segments of `tracked` (every segment when negative).
bool lensAgainstWall(const ColonModel& colon, const Points& q, int tracked, const Vec3& tip_W, const Vec3& forward_W);

}  // namespace colosim
