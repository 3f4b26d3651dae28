// The renderer: a thin GL 3.3 core layer drawing the onboard and global views into
// whatever GL context is current (OSMesa's OffscreenContext or GLFW's Window). Meshes
// are rebuilt from the control points on every draw (tube_mesh.h) and streamed to GL.
//
// A Renderer owns GL objects of the context that was current when it was made: make
// that context current (OffscreenContext / Window do it on construction) before making,
// using or destroying it.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/colon_model.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/mucosa_texture.h"
#include "render/tube_mesh.h"

namespace colosim {

/// A rectangle of the current framebuffer in GL pixels (origin at the bottom left).
struct Viewport {
  int x = 0, y = 0, width = 0, height = 0;
};

/// Look of the global (scope-position) view.
struct GlobalStyle {
  std::array<float, 3> background{0.07f, 0.08f, 0.11f};
  std::array<float, 3> colon_rgb{0.95f, 0.55f, 0.55f};
  float colon_alpha_face = 0.07f;                       ///< opacity where the wall faces the viewer [-]
  float colon_alpha_silhouette = 0.55f;                 ///< opacity at grazing angles (the outline) [-]
  std::array<float, 3> scope_rgb{0.15f, 0.95f, 0.35f};  ///< distinct, opaque
  std::array<float, 3> tip_rgb{1.0f, 0.85f, 0.1f};      ///< the last few cm of the scope
  double tip_length_m = 0.03;
  // The outside view needs no fine detail: a coarser colon without folds keeps it cheap.
  int colon_sides = 16;               ///< facets around the colon
  int colon_samples_per_segment = 4;  ///< rings per spline segment
  double render_scale = 1.0;          ///< as OnboardOptics::render_scale
};

class Renderer {
 public:
  /// Compiles the shaders and uploads the mucosa texture. Needs a current GL 3.3 context
  /// loaded with glad; throws std::runtime_error with the GL log if a shader fails.
  explicit Renderer(const TubeOptions& tube = {}, const MucosaOptions& mucosa = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// The colonoscope image from `camera` (at the tip, forward = tip axis): the colon wall
  /// lit by the tip light, and the scope itself (visible when retroflexed).
  void drawOnboard(const ColonModel& model, const Points& q, const ScopeShape& scope,
                   const CameraPose& camera, const Viewport& viewport, const OnboardOptics& optics = {});
  void drawOnboard(const ColonModel& model, const Points& q, const ScopeShape& scope,
                   const CameraPose& camera, int width, int height) {
    drawOnboard(model, q, scope, camera, Viewport{0, 0, width, height});
  }

  /// The scope-position display: see-through colon, opaque scope, from an orbit camera.
  void drawGlobal(const ColonModel& model, const Points& q, const ScopeShape& scope,
                  const OrbitCamera& camera, const Viewport& viewport, const GlobalStyle& style = {});
  void drawGlobal(const ColonModel& model, const Points& q, const ScopeShape& scope,
                  const OrbitCamera& camera, int width, int height) {
    drawGlobal(model, q, scope, camera, Viewport{0, 0, width, height});
  }

  /// The last meshes built (for inspection and tests): the onboard view's colon, the
  /// global view's coarser colon, and the scope.
  const TubeMesh& colonMesh() const { return colon_mesh_; }
  const TubeMesh& globalColonMesh() const { return colon_global_mesh_; }
  const TubeMesh& scopeMesh() const { return scope_mesh_; }
  const TubeOptions& tubeOptions() const { return tube_; }

 private:
  struct Gl;
  void uploadMeshes(const ColonModel& model, const Points& q, const ScopeShape& scope,
                    const TubeOptions& options, bool global);
  // Render scale: beginScaled binds an offscreen target of the scaled size (when scale < 1)
  // and returns the viewport to draw into; endScaled stretches it onto `viewport` of the
  // framebuffer that was bound before. std::invalid_argument outside [0.25, 1].
  Viewport beginScaled(const Viewport& viewport, double scale);
  void endScaled(const Viewport& viewport, const Viewport& drawn);
  // Exact distortion: binds the rectilinear target sized for `target` and returns its viewport.
  Viewport beginExact(const Viewport& target);
  TubeOptions tube_;
  ColonRings rings_;
  TubeMesh colon_mesh_, colon_global_mesh_, scope_mesh_;
  std::vector<uint32_t> detail_indices_;  // the onboard colon's triangles drawn in the last frame
  std::unique_ptr<Gl> gl_;
};

/// Reads a rectangle of the current framebuffer as a top-down RGBA image (glFinish, then
/// glReadPixels, whose rows come bottom-up, flipped).
Image readFramebuffer(const Viewport& viewport);

/// Keeps the heap's freed memory in the process between frames (glibc's trim threshold to
/// 128 MB; once per process, called by both GL back ends when they make a context).
/// llvmpipe, the GL here, allocates and frees megabytes per draw; glibc gave the heap's
/// free top back to the system after each, and the next frame had the kernel map and zero
/// it again page by page: 60 % of a global-view frame (`colosim bench render`). The cost is
/// at most 128 MB kept mapped beyond what the process has needed at once.
void keepDriverMemoryBetweenFrames();

/// Drains glGetError: the error codes raised since the last call (empty when none).
std::vector<unsigned> drainGlErrors();

}  // namespace colosim
