#include "trainer/frame_export.h"

#include <cstdio>

#include "render/camera.h"
#include "render/offscreen_context.h"
#include "render/renderer.h"
#include "render/video.h"
#include "trainer/scene_drawing.h"

namespace colosim {

SceneImager::SceneImager(std::string view, int width_px, int height_px)
    : view_(std::move(view)), width_px_(width_px), height_px_(height_px) {}

SceneImager::~SceneImager() = default;

bool SceneImager::render(const Simulation& sim, Image& out) {
  if (!sim.scene(scene_)) return false;
  if (!context_) {
    context_ = std::make_unique<OffscreenContext>(imageWidth(), height_px_);
    renderer_ = std::make_unique<Renderer>();
    global_camera_ = std::make_unique<OrbitCamera>(globalCameraFor(scene_, static_cast<double>(width_px_) / height_px_));
  }
  context_->makeCurrent();
  drawViews(*renderer_, scene_, view_, width_px_, height_px_, *global_camera_);
  context_->read(out);
  return true;
}

FrameExporter::FrameExporter(const FrameExportOptions& options)
    : o_(options), imager_(options.view, options.width_px, options.height_px) {
  if (!o_.video_path.empty()) {
    VideoOptions v;
    v.fps = o_.fps;
    video_ = std::make_unique<VideoEncoder>(o_.video_path, imager_.imageWidth(), imager_.imageHeight(), v);
  }
}

FrameExporter::~FrameExporter() = default;

void FrameExporter::operator()(const Simulation& sim, long steps_done) {
  if (!imager_.render(sim, image_)) return;
  if (!o_.frames_dir.empty()) {
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%06ld.png", steps_done);
    writePng(o_.frames_dir + name, image_);
  }
  if (video_) video_->add(image_);
  ++frames_;
}

void FrameExporter::finish() {
  if (video_) video_->finish();
}

}  // namespace colosim
