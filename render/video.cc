#include "render/video.h"

#include <cstring>
#include <vector>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace colosim {

namespace {

// FFmpeg and x264 report every encode on stderr at their default level: errors only.
void quietLibav() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_ERROR); });
}

std::string avError(int code) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
  av_strerror(code, buf, sizeof buf);
  return buf;
}

}  // namespace

struct VideoEncoder::Impl {
  std::string path;
  bool created = false;   // the file is ours: removed when the encoder ends unfinished
  bool finished = false;
  int width = 0, height = 0;
  std::string codec_name;
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* sws = nullptr;
  /// The frame's RGBA copied into rows padded to 64 bytes, with a zeroed row before and
  /// after: the converter's vector code may read a little beyond a row or the image.
  std::vector<uint8_t> rgba;
  int rgba_stride = 0;

  [[noreturn]] void fail(const std::string& what, int code = 0) const {
    throw std::runtime_error(path + ": " + what + (code ? " (" + avError(code) + ")" : std::string()));
  }

  // Sends one frame (nullptr: flush) and writes every packet the encoder gives back.
  void encode(const AVFrame* f) {
    int rc = avcodec_send_frame(codec, f);
    if (rc < 0) fail("the encoder refused a frame", rc);
    for (;;) {
      rc = avcodec_receive_packet(codec, packet);
      if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return;
      if (rc < 0) fail("encoding failed", rc);
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      rc = av_interleaved_write_frame(format, packet);  // takes the packet's data
      if (rc < 0) fail("cannot write to the file", rc);
    }
  }

  ~Impl() {
    sws_freeContext(sws);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format) {
      if (format->pb) avio_closep(&format->pb);
      avformat_free_context(format);
    }
    if (created && !finished) std::remove(path.c_str());
  }
};

