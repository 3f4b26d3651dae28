// A GLFW window owning a GL 3.3 core context, drawn by the same Renderer as the
// headless path. Mouse on the global view: left drag orbits, right (or shift-left)
// drag pans, the wheel zooms.
#pragma once

#include <string>
#include <vector>

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
  /// Where the global view starts, as a fraction of the window's width: the mouse steers
  /// it right of there (0.5: split view, the default; 0: it fills the window; 1: hidden).
  void setGlobalViewLeft(double fraction) { global_left_ = fraction; }
  /// While blocked, a mouse press does not start steering the global view (an ImGui
  /// widget under the cursor takes it: Gui::wantsMouse).
  void setMouseBlocked(bool blocked) { mouse_blocked_ = blocked; }

  /// The keys pressed (GLFW key codes, in order) since the last call: presses are seen even
  /// when the key was released again before the next poll (a busy frame), unlike the
  /// state glfwGetKey gives.
  std::vector<int> takeKeyPresses();

  /// The GLFW window, for polling keys and gamepads (colosim train).
  GLFWwindow* handle() { return window_; }

  /// Split view: onboard on the left half, global on the right half.
  void drawSplit(Renderer& renderer, const ColonModel& model, const Points& q, const ScopeShape& scope,
                 const CameraPose& onboard, const OnboardOptics& optics = {}, const GlobalStyle& style = {});

  /// Clears the whole back buffer to this colour (a screen with no view behind it).
  void clear(float r, float g, float b);

  /// The current back buffer, top-down (before swapBuffers).
  Image read() const;

 private:
  static void onCursor(GLFWwindow* w, double x, double y);
  static void onButton(GLFWwindow* w, int button, int action, int mods);
  static void onScroll(GLFWwindow* w, double dx, double dy);
  static void onKey(GLFWwindow* w, int key, int scancode, int action, int mods);

  GLFWwindow* window_ = nullptr;
  OrbitCamera orbit_;
  bool orbit_framed_ = false;  // framed on the colon at the first draw
  double global_left_ = 0.5;   // the global view's left edge over the window's width
  bool mouse_blocked_ = false;
  std::vector<int> key_presses_;  // since the last takeKeyPresses
  int drag_button_ = -1;
  bool drag_pan_ = false;
  double last_x_ = 0, last_y_ = 0;
};

}  // namespace colosim
