#include "render/window.h"

// GLFW must not include the system GL header: glad provides GL.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glad/gl.h>

#include <algorithm>
#include <stdexcept>

namespace colosim {

namespace {

int g_glfw_users = 0;  // glfwInit / glfwTerminate are process-wide: count the windows
std::string g_glfw_error;

void onGlfwError(int, const char* text) { g_glfw_error = text ? text : "unknown"; }

}  // namespace

Window::Window(int width, int height, const std::string& title, bool visible) {
  keepDriverMemoryBetweenFrames();
  glfwSetErrorCallback(onGlfwError);
  if (g_glfw_users == 0 && !glfwInit())
    throw std::runtime_error("render: GLFW could not start (no display?): " + g_glfw_error);
  ++g_glfw_users;
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    if (--g_glfw_users == 0) glfwTerminate();
    throw std::runtime_error("render: GLFW could not open a GL 3.3 core window: " + g_glfw_error);
  }
  glfwSetWindowUserPointer(window_, this);
  glfwSetCursorPosCallback(window_, onCursor);
  glfwSetMouseButtonCallback(window_, onButton);
  glfwSetScrollCallback(window_, onScroll);
  glfwSetKeyCallback(window_, onKey);
  makeCurrent();
  glfwSwapInterval(1);
}

Window::~Window() {
  glfwDestroyWindow(window_);
  if (--g_glfw_users == 0) glfwTerminate();
}

void Window::makeCurrent() {
  glfwMakeContextCurrent(window_);
  if (!gladLoadGL(glfwGetProcAddress))
    throw std::runtime_error("render: glad could not load GL through GLFW");
}

bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }
void Window::pollEvents() { glfwPollEvents(); }
void Window::swapBuffers() { glfwSwapBuffers(window_); }

int Window::framebufferWidth() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return w;
}

int Window::framebufferHeight() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return h;
}

void Window::drawSplit(Renderer& renderer, const ColonModel& model, const Points& q, const ScopeShape& scope,
                       const CameraPose& onboard, const OnboardOptics& optics, const GlobalStyle& style) {
  const int w = framebufferWidth(), h = framebufferHeight();
  if (w < 2 || h < 1) return;  // minimised
  const Viewport left{0, 0, w / 2, h}, right{w / 2, 0, w - w / 2, h};
  if (!orbit_framed_) {
    Vec3 lo = q.rowwise().minCoeff(), hi = q.rowwise().maxCoeff();
    orbit_ = frameBox(lo, hi, static_cast<double>(right.width) / right.height);
    orbit_framed_ = true;
  }
  renderer.drawOnboard(model, q, scope, onboard, left, optics);
  renderer.drawGlobal(model, q, scope, orbit_, right, style);
}

void Window::clear(float r, float g, float b) {
  glViewport(0, 0, framebufferWidth(), framebufferHeight());
  glDisable(GL_SCISSOR_TEST);
  glClearColor(r, g, b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

Image Window::read() const {
  return readFramebuffer(Viewport{0, 0, framebufferWidth(), framebufferHeight()});
}

void Window::onButton(GLFWwindow* w, int button, int action, int mods) {
  auto* self = static_cast<Window*>(glfwGetWindowUserPointer(w));
  if (action == GLFW_PRESS) {
    double x = 0, y = 0;
    int ww = 0, wh = 0;
    glfwGetCursorPos(w, &x, &y);
    glfwGetWindowSize(w, &ww, &wh);
    if (x < self->global_left_ * ww) return;  // left of it is the onboard view: not steerable here
    if (self->mouse_blocked_) return;         // on a widget
    self->drag_button_ = button;
    self->drag_pan_ = button == GLFW_MOUSE_BUTTON_RIGHT || (mods & GLFW_MOD_SHIFT);
    glfwGetCursorPos(w, &self->last_x_, &self->last_y_);
  } else if (action == GLFW_RELEASE && button == self->drag_button_) {
    self->drag_button_ = -1;
  }
}

void Window::onCursor(GLFWwindow* w, double x, double y) {
  auto* self = static_cast<Window*>(glfwGetWindowUserPointer(w));
  if (self->drag_button_ < 0) return;
  int ww = 0, wh = 0;
  glfwGetWindowSize(w, &ww, &wh);
  const double dx = (x - self->last_x_) / std::max(wh, 1), dy = (y - self->last_y_) / std::max(wh, 1);
  self->last_x_ = x, self->last_y_ = y;
  if (self->drag_pan_)
    self->orbit_.pan(-dx, dy);
  else
    self->orbit_.orbit(-3.0 * dx, 3.0 * dy);
}

std::vector<int> Window::takeKeyPresses() {
  std::vector<int> presses;
  presses.swap(key_presses_);
  return presses;
}

void Window::onKey(GLFWwindow* w, int key, int, int action, int) {
  auto* self = static_cast<Window*>(glfwGetWindowUserPointer(w));
  if (action == GLFW_PRESS && self->key_presses_.size() < 256) self->key_presses_.push_back(key);
}

void Window::onScroll(GLFWwindow* w, double, double dy) {
  auto* self = static_cast<Window*>(glfwGetWindowUserPointer(w));
  double x = 0, y = 0;
  int ww = 0, wh = 0;
  glfwGetCursorPos(w, &x, &y);
  glfwGetWindowSize(w, &ww, &wh);
  if (x < self->global_left_ * ww || self->mouse_blocked_) return;
  self->orbit_.zoom(dy > 0 ? 0.9 : 1.0 / 0.9);
}

}  // namespace colosim