VideoEncoder::VideoEncoder(const std::string& path, int width_px, int height_px, const VideoOptions& o)
    : impl_(std::make_unique<Impl>()) {
  quietLibav();
  Impl& v = *impl_;
  v.path = path;
  v.width = width_px;
  v.height = height_px;
  if (width_px < 16 || height_px < 16 || width_px % 2 || height_px % 2)
    v.fail("a video needs an even width and height of at least 16 px, got " + std::to_string(width_px) + "x" +
           std::to_string(height_px));
  if (!(o.fps > 0)) v.fail("the frame rate must be positive");
  // Claim the name first (O_EXCL): an existing file is never touched, not even truncated.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) v.fail("exists (a video never overwrites a file)");
    v.fail("cannot create the file");
  }
  ::close(fd);
  v.created = true;

  int rc = avformat_alloc_output_context2(&v.format, nullptr, nullptr, path.c_str());
  if (rc < 0 || !v.format) v.fail("no video container for this file name (use .mp4)", rc);
  v.format->flags |= AVFMT_FLAG_BITEXACT;  // no version strings or times in the file: same bytes every run
  const AVCodec* enc = avcodec_find_encoder_by_name("libx264");
  if (!enc) enc = avcodec_find_encoder(AV_CODEC_ID_MPEG4);
  if (!enc) v.fail("libavcodec has neither libx264 nor an MPEG-4 encoder");
  v.codec_name = enc->name;
  v.codec = avcodec_alloc_context3(enc);
  v.stream = avformat_new_stream(v.format, nullptr);
  v.frame = av_frame_alloc();
  v.packet = av_packet_alloc();
  if (!v.codec || !v.stream || !v.frame || !v.packet) v.fail("out of memory");

  const AVRational rate = av_d2q(o.fps, 100000);
  v.codec->width = width_px;
  v.codec->height = height_px;
  v.codec->pix_fmt = AV_PIX_FMT_YUV420P;
  v.codec->time_base = av_inv_q(rate);
  v.codec->framerate = rate;
  v.codec->gop_size = 30;
  v.codec->thread_count = 1;  // x264's output depends on its thread count
  v.codec->flags |= AV_CODEC_FLAG_BITEXACT;
  if (v.format->oformat->flags & AVFMT_GLOBALHEADER) v.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  if (v.codec_name == "libx264") {
    av_opt_set(v.codec->priv_data, "preset", o.preset.c_str(), 0);
    av_opt_set(v.codec->priv_data, "crf", std::to_string(o.crf).c_str(), 0);
#if defined(__x86_64__) || defined(__i386__)
    // x264 0.164's AVX-512 code reads heap it never wrote: on an AVX-512 machine (AMD EPYC
    // Zen 4 here) the same frames gave other bytes whenever malloc handed back used memory
    // (MALLOC_PERTURB_ changed the file; asm=AVX2 never did). Its AVX2 code gives the bytes
    // the AVX-512 code gives on fresh memory. Every AVX-512 processor has AVX2, FMA3 and BMI2.
    if (__builtin_cpu_supports("avx512f")) av_opt_set(v.codec->priv_data, "x264-params", "asm=AVX2", 0);
#endif
  } else {
    v.codec->bit_rate = 0;
    v.codec->global_quality = FF_QP2LAMBDA * 3;  // MPEG-4: fixed quantiser 3 (near-transparent)
    v.codec->flags |= AV_CODEC_FLAG_QSCALE;
  }
  rc = avcodec_open2(v.codec, enc, nullptr);
  if (rc < 0) v.fail("cannot open the " + v.codec_name + " encoder", rc);
  rc = avcodec_parameters_from_context(v.stream->codecpar, v.codec);
  if (rc < 0) v.fail("cannot set the stream parameters", rc);
  v.stream->time_base = v.codec->time_base;
  v.stream->avg_frame_rate = rate;

  v.frame->format = AV_PIX_FMT_YUV420P;
  v.frame->width = width_px;
  v.frame->height = height_px;
  rc = av_frame_get_buffer(v.frame, 0);
  if (rc < 0) v.fail("cannot allocate a frame", rc);
  // The planes' padding beyond the width is never written by the conversion: zeroed so
  // that nothing the encoder may read there differs from run to run.
  for (int p = 0; p < 3; ++p)
    std::memset(v.frame->data[p], 0, static_cast<size_t>(v.frame->linesize[p]) * (p == 0 ? height_px : (height_px + 1) / 2));
  v.sws = sws_getContext(width_px, height_px, AV_PIX_FMT_RGBA, width_px, height_px, AV_PIX_FMT_YUV420P,
                         SWS_BICUBIC | SWS_ACCURATE_RND | SWS_BITEXACT, nullptr, nullptr, nullptr);
  if (!v.sws) v.fail("cannot convert RGBA to YUV");
  v.rgba_stride = (4 * width_px + 63) / 64 * 64;
  v.rgba.assign(static_cast<size_t>(v.rgba_stride) * (height_px + 2), 0);

  rc = avio_open(&v.format->pb, path.c_str(), AVIO_FLAG_WRITE);
  if (rc < 0) v.fail("cannot open the file for writing", rc);
  rc = avformat_write_header(v.format, nullptr);
  if (rc < 0) v.fail("cannot write the video header", rc);
}

VideoEncoder::~VideoEncoder() = default;

const std::string& VideoEncoder::codec() const { return impl_->codec_name; }

void VideoEncoder::add(const Image& image) {
  Impl& v = *impl_;
  if (v.finished) v.fail("frame added after the video was finished");
  if (image.width != v.width || image.height != v.height)
    v.fail("frame of " + std::to_string(image.width) + "x" + std::to_string(image.height) + " px in a video of " +
           std::to_string(v.width) + "x" + std::to_string(v.height) + " px");
  int rc = av_frame_make_writable(v.frame);
  if (rc < 0) v.fail("cannot write the frame", rc);
  const size_t row = 4 * static_cast<size_t>(image.width);
  for (int y = 0; y < image.height; ++y)
    std::memcpy(v.rgba.data() + static_cast<size_t>(v.rgba_stride) * (y + 1), image.rgba.data() + row * y, row);
  const uint8_t* src[1] = {v.rgba.data() + v.rgba_stride};
  const int stride[1] = {v.rgba_stride};
  sws_scale(v.sws, src, stride, 0, image.height, v.frame->data, v.frame->linesize);
  v.frame->pts = frames_++;
  v.encode(v.frame);
}

