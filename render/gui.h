// Dear ImGui over a Window (Debian's libimgui-dev 1.86, with its GLFW and OpenGL 3
// back ends): the panels, overlays and screens that colosim train draws over the views.
// The caller includes <imgui.h> and builds its widgets between newFrame() and render().
#pragma once

namespace colosim {

class Window;

/// One ImGui context bound to a window's GL 3.3 core context. The window's own mouse
/// callbacks keep working: ImGui's GLFW back end chains to them.
class Gui {
 public:
  /// Creates the ImGui context and its GLFW and OpenGL 3 back ends for `window` (current).
  /// font_px: size of ImGui's built-in font [px]. Throws std::runtime_error when a back end
  /// cannot start.
  explicit Gui(Window& window, float font_px = 15.0f);
  ~Gui();
  Gui(const Gui&) = delete;
  Gui& operator=(const Gui&) = delete;

  /// Starts an ImGui frame (after Window::pollEvents).
  void newFrame();
  /// Draws the frame's widgets over what is in the back buffer (before swapBuffers).
  void render();
  /// ImGui wants the mouse (a widget under the cursor): the window then leaves the global
  /// view's camera alone.
  bool wantsMouse() const;
};

}  // namespace colosim
