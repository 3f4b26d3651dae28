// What the colosim command simulates and how it draws frames: one place to plug in the
// real colon + scope simulation and the renderer (linked at compile time).
#pragma once

#include <functional>
#include <string>

#include "core/spline.h"
#include "trainer/simulation.h"

namespace colosim::app {

/// The simulation behind colosim run/replay/score.
SimulationFactory simulationFactory();

/// Writes frames of a simulation into a folder during a run or replay.
using FrameWriter = std::function<void(const Simulation&, long steps_done)>;
/// A frame writer for `dir` with view "onboard", "global" or "both" at width x height
/// pixels; an empty function when this build has no renderer.
FrameWriter makeFrameWriter(const std::string& dir, const std::string& view, int width_px, int height_px);

}  // namespace colosim::app

namespace colosim {
class Renderer;
struct OrbitCamera;
struct CameraPose;
struct ScopeShape;
struct ColonModel;
class WorldSimulation;
}  // namespace colosim

namespace colosim::app {
/// Draws `view` ("onboard", "global" or "both" side by side, each width x height pixels)
/// of a world simulation into the current GL context; the onboard view at onboard_scale
/// (OnboardOptics::render_scale).
void drawViews(Renderer& renderer, const WorldSimulation& sim, const std::string& view, int width_px,
               int height_px, const OrbitCamera& global_camera, double onboard_scale = 1.0);
/// The same from the parts of a state (a snapshot copied out of colosim train's physics
/// thread): colon control points q (3 x n) [m], the scope, and the onboard camera.
void drawViews(Renderer& renderer, const ColonModel& colon, const Points& q, const ScopeShape& scope,
               const CameraPose& tip_camera, const std::string& view, int width_px, int height_px,
               const OrbitCamera& global_camera, double onboard_scale = 1.0);
/// The onboard camera at the scope tip: at p_WTip_m, forward along the tip segment's axis
/// (R_WTip's d3), the image's right -d1 and its down -d2 (core/scope_model.h).
CameraPose tipCameraPose(const Vec3& p_WTip_m, const Mat3& R_WTip);

}  // namespace colosim::app
