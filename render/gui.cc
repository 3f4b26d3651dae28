#include "render/gui.h"

#include <stdexcept>

// GLFW must not include the system GL header: glad (the renderer) and ImGui's own loader
// provide GL.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "render/window.h"

namespace colosim {

Gui::Gui(Window& window, float font_px) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini written next to the user's files
  ImFontConfig font;
  font.SizePixels = font_px;
  io.Fonts->AddFontDefault(&font);
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 4.0f;
  // Callbacks installed: ImGui sees keys and the mouse, then calls the window's own.
  if (!ImGui_ImplGlfw_InitForOpenGL(window.handle(), true)) {
    ImGui::DestroyContext();
    throw std::runtime_error("render: ImGui's GLFW back end could not start");
  }
  if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    throw std::runtime_error("render: ImGui's OpenGL 3 back end could not start");
  }
}

Gui::~Gui() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Gui::newFrame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void Gui::render() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool Gui::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }

}  // namespace colosim
