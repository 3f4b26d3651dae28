#include "render/image.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/fixture.h"

namespace colosim {
namespace {

TEST(Png, RoundTripsExactly) {
  test::TempDir dir;
  Image img(37, 19);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      uint8_t* p = img.at(x, y);
      p[0] = static_cast<uint8_t>(7 * x), p[1] = static_cast<uint8_t>(13 * y),
      p[2] = static_cast<uint8_t>(x ^ y), p[3] = static_cast<uint8_t>(255 - x);
    }
  const std::string path = dir.file("a.png");
  writePng(path, img);
  const Image back = readPng(path);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 19);
  EXPECT_EQ(back.rgba, img.rgba);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(Png, BadFilesAreErrorsNamingThePath) {
  test::TempDir dir;
  const std::string junk = dir.write("junk.png", "not a png at all");
  try {
    readPng(junk);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(junk), std::string::npos);
  }
  // A truncated PNG.
  Image img(64, 64);
  writePng(dir.file("ok.png"), img);
  const std::string bytes = test::readFile(dir.file("ok.png"));
  const std::string cut = dir.write("cut.png", bytes.substr(0, bytes.size() / 2));
  EXPECT_THROW(readPng(cut), std::runtime_error);
  EXPECT_THROW(readPng(dir.file("missing.png")), std::runtime_error);
  EXPECT_THROW(writePng(dir.file("no/such/dir/x.png"), img), std::runtime_error);
  EXPECT_THROW(writePng(dir.file("empty.png"), Image()), std::runtime_error);
}

}  // namespace
}  // namespace colosim