void VideoEncoder::finish() {
  Impl& v = *impl_;
  if (v.finished) return;
  v.encode(nullptr);
  const int rc = av_write_trailer(v.format);
  if (rc < 0) v.fail("cannot finish the file", rc);
  avio_closep(&v.format->pb);
  v.finished = true;
}

std::vector<Image> readVideoFrames(const std::string& path) {
  quietLibav();
  auto fail = [&](const std::string& what, int code) -> void {
    throw std::runtime_error(path + ": " + what + (code < 0 ? " (" + avError(code) + ")" : std::string()));
  };
  AVFormatContext* format = nullptr;
  int rc = avformat_open_input(&format, path.c_str(), nullptr, nullptr);
  if (rc < 0) fail("cannot open the video", rc);
  std::unique_ptr<AVFormatContext, void (*)(AVFormatContext*)> format_guard(
      format, [](AVFormatContext* f) { avformat_close_input(&f); });
  rc = avformat_find_stream_info(format, nullptr);
  if (rc < 0) fail("cannot read the stream information", rc);
  const AVCodec* dec = nullptr;
  const int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, &dec, 0);
  if (index < 0 || !dec) fail("no video stream", index);
  std::unique_ptr<AVCodecContext, void (*)(AVCodecContext*)> codec(
      avcodec_alloc_context3(dec), [](AVCodecContext* c) { avcodec_free_context(&c); });
  avcodec_parameters_to_context(codec.get(), format->streams[index]->codecpar);
  codec->thread_count = 1;
  rc = avcodec_open2(codec.get(), dec, nullptr);
  if (rc < 0) fail("cannot open the decoder", rc);
  std::unique_ptr<AVFrame, void (*)(AVFrame*)> frame(av_frame_alloc(), [](AVFrame* f) { av_frame_free(&f); });
  std::unique_ptr<AVPacket, void (*)(AVPacket*)> packet(av_packet_alloc(), [](AVPacket* p) { av_packet_free(&p); });
  std::unique_ptr<SwsContext, void (*)(SwsContext*)> sws(nullptr, sws_freeContext);
  std::vector<Image> out;
  auto drain = [&] {
    for (;;) {
      const int r = avcodec_receive_frame(codec.get(), frame.get());
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      if (r < 0) fail("decoding failed", r);
      Image img(frame->width, frame->height);
      sws.reset(sws_getCachedContext(sws.release(), frame->width, frame->height, static_cast<AVPixelFormat>(frame->format),
                                 img.width, img.height, AV_PIX_FMT_RGBA,
                                 SWS_BICUBIC | SWS_ACCURATE_RND | SWS_BITEXACT, nullptr, nullptr, nullptr));
      if (!sws) fail("cannot convert the frames to RGBA", 0);
      uint8_t* dst[1] = {img.rgba.data()};
      const int stride[1] = {4 * img.width};
      sws_scale(sws.get(), frame->data, frame->linesize, 0, frame->height, dst, stride);
      out.push_back(std::move(img));
    }
  };
  while (av_read_frame(format, packet.get()) >= 0) {
    if (packet->stream_index == index) {
      rc = avcodec_send_packet(codec.get(), packet.get());
      if (rc < 0) {
        av_packet_unref(packet.get());
        fail("the decoder refused a packet", rc);
      }
      drain();
    }
    av_packet_unref(packet.get());
  }
  avcodec_send_packet(codec.get(), nullptr);
  drain();
  return out;
}

}  // namespace colosim
