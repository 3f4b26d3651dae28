// Images of a simulation for export: PNG frames and videos of a run or replay, and the
// global views of a session report, each rendered once offscreen (OSMesa).
#pragma once

#include <memory>
#include <string>

#include "render/image.h"
#include "trainer/simulation.h"

namespace colosim {

class OffscreenContext;
class Renderer;
class VideoEncoder;
struct OrbitCamera;

/// Renders a simulation's scene (view "onboard", "global" or "both" side by side, each
/// width x height pixels) into images, in its own offscreen GL context, made on the
/// first image. The global camera frames the colon's rest shape.
class SceneImager {
 public:
  SceneImager(std::string view, int width_px, int height_px);
  ~SceneImager();
  SceneImager(const SceneImager&) = delete;
  SceneImager& operator=(const SceneImager&) = delete;
  /// The current state as an image; false when the simulation has nothing to draw.
  bool render(const Simulation& sim, Image& out);
  /// Image size [px]: twice the width for "both".
  int imageWidth() const { return view_ == "both" ? 2 * width_px_ : width_px_; }
  int imageHeight() const { return height_px_; }

 private:
  std::string view_;
  int width_px_, height_px_;
  std::unique_ptr<OffscreenContext> context_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<OrbitCamera> global_camera_;
  SceneView scene_;
};

/// What a run or replay exports: PNG frames into a folder, a video file, or both, from
/// one rendering per frame.
struct FrameExportOptions {
  std::string frames_dir;  ///< "" for none: frame_NNNNNN.png, NNNNNN the steps done
  std::string video_path;  ///< "" for none: a new file (render/video.h)
  std::string view = "onboard";
  int width_px = 640, height_px = 480;  ///< each view [px]
  double fps = 30;  ///< playback rate of the video [frames per second]: one frame per 1 / fps simulated s
};

/// The frame hook of a run or replay (RunHooks::on_frame). Creates the video file at
/// construction (std::runtime_error when it exists or cannot be made).
class FrameExporter {
 public:
  explicit FrameExporter(const FrameExportOptions& options);
  ~FrameExporter();
  /// Renders the current state and writes it as a PNG and/or a video frame.
  void operator()(const Simulation& sim, long steps_done);
  /// Completes the video (call after the run; without it the incomplete video is removed).
  void finish();
  long frames() const { return frames_; }

 private:
  FrameExportOptions o_;
  SceneImager imager_;
  std::unique_ptr<VideoEncoder> video_;
  Image image_;
  long frames_ = 0;
};

}  // namespace colosim
