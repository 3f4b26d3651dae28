// What colosim simulates (colon, scope, contacts: trainer/world_simulation.h) and how it
// draws frames (render/, OSMesa).
#include "trainer/app/simulation_factory.h"

#include <cstdio>
#include <memory>

#include "render/offscreen_context.h"
#include "render/renderer.h"
#include "trainer/world_simulation.h"

namespace colosim::app {

SimulationFactory simulationFactory() { return makeWorldSimulation; }

CameraPose tipCameraPose(const Vec3& p_WTip_m, const Mat3& R_WTip) {
  CameraPose pose;
  pose.p_WC_m = p_WTip_m;
  pose.R_WC.col(0) = -R_WTip.col(0);
  pose.R_WC.col(1) = -R_WTip.col(1);
  pose.R_WC.col(2) = R_WTip.col(2);
  return pose;
}

namespace {

// The onboard camera at the scope tip.
CameraPose tipCamera(const WorldSimulation& sim) {
  const ScopeState& s = sim.state().scope;
  return tipCameraPose(tipPosition(sim.model().scope, s), s.R_WS[0]);
}

struct FrameState {
  std::unique_ptr<OffscreenContext> context;
  std::unique_ptr<Renderer> renderer;
  OrbitCamera global_camera;
};

}  // namespace

void drawViews(Renderer& renderer, const WorldSimulation& sim, const std::string& view, int width_px,
               int height_px, const OrbitCamera& global_camera, double onboard_scale) {
  ScopeShape shape;
  shape.centreline_m = sim.scopeCentreline();
  shape.radius_m = sim.model().scope.radius_m;
  drawViews(renderer, sim.model().colon, sim.state().colon.q, shape, tipCamera(sim), view, width_px, height_px,
            global_camera, onboard_scale);
}

void drawViews(Renderer& renderer, const ColonModel& colon, const Points& q, const ScopeShape& shape,
               const CameraPose& tip_camera, const std::string& view, int width_px, int height_px,
               const OrbitCamera& global_camera, double onboard_scale) {
  int x = 0;
  if (view == "onboard" || view == "both") {
    OnboardOptics optics;
    optics.render_scale = onboard_scale;
    renderer.drawOnboard(colon, q, shape, tip_camera, Viewport{0, 0, width_px, height_px}, optics);
    x = width_px;
  }
  // The global view stays at full size: under llvmpipe its cost is mostly per vertex and
  // the stretching blit would cost what the smaller image saves (measured, README).
  if (view == "global" || view == "both")
    renderer.drawGlobal(colon, q, shape, global_camera, Viewport{x, 0, width_px, height_px});
}

FrameWriter makeFrameWriter(const std::string& dir, const std::string& view, int width_px, int height_px) {
  auto st = std::make_shared<FrameState>();
  return [st, dir, view, width_px, height_px](const Simulation& base, long steps_done) {
    const auto* sim = dynamic_cast<const WorldSimulation*>(&base);
    if (!sim) return;
    const int total_width = view == "both" ? 2 * width_px : width_px;
    if (!st->context) {
      st->context = std::make_unique<OffscreenContext>(total_width, height_px);
      st->renderer = std::make_unique<Renderer>();
      const Points& rest = sim->model().colon.q_rest;
      st->global_camera = frameBox(rest.rowwise().minCoeff(), rest.rowwise().maxCoeff(),
                                   static_cast<double>(width_px) / height_px);
    }
    st->context->makeCurrent();
    drawViews(*st->renderer, *sim, view, width_px, height_px, st->global_camera);
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%06ld.png", steps_done);
    writePng(dir + name, st->context->read());
  };
}

}  // namespace colosim::app
