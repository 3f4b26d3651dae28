// A GLFW window owning a GL 3.3 core context, drawn by the same Renderer as the
// headless path. Mouse on the global view: left drag orbits, right (or shift-left)
// drag pans, the wheel zooms.
#pragma once

#include <string>

#include "render/camera.h"
#include "render/image.h"
#include "render/renderer.h"

struct GLFWwindow;

namespace colosim {

class Window {
 public:
  /// Opens a window (hidden when visible = false) with a 3.3 core context, makes it
  /// current and loads GL through glad. Throws std::runtime_error without a display.
  Window(int width, int height, const std::string& title, bool visible = true);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  void makeCurrent();
  bool shouldClose() const;
  void pollEvents();
  void swapBuffers();
  int framebufferWidth() const;
  int framebufferHeight() const;

  /// The global view's camera, steered by the mouse over the right half of the window.
  OrbitCamera& globalCamera() { return orbit_; }

  /// Split view: onboard on the left half, global on the right half.
  void drawSplit(Renderer& renderer, const ColonModel& model, const Points& q, const ScopeShape& scope,
                 const CameraPose& onboard, const OnboardOptics& optics = {}, const GlobalStyle& style = {});

  /// The current back buffer, top-down (before swapBuffers).
  Image read() const;

 private:
  static void onCursor(GLFWwindow* w, double x, double y);
  static void onButton(GLFWwindow* w, int button, int action, int mods);
  static void onScroll(GLFWwindow* w, double dx, double dy);

  GLFWwindow* window_ = nullptr;
  OrbitCamera orbit_;
  bool orbit_framed_ = false;  // framed on the colon at the first draw
  int drag_button_ = -1;
  bool drag_pan_ = false;
  double last_x_ = 0, last_y_ = 0;
};

}  // namespace colosim
