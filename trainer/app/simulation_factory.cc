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

namespace {

// The onboard camera at the scope tip: forward along the tip axis, the image's right is
// -d1 and its down -d2 (core/scope_model.h).
CameraPose tipCamera(const WorldSimulation& sim) {
  const ScopeState& s = sim.state().scope;
  CameraPose pose;
  pose.p_WC_m = tipPosition(sim.model().scope, s);
  const Mat3& R = s.R_WS[0];
  pose.R_WC.col(0) = -R.col(0);
  pose.R_WC.col(1) = -R.col(1);
  pose.R_WC.col(2) = R.col(2);
  return pose;
}

struct FrameState {
  std::unique_ptr<OffscreenContext> context;
  std::unique_ptr<Renderer> renderer;
  OrbitCamera global_camera;
};

}  // namespace

void drawViews(Renderer& renderer, const WorldSimulation& sim, const std::string& view, int width_px,
               int height_px, const OrbitCamera& global_camera) {
  const ColonModel& colon = sim.model().colon;
  const Points& q = sim.state().colon.q;
  ScopeShape shape;
  shape.centreline_m = sim.scopeCentreline();
  shape.radius_m = sim.model().scope.radius_m;
  int x = 0;
  if (view == "onboard" || view == "both") {
    renderer.drawOnboard(colon, q, shape, tipCamera(sim), Viewport{0, 0, width_px, height_px});
    x = width_px;
  }
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
