// Exports through the command (issue 19): `colosim run/replay --video` decoded back and
// compared with the PNG frames of the same steps.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "fixture.h"
#include "render/image.h"
#include "render/video.h"

namespace colosim {
namespace {

namespace fs = std::filesystem;

using Result = test::CommandOutput;


// Mean |difference| over the RGB channels [levels of 255].
double meanAbsDiff(const Image& a, const Image& b) {
  double sum = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) sum += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
  return sum / (3.0 * a.width * a.height);
}

// 3 s of the expert's scenario at 4 frames per simulated second, both views at 96 x 64
// each: 13 frames (steps 0, 250, ..., 3000); the scope starts turning at 2 s.
constexpr const char* kRunArgs = "run sigmoid_untwist --duration 3 --fps 4 --view both --size 96x64";

TEST(VideoCli, RunVideoHasThePngFramesAndReplayMakesTheSameFile) {
  test::TempDir dir;
  const std::string video = dir.file("run.mp4"), frames = dir.file("frames"), session = dir.file("s.jsonl");
  const Result r = test::runColosim(std::string(kRunArgs) + " --frames " + frames + " --video " + video + " --record " + session, dir);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("video written in"), std::string::npos) << r.out;
  // FFmpeg's and x264's chatter stays off (the sanitized build's LeakSanitizer adds its
  // report of suppressed leaks at exit: not ours to silence).
  std::string run_err = r.err;
  const size_t lsan = run_err.find("-----------------------------------------------------\nSuppressions used:");
  if (lsan != std::string::npos) run_err.erase(lsan);
  EXPECT_EQ(run_err, "");

  std::vector<std::string> pngs;
  for (const auto& e : fs::directory_iterator(frames)) pngs.push_back(e.path().string());
  std::sort(pngs.begin(), pngs.end());
  ASSERT_EQ(pngs.size(), 13u);
  const std::vector<Image> decoded = readVideoFrames(video);
  ASSERT_EQ(decoded.size(), pngs.size());
  // The frame of step 3000 against its PNG: H.264 at crf 18 in 4:2:0 costs 2.3 levels of
  // 255 on average here (measured; the small image is mostly edges); 4 levels allowed. The
  // frames of 2 s (before the scope turns) and 2.75 s differ from it by 14.4 and 5.3 levels.
  const Image png = readPng(pngs[12]);
  ASSERT_EQ(decoded[12].width, png.width);
  ASSERT_EQ(decoded[12].height, png.height);
  const double err = meanAbsDiff(decoded[12], png);
  EXPECT_LT(err, 4.0);
  EXPECT_GT(meanAbsDiff(decoded[11], png), 4.0);  // the frame before is told apart
  EXPECT_EQ(decoded[0].width, 192);  // both views side by side

  // The replay of the recorded session gives the same frames, hence the same bytes.
  const std::string replayed = dir.file("replay.mp4");
  const Result p = test::runColosim("replay " + session + " --fps 4 --view both --size 96x64 --video " + replayed, dir);
  ASSERT_EQ(p.code, 0) << p.out << p.err;
  EXPECT_TRUE(test::readFile(replayed) == test::readFile(video));  // (no dump of the bytes)
}

TEST(VideoCli, NeverOverwritesAFile) {
  test::TempDir dir;
  const std::string video = dir.write("taken.mp4", "precious");
  for (const std::string& args : {std::string("run sigmoid_untwist --duration 1 --video ") + video,
                                  "run sigmoid_untwist --duration 1 --frames " + dir.file("f") + " --video " + video}) {
    const Result r = test::runColosim(args, dir);
    EXPECT_EQ(r.code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(video + ": exists"), std::string::npos) << r.err;
    EXPECT_EQ(test::readFile(video), "precious");
    EXPECT_FALSE(fs::exists(dir.file("f")));  // checked before any output
  }
  const Result odd = test::runColosim("run sigmoid_untwist --duration 1 --size 97x64 --video " + dir.file("odd.mp4"), dir);
  EXPECT_EQ(odd.code, 2);
  EXPECT_NE(odd.err.find("even width and height"), std::string::npos) << odd.err;
  EXPECT_FALSE(fs::exists(dir.file("odd.mp4")));
}

}  // namespace
}  // namespace colosim
