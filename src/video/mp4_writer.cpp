#include "video/mp4_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/cpu.h>
#include <libavutil/error.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libavutil/rational.h>
}

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "core/partial_file.h"
#include "video/av_error_text.h"
#include "video/yuv420.h"

namespace tissu {
namespace {

// libx264 and the muxer log every file's settings and statistics at the info level, which
// would break the progress bar on stderr; keep errors only, unless a caller asked for more.
void quiet_libav_logging() {
  if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_ERROR);
}

}  // namespace

FrameRate::FrameRate(double fps) : num(0), den(1) {
  if (std::isfinite(fps) && fps > 0) {
    const AVRational q = av_d2q(fps, 100000);
    num = q.num;
    den = q.den;
  }
}

struct Mp4Writer::State {
  std::string path;
  std::string partial_path;
  int width = 0, height = 0;              // of the input frames
  int video_width = 0, video_height = 0;  // even
  long long frames = 0;
  bool open = false;

  AVFormatContext* format = nullptr;
  AVStream* stream = nullptr;  // owned by `format`
  AVCodecContext* codec = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  std::vector<std::uint8_t> padded;  // odd-sized input copied to even size

  ~State() { release(); }

  // Closes, removes the temporary file and throws "<path>: <problem>".
  [[noreturn]] void fail(const std::string& problem) {
    release();
    discard_partial_file(partial_path);
    throw OutputError(path + ": " + problem);
  }

  [[noreturn]] void fail(const std::string& what, int code) { fail(what + ": " + av_error_text(code)); }

  void check(int code, const char* what) {
    if (code < 0) fail(what, code);
  }

  // Frees every libav object; closes the temporary file without checking (used on failure).
  void release() noexcept {
    open = false;
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&codec);
    if (format) {
      if (format->pb) avio_closep(&format->pb);
      avformat_free_context(format);
      format = nullptr;
      stream = nullptr;
    }
  }

  void open_file(FrameRate fps, const Mp4Options& options);
  void open_encoder(FrameRate fps, const Mp4Options& options);
  const std::uint8_t* even_sized(const std::uint8_t* rgb);
  void encode(AVFrame* input);
};

