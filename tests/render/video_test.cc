#include "render/video.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "tests/fixture.h"

namespace colosim {
namespace {

// A smooth test card that moves with k: what a lossy codec keeps well.
Image card(int w, int h, int k) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = img.at(x, y);
      p[0] = static_cast<uint8_t>(128 + 100 * std::sin(0.1 * (x + 3 * k)));
      p[1] = static_cast<uint8_t>(128 + 100 * std::cos(0.13 * (y - 2 * k)));
      p[2] = static_cast<uint8_t>((x + y) * 255 / (w + h));
      p[3] = 255;
    }
  return img;
}

// Mean |difference| over the RGB channels [levels of 255].
double meanAbsDiff(const Image& a, const Image& b) {
  double sum = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) sum += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
  return sum / (3.0 * a.width * a.height);
}

TEST(Video, EncodesEveryFrameAndDecodesCloseToTheImages) {
  test::TempDir dir;
  const std::string path = dir.file("card.mp4");
  {
    VideoEncoder v(path, 96, 64, VideoOptions{});
    EXPECT_EQ(v.codec(), "libx264");  // Debian's libavcodec is built with it
    for (int k = 0; k < 12; ++k) v.add(card(96, 64, k));
    v.finish();
    EXPECT_EQ(v.frames(), 12);
  }
  const std::vector<Image> back = readVideoFrames(path);
  ASSERT_EQ(back.size(), 12u);
  for (int k = 0; k < 12; ++k) {
    ASSERT_EQ(back[k].width, 96);
    ASSERT_EQ(back[k].height, 64);
    // crf 18 with 4:2:0 chroma: ~1 level measured on this card; a frame out of order
    // differs by tens of levels.
    EXPECT_LT(meanAbsDiff(back[k], card(96, 64, k)), 3.0) << "frame " << k;
  }
  EXPECT_GT(meanAbsDiff(back[5], card(96, 64, 8)), 10.0);
}

// The second video is encoded with glibc filling every fresh allocation with a pattern, so
// an encoder that reads memory it never wrote gives other bytes (x264's AVX-512 code did).
TEST(Video, SameFramesGiveTheSameBytes) {
  test::TempDir dir;
  for (const char* name : {"a.mp4", "b.mp4"}) {
    if (name[0] == 'b') mallopt(M_PERTURB, 0x5a);
    VideoEncoder v(dir.file(name), 32, 32);
    for (int k = 0; k < 5; ++k) v.add(card(32, 32, k));
    v.finish();
  }
  mallopt(M_PERTURB, 0);
  EXPECT_EQ(test::readFile(dir.file("a.mp4")), test::readFile(dir.file("b.mp4")));
}

TEST(Video, NeverOverwritesAFile) {
  test::TempDir dir;
  const std::string path = dir.write("taken.mp4", "precious");
  try {
    VideoEncoder v(path, 32, 32);
    FAIL() << "an existing file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exists"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::readFile(path), "precious");
}

TEST(Video, UnfinishedOrBadVideosLeaveNoFile) {
  test::TempDir dir;
  const std::string path = dir.file("cut.mp4");
  {
    VideoEncoder v(path, 32, 32);
    v.add(card(32, 32, 0));
    EXPECT_THROW(v.add(card(34, 32, 0)), std::runtime_error);  // wrong size
  }  // not finished: the incomplete file is removed
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_THROW(VideoEncoder(dir.file("odd.mp4"), 33, 32), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir.file("odd.mp4")));
  EXPECT_THROW(readVideoFrames(dir.write("junk.mp4", "not a video")), std::runtime_error);
}

}  // namespace
}  // namespace colosim
