// Video files through FFmpeg's libraries (Debian's libavcodec/libavformat/libswscale):
// frames of a run or replay encoded as H.264 (libx264) in MP4, and read back.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/image.h"

namespace colosim {

struct VideoOptions {
  double fps = 30;        ///< frames per second of playback [1/s]
  int crf = 18;           ///< x264 constant rate factor: 0 lossless, 18 visually lossless, 51 worst
  std::string preset = "fast";  ///< x264 speed/size preset
};

/// Encodes RGBA images of one size into a new video file. The container is chosen from the
/// file name (.mp4, .mkv, ...); the codec is libx264 (yuv420p), or MPEG-4 part 2 when
/// libavcodec has no libx264. The encoder runs on one thread with FFmpeg's bit-exact flags,
/// so the same frames give the same bytes on every machine.
class VideoEncoder {
 public:
  /// Creates `path`, which must not exist (std::runtime_error naming it otherwise: a video
  /// never overwrites a file), for width x height images (both even, >= 16).
  VideoEncoder(const std::string& path, int width_px, int height_px, const VideoOptions& options = {});
  /// Without finish(): closes what it can and removes the incomplete file it created.
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  /// Adds the next frame (the size given at construction; std::runtime_error otherwise).
  void add(const Image& image);
  /// Flushes the encoder and writes the file's index. Frames added: frames().
  void finish();
  long frames() const { return frames_; }
  /// The encoder's name ("libx264" or "mpeg4").
  const std::string& codec() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  long frames_ = 0;
};

/// Decodes every frame of a video file into RGBA images (tests, tools). std::runtime_error
/// naming the path when it cannot be opened or decoded.
std::vector<Image> readVideoFrames(const std::string& path);

}  // namespace colosim
