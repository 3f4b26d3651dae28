#include "render/offscreen_context.h"

// clang-format off
// glad first: it defines the GL types and keeps GL/gl.h (pulled by osmesa.h) out.
#include <glad/gl.h>
#include <GL/osmesa.h>
// clang-format on

#include <cstring>
#include <stdexcept>
#include <string>

#include "render/renderer.h"

namespace colosim {

namespace {

GLADapiproc osmesaProc(const char* name) { return reinterpret_cast<GLADapiproc>(OSMesaGetProcAddress(name)); }

}  // namespace

OffscreenContext::OffscreenContext(int width, int height) {
  if (width <= 0 || height <= 0)
    throw std::runtime_error("render: offscreen size must be positive, got " + std::to_string(width) + " x " +
                             std::to_string(height));
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         0,
                         OSMESA_ACCUM_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  keepDriverMemoryBetweenFrames();
  ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx_) throw std::runtime_error("render: OSMesa could not create a GL 3.3 core context");
  try {
    resize(width, height);
  } catch (...) {
    OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
    throw;
  }
}

OffscreenContext::~OffscreenContext() {
  if (ctx_) OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
}

void OffscreenContext::resize(int width, int height) {
  if (width <= 0 || height <= 0) throw std::runtime_error("render: offscreen size must be positive");
  width_ = width;
  height_ = height;
  buffer_.assign(static_cast<size_t>(width) * height * 4, 0);
  makeCurrent();
}

void OffscreenContext::makeCurrent() {
  if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(ctx_), buffer_.data(), GL_UNSIGNED_BYTE, width_, height_))
    throw std::runtime_error("render: OSMesaMakeCurrent failed");
  if (!gladLoadGL(osmesaProc)) throw std::runtime_error("render: glad could not load GL through OSMesa");
}

Image OffscreenContext::read() const {
  Image img;
  read(img);
  return img;
}

void OffscreenContext::read(Image& out) const {
  // OSMesa renders into our buffer: after glFinish it holds the image (OSMesa's contract),
  // bottom row first. Copying its rows in reverse order is the whole read: no glReadPixels
  // (a second copy with a format conversion) and no flip in place.
  glFinish();
  out.width = width_;
  out.height = height_;
  const size_t stride = static_cast<size_t>(width_) * 4;
  out.rgba.resize(stride * height_);
  for (int y = 0; y < height_; ++y)
    std::memcpy(out.at(0, y), buffer_.data() + stride * static_cast<size_t>(height_ - 1 - y), stride);
}

}  // namespace colosim