void Mp4Writer::State::open_encoder(FrameRate fps, const Mp4Options& options) {
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
  if (!encoder) fail("cannot encode H.264", AVERROR_ENCODER_NOT_FOUND);
  codec = avcodec_alloc_context3(encoder);
  if (!codec) fail("cannot encode H.264", AVERROR(ENOMEM));
  codec->width = video_width;
  codec->height = video_height;
  codec->pix_fmt = AV_PIX_FMT_YUV420P;
  codec->time_base = AVRational{fps.den, fps.num};  // one tick per frame
  codec->framerate = AVRational{fps.num, fps.den};
  codec->gop_size = std::max(1, int(std::lround(options.keyframe_interval_s * fps.value())));
  codec->thread_count = std::max(1, options.encoder_threads);
  // Rendered RGB is converted with BT.709 coefficients to limited range (video/yuv420.h); say
  // so in the stream.
  codec->color_range = AVCOL_RANGE_MPEG;
  codec->colorspace = AVCOL_SPC_BT709;
  codec->color_primaries = AVCOL_PRI_BT709;
  codec->color_trc = AVCOL_TRC_BT709;
  if (format->oformat->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

  AVDictionary* settings = nullptr;
  // x264's AVX-512 routines read memory they never wrote: with them the same frames gave
  // different bytes from run to run (seen with glibc's M_PERTURB). Every processor with
  // AVX-512 has AVX2, so x264 is limited to AVX2 there.
  const bool avx512 = av_get_cpu_flags() & AV_CPU_FLAG_AVX512;
  std::string x264_params = options.x264_params;
  if (avx512) x264_params += std::string(x264_params.empty() ? "" : ":") + "asm=AVX2";
  if (av_dict_set(&settings, "preset", options.preset.c_str(), 0) < 0 ||
      av_dict_set(&settings, "crf", std::to_string(options.crf).c_str(), 0) < 0 ||
      (!options.tune.empty() && av_dict_set(&settings, "tune", options.tune.c_str(), 0) < 0) ||
      (!x264_params.empty() && av_dict_set(&settings, "x264-params", x264_params.c_str(), 0) < 0)) {
    av_dict_free(&settings);
    fail("cannot start the H.264 encoder", AVERROR(ENOMEM));
  }
  const int opened = avcodec_open2(codec, encoder, &settings);
  const bool all_used = av_dict_count(settings) == 0;
  av_dict_free(&settings);
  check(opened, "cannot start the H.264 encoder");
  if (!all_used) fail("cannot start the H.264 encoder", AVERROR_OPTION_NOT_FOUND);

  check(avcodec_parameters_from_context(stream->codecpar, codec), "cannot set up the video stream");
  stream->time_base = codec->time_base;  // a hint; the muxer picks its own
  stream->avg_frame_rate = codec->framerate;
  stream->r_frame_rate = codec->framerate;

  frame = av_frame_alloc();
  packet = av_packet_alloc();
  if (!frame || !packet) fail("cannot allocate a video frame", AVERROR(ENOMEM));
  frame->format = AV_PIX_FMT_YUV420P;
  frame->width = video_width;
  frame->height = video_height;
  frame->color_range = codec->color_range;
  frame->colorspace = codec->colorspace;
  check(av_frame_get_buffer(frame, 0), "cannot allocate a video frame");
}

void Mp4Writer::State::open_file(FrameRate fps, const Mp4Options& options) {
  // "file:" keeps a ':' in the path from being read as a protocol name.
  const std::string url = "file:" + partial_path;
  check(avformat_alloc_output_context2(&format, nullptr, "mp4", url.c_str()), "cannot set up MP4 output");
  stream = avformat_new_stream(format, nullptr);
  if (!stream) fail("cannot set up MP4 output", AVERROR(ENOMEM));
  open_encoder(fps, options);

  check(avio_open(&format->pb, url.c_str(), AVIO_FLAG_WRITE), "cannot create video file");
  AVDictionary* muxer_settings = nullptr;
  // The index ('moov') goes before the samples, so browsers start playing while loading.
  check(av_dict_set(&muxer_settings, "movflags", "+faststart", 0), "cannot set up MP4 output");
  const int written = avformat_write_header(format, &muxer_settings);
  av_dict_free(&muxer_settings);
  check(written, "cannot write MP4 header");
  check(format->pb->error, "cannot write MP4 header");
  open = true;
}

const std::uint8_t* Mp4Writer::State::even_sized(const std::uint8_t* rgb) {
  if (video_width == width && video_height == height) return rgb;
  const std::size_t in_row = std::size_t(width) * 3, out_row = std::size_t(video_width) * 3;
  padded.resize(out_row * video_height);
  for (int y = 0; y < video_height; ++y) {
    const std::uint8_t* source = rgb + std::size_t(std::min(y, height - 1)) * in_row;
    std::uint8_t* target = padded.data() + std::size_t(y) * out_row;
    std::memcpy(target, source, in_row);
    if (video_width != width) std::memcpy(target + in_row, source + in_row - 3, 3);
  }
  return padded.data();
}

// Sends one frame (or nullptr to flush) and writes every packet the encoder has ready.
void Mp4Writer::State::encode(AVFrame* input) {
  check(avcodec_send_frame(codec, input), "cannot encode frame");
  for (;;) {
    const int received = avcodec_receive_packet(codec, packet);
    if (received == AVERROR(EAGAIN) || received == AVERROR_EOF) return;
    check(received, "cannot encode frame");
    packet->duration = 1;  // one frame, in codec ticks; sets the last frame's length too
    av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
    packet->stream_index = stream->index;
    check(av_interleaved_write_frame(format, packet), "cannot write video");
    check(format->pb->error, "cannot write video");
  }
}

Mp4Writer::Mp4Writer(std::string path, int width, int height, FrameRate fps, const Mp4Options& options)
    : state_(std::make_unique<State>()) {
  if (width <= 0 || height <= 0) {
    throw InputError(path + ": video size must be positive, got " + std::to_string(width) + "x" +
                     std::to_string(height));
  }
  if (fps.num <= 0 || fps.den <= 0) {
    throw InputError(path + ": frame rate must be positive, got " + std::to_string(fps.num) + "/" +
                     std::to_string(fps.den));
  }
  quiet_libav_logging();
  State& s = *state_;
  s.path = std::move(path);
  s.partial_path = partial_path_for(s.path);
  s.width = width;
  s.height = height;
  s.video_width = width + (width & 1);
  s.video_height = height + (height & 1);
  try {
    s.open_file(fps, options);
  } catch (...) {  // OutputError has cleaned up already; std::bad_alloc has not
    s.release();
    discard_partial_file(s.partial_path);
    throw;
  }
}

Mp4Writer::~Mp4Writer() { abort(); }
Mp4Writer::Mp4Writer(Mp4Writer&&) noexcept = default;

Mp4Writer& Mp4Writer::operator=(Mp4Writer&& other) noexcept {
  if (this != &other) {
    abort();
    state_ = std::move(other.state_);
  }
  return *this;
}

void Mp4Writer::write_frame(const std::uint8_t* rgb) {
  if (!is_open()) throw std::logic_error("Mp4Writer::write_frame: the writer is closed");
  State& s = *state_;
  s.check(av_frame_make_writable(s.frame), "cannot encode frame");
  const std::uint8_t* source = s.even_sized(rgb);
  rgb_to_yuv420(source, s.video_width * 3, s.video_width, s.video_height, s.frame->data[0], s.frame->linesize[0],
                s.frame->data[1], s.frame->linesize[1], s.frame->data[2], s.frame->linesize[2]);
  s.frame->pts = s.frames;
  s.encode(s.frame);
  ++s.frames;
}

void Mp4Writer::write_frame(const Image& frame) {
  if (!state_) throw std::logic_error("Mp4Writer::write_frame: the writer is closed");
  if (frame.width != state_->width || frame.height != state_->height ||
      frame.rgb.size() != frame.byte_size()) {
    throw std::invalid_argument(state_->path + ": frame is " + std::to_string(frame.width) + "x" +
                                std::to_string(frame.height) + ", the video is " +
                                std::to_string(state_->width) + "x" + std::to_string(state_->height));
  }
  write_frame(frame.rgb.data());
}

void Mp4Writer::finish() {
  if (!is_open()) throw std::logic_error("Mp4Writer::finish: the writer is closed");
  State& s = *state_;
  if (s.frames == 0) s.fail("no frames to write");  // players reject an empty MP4
  s.encode(nullptr);
  s.check(av_write_trailer(s.format), "cannot complete MP4");
  avio_flush(s.format->pb);  // av_write_trailer flushes too, but avio_closep ignores write errors
  s.check(s.format->pb->error, "cannot complete MP4");
  s.check(avio_closep(&s.format->pb), "cannot complete MP4");
  s.release();
  try {
    sync_file_to_disk(s.partial_path, s.path);
    commit_partial_file(s.partial_path, s.path);
  } catch (...) {
    discard_partial_file(s.partial_path);
    throw;
  }
}

void Mp4Writer::abort() noexcept {
  if (!is_open()) return;
  state_->release();
  discard_partial_file(state_->partial_path);
}

const std::string& Mp4Writer::path() const { return state_->path; }
int Mp4Writer::width() const { return state_->width; }
int Mp4Writer::height() const { return state_->height; }
int Mp4Writer::video_width() const { return state_->video_width; }
int Mp4Writer::video_height() const { return state_->video_height; }
long long Mp4Writer::frames_written() const { return state_->frames; }
bool Mp4Writer::is_open() const { return state_ && state_->open; }

}  // namespace tissu
