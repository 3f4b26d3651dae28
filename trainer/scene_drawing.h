// Drawing a simulation's scene (Simulation::scene) with the renderer: the onboard and
// global views side by side, and PNG frames of a run or replay (render/, OSMesa).
#pragma once

#include <functional>
#include <string>

#include "core/spline.h"
#include "trainer/simulation.h"

namespace colosim {

class Renderer;
struct OrbitCamera;
struct CameraPose;

/// Draws `view` ("onboard", "global" or "both" side by side, each width x height pixels)
/// of a scene into the current GL context; the onboard view at onboard_scale
/// (OnboardOptics::render_scale).
void drawViews(Renderer& renderer, const SceneView& scene, const std::string& view, int width_px, int height_px,
               const OrbitCamera& global_camera, double onboard_scale = 1.0);
/// The onboard camera at the scope tip: at p_WTip_m, forward along the tip segment's axis
/// (R_WTip's d3), the image's right -d1 and its down -d2 (core/scope_model.h).
CameraPose tipCameraPose(const Vec3& p_WTip_m, const Mat3& R_WTip);
/// The global camera framing the colon's rest shape at this aspect ratio (width / height).
OrbitCamera globalCameraFor(const SceneView& scene, double aspect);

/// Writes frames of a simulation into a folder during a run or replay (RunHooks::on_frame).
using FrameWriter = std::function<void(const Simulation&, long steps_done)>;
/// A frame writer for `dir` with view "onboard", "global" or "both" at width x height
/// pixels (each view): frame_NNNNNN.png, NNNNNN the steps done. A simulation with no
/// scene writes no frames.
FrameWriter makeFrameWriter(const std::string& dir, const std::string& view, int width_px, int height_px);

}  // namespace colosim
