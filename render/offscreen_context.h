// A headless GL 3.3 core context through OSMesa (Mesa's llvmpipe): no display needed.
// Used by tests, benchmarks and image export.
#pragma once

#include <cstdint>
#include <vector>

#include "render/image.h"

namespace colosim {

class OffscreenContext {
 public:
  /// Creates a width x height RGBA context with a 24-bit depth buffer, makes it current
  /// and loads GL through glad. Throws std::runtime_error if OSMesa cannot make a 3.3
  /// core context or the size is not positive.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Makes this context current again (and reloads glad's function pointers: another
  /// context, e.g. a GLFW window, may have been current in between).
  void makeCurrent();
  /// Changes the image size; the context, and a Renderer made in it, stay valid.
  void resize(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  /// The whole image, top-down: glFinish, then the rows of OSMesa's buffer (which hold
  /// what glReadPixels would return; tested).
  Image read() const;
  /// The same into `out`, reusing its storage: a frame loop allocates nothing after its
  /// first frame.
  void read(Image& out) const;

 private:
  void* ctx_ = nullptr;  // OSMesaContext
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> buffer_;  // OSMesa's colour buffer
};

}  // namespace colosim
