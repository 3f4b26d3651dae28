// GLFW smoke test: a real window (under xvfb-run -a in ctest) drawn by the same Renderer.
#include "render/window.h"

#include <gtest/gtest.h>

#include "tests/render/render_fixture.h"

namespace colosim {
namespace {

TEST(Window, SplitViewDrawsBothHalves) {
  std::unique_ptr<Window> window;
  try {
    window = std::make_unique<Window>(480, 240, "colosim window test", /*visible=*/true);
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no display: " << e.what();
  }
  Renderer renderer;
  const ColonModel colon = test::straightColon();
  const ScopeShape scope{{Vec3(0, 0, 0), Vec3(0, 0, 0.03), Vec3(0, 0, 0.06)}, 0.0065};
  const CameraPose tip = lookAlong(Vec3(0, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY());
  for (int frame = 0; frame < 3; ++frame) {
    window->pollEvents();
    window->drawSplit(renderer, colon, colon.q_rest, scope, tip);
    ASSERT_TRUE(drainGlErrors().empty());
    if (frame < 2) window->swapBuffers();
  }
  const Image img = window->read();
  ASSERT_EQ(img.width, window->framebufferWidth());
  ASSERT_EQ(img.height, window->framebufferHeight());
  // Left half: the onboard image has a bright wall; right half: the global background.
  double left = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width / 2; ++x) left += img.at(x, y)[0];
  EXPECT_GT(left / (img.height * img.width / 2), 40);
  const GlobalStyle style;
  EXPECT_NEAR(img.at(img.width - 1, 0)[2], std::lround(style.background[2] * 255), 1);
  window->globalCamera().orbit(0.3, 0.1);
  window->globalCamera().zoom(0.8);
  window->drawSplit(renderer, colon, colon.q_rest, scope, tip);
  EXPECT_TRUE(drainGlErrors().empty());
}

}  // namespace
}  // namespace colosim
