#include "trainer/scene_drawing.h"

#include <cstdio>
#include <memory>

#include "core/colon_model.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/offscreen_context.h"
#include "render/renderer.h"

namespace colosim {

CameraPose tipCameraPose(const Vec3& p_WTip_m, const Mat3& R_WTip) {
  CameraPose pose;
  pose.p_WC_m = p_WTip_m;
  pose.R_WC.col(0) = -R_WTip.col(0);
  pose.R_WC.col(1) = -R_WTip.col(1);
  pose.R_WC.col(2) = R_WTip.col(2);
  return pose;
}

OrbitCamera globalCameraFor(const SceneView& scene, double aspect) {
  const Points& rest = scene.colon->q_rest;
  return frameBox(rest.rowwise().minCoeff(), rest.rowwise().maxCoeff(), aspect);
}

void drawViews(Renderer& renderer, const SceneView& scene, const std::string& view, int width_px, int height_px,
               const OrbitCamera& global_camera, double onboard_scale) {
  ScopeShape shape;
  shape.centreline_m = scene.scope_centreline_m;
  shape.radius_m = scene.scope_radius_m;
  int x = 0;
  if (view == "onboard" || view == "both") {
    OnboardOptics optics;
    optics.render_scale = onboard_scale;
    optics.light_ref_m = scene.tip_light_reach_m;
    renderer.drawOnboard(*scene.colon, scene.colon_q, shape, tipCameraPose(scene.p_WTip_m, scene.R_WTip),
                         Viewport{0, 0, width_px, height_px}, optics);
    x = width_px;
  }
  // The global view stays at full size: under llvmpipe its cost is mostly per vertex and
  // the stretching blit would cost what the smaller image saves (measured, README).
  if (view == "global" || view == "both")
    renderer.drawGlobal(*scene.colon, scene.colon_q, shape, global_camera, Viewport{x, 0, width_px, height_px});
}

namespace {

struct FrameState {
  std::unique_ptr<OffscreenContext> context;
  std::unique_ptr<Renderer> renderer;
  OrbitCamera global_camera;
  SceneView scene;
  Image image;  // the frame read back, its storage kept between frames
};

}  // namespace

FrameWriter makeFrameWriter(const std::string& dir, const std::string& view, int width_px, int height_px) {
  auto st = std::make_shared<FrameState>();
  return [st, dir, view, width_px, height_px](const Simulation& sim, long steps_done) {
    if (!sim.scene(st->scene)) return;
    const int total_width = view == "both" ? 2 * width_px : width_px;
    if (!st->context) {
      st->context = std::make_unique<OffscreenContext>(total_width, height_px);
      st->renderer = std::make_unique<Renderer>();
      st->global_camera = globalCameraFor(st->scene, static_cast<double>(width_px) / height_px);
    }
    st->context->makeCurrent();
    drawViews(*st->renderer, st->scene, view, width_px, height_px, st->global_camera);
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%06ld.png", steps_done);
    st->context->read(st->image);
    writePng(dir + name, st->image);
  };
}

}  // namespace colosim
