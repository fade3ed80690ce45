#include "video/mp4_reader.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}

#include "core/error.h"
#include "video/av_error_text.h"

namespace tissu {

struct Mp4Reader::State {
  std::string path;
  long long frames = 0;
  bool draining = false;  // the end of the file was reached; the decoder is being flushed

  AVFormatContext* format = nullptr;
  AVCodecContext* decoder = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  int stream_index = -1;

  SwsContext* to_rgb = nullptr;  // for the size and pixel format below
  int rgb_width = 0, rgb_height = 0, rgb_source_format = -1;

  ~State() {
    sws_freeContext(to_rgb);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&decoder);
    avformat_close_input(&format);
  }

  [[noreturn]] void fail(const std::string& problem, int code) const {
    throw InputError(path + ": " + problem + ": " + av_error_text(code));
  }

  void open();
  void to_image(Image& image);
};

void Mp4Reader::State::open() {
  // Decoders log concealed errors and the like on stderr; our errors are exceptions.
  if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_QUIET);
  packet = av_packet_alloc();
  frame = av_frame_alloc();
  if (!packet || !frame) fail("cannot read video", AVERROR(ENOMEM));
  int code = avformat_open_input(&format, path.c_str(), nullptr, nullptr);
  if (code < 0) fail("cannot open video", code);
  code = avformat_find_stream_info(format, nullptr);
  if (code < 0) fail("not a readable video", code);
  const AVCodec* codec = nullptr;
  stream_index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
  if (stream_index < 0) fail("no video stream", stream_index);
  decoder = avcodec_alloc_context3(codec);
  if (!decoder) fail("cannot decode video", AVERROR(ENOMEM));
  code = avcodec_parameters_to_context(decoder, format->streams[stream_index]->codecpar);
  if (code >= 0) code = avcodec_open2(decoder, codec, nullptr);
  if (code < 0) fail(std::string("cannot decode ") + avcodec_get_name(codec->id) + " video", code);
}

void Mp4Reader::State::to_image(Image& image) {
  if (!to_rgb || frame->width != rgb_width || frame->height != rgb_height ||
      frame->format != rgb_source_format) {
    sws_freeContext(to_rgb);
    to_rgb = sws_getContext(frame->width, frame->height, AVPixelFormat(frame->format), frame->width,
                            frame->height, AV_PIX_FMT_RGB24,
                            SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr,
                            nullptr);
    if (!to_rgb) fail("cannot convert frame " + std::to_string(frames) + " to RGB", AVERROR(EINVAL));
    rgb_width = frame->width;
    rgb_height = frame->height;
    rgb_source_format = frame->format;
    const int* coefficients =
        sws_getCoefficients(frame->colorspace == AVCOL_SPC_BT709 ? SWS_CS_ITU709 : SWS_CS_DEFAULT);
    sws_setColorspaceDetails(to_rgb, coefficients, frame->color_range == AVCOL_RANGE_JPEG,
                             coefficients, 1, 0, 1 << 16, 1 << 16);
  }
  image = Image(frame->width, frame->height);
  std::uint8_t* target[1] = {image.rgb.data()};
  const int stride[1] = {frame->width * 3};
  sws_scale(to_rgb, frame->data, frame->linesize, 0, frame->height, target, stride);
}

Mp4Reader::Mp4Reader(std::string path) : state_(std::make_unique<State>()) {
  state_->path = std::move(path);
  state_->open();
}

Mp4Reader::~Mp4Reader() = default;
Mp4Reader::Mp4Reader(Mp4Reader&&) noexcept = default;
Mp4Reader& Mp4Reader::operator=(Mp4Reader&&) noexcept = default;

bool Mp4Reader::read_frame(Image& image) {
  State& s = *state_;
  for (;;) {
    int code = avcodec_receive_frame(s.decoder, s.frame);
    if (code == 0) {
      s.to_image(image);
      av_frame_unref(s.frame);
      ++s.frames;
      return true;
    }
    if (code == AVERROR_EOF) return false;
    if (code != AVERROR(EAGAIN) || s.draining) {
      s.fail("cannot decode frame " + std::to_string(s.frames), code);
    }
    // The decoder needs the next packet of the video stream, or the end of the file.
    code = av_read_frame(s.format, s.packet);
    if (code == AVERROR_EOF) {
      s.draining = true;
      code = avcodec_send_packet(s.decoder, nullptr);
    } else if (code < 0) {
      s.fail("cannot read frame " + std::to_string(s.frames), code);
    } else if (s.packet->stream_index == s.stream_index) {
      code = avcodec_send_packet(s.decoder, s.packet);
      av_packet_unref(s.packet);
    } else {
      av_packet_unref(s.packet);
      continue;
    }
    if (code < 0) s.fail("cannot decode frame " + std::to_string(s.frames), code);
  }
}

const std::string& Mp4Reader::path() const { return state_->path; }
long long Mp4Reader::frames_read() const { return state_->frames; }

}  // namespace tissu
