// What the colosim command simulates and how it draws frames: one place to plug in the
// real colon + scope simulation and the renderer (linked at compile time).
#pragma once

#include <functional>
#include <string>

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
class WorldSimulation;
}  // namespace colosim

namespace colosim::app {
/// Draws `view` ("onboard", "global" or "both" side by side, each width x height pixels)
/// of a world simulation into the current GL context.
void drawViews(Renderer& renderer, const WorldSimulation& sim, const std::string& view, int width_px,
               int height_px, const OrbitCamera& global_camera);

}  // namespace colosim::app
