#include "video_test_support.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

namespace tissu::test {

Image moving_gradient(int width, int height, int index) {
  Image image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = std::uint8_t((x + index * 4) * 255 / (width + 120) % 256);
      p[1] = std::uint8_t(y * 255 / std::max(1, height - 1));
      p[2] = std::uint8_t(255 - (x + y + index * 2) * 255 / (width + height + 60) % 256);
    }
  }
  return image;
}

Image noise_image(int width, int height, unsigned seed) {
  Image image(width, height);
  std::mt19937 random(seed);
  for (auto& byte : image.rgb) byte = std::uint8_t(random() >> 24);
  return image;
}

ScratchDir::ScratchDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "tissu-video-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a scratch directory");
  path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::permissions(path_, std::filesystem::perms::owner_all, ignored);
  std::filesystem::remove_all(path_, ignored);
}

std::vector<std::string> ScratchDir::entries() const {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(path_)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<std::string> top_level_boxes(const std::string& path) {
  const std::vector<char> bytes = file_bytes(path);
  auto read_be = [&](std::size_t at, int count) {
    std::uint64_t value = 0;
    for (int i = 0; i < count; ++i) value = value << 8 | std::uint8_t(bytes[at + i]);
    return value;
  };
  std::vector<std::string> boxes;
  std::size_t at = 0;
  while (at + 8 <= bytes.size()) {
    std::uint64_t size = read_be(at, 4);
    boxes.emplace_back(bytes.data() + at + 4, 4);
    if (size == 1 && at + 16 <= bytes.size()) size = read_be(at + 8, 8);  // 64-bit size
    if (size == 0) break;                                                 // to the end of the file
    if (size < 8) {
      ADD_FAILURE() << path << ": box " << boxes.back() << " has size " << size;
      break;
    }
    at += size;
  }
  return boxes;
}

namespace {

struct Demuxer {
  AVFormatContext* format = nullptr;
  AVCodecContext* decoder = nullptr;
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* to_rgb = nullptr;
  ~Demuxer() {
    sws_freeContext(to_rgb);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&decoder);
    avformat_close_input(&format);
  }
};

Image frame_to_rgb(Demuxer& d) {
  const AVFrame* f = d.frame;
  Image image(f->width, f->height);
  if (!d.to_rgb) {
    d.to_rgb =
        sws_getContext(f->width, f->height, AVPixelFormat(f->format), f->width, f->height, AV_PIX_FMT_RGB24,
                       SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr, nullptr);
    // Decode as the stream is tagged (BT.709, limited range), as a browser would.
    const int* coefficients =
        sws_getCoefficients(f->colorspace == AVCOL_SPC_BT709 ? SWS_CS_ITU709 : SWS_CS_DEFAULT);
    sws_setColorspaceDetails(d.to_rgb, coefficients, f->color_range == AVCOL_RANGE_JPEG, coefficients, 1, 0,
                             1 << 16, 1 << 16);
  }
  std::uint8_t* target[1] = {image.rgb.data()};
  const int stride[1] = {f->width * 3};
  sws_scale(d.to_rgb, f->data, f->linesize, 0, f->height, target, stride);
  return image;
}

void receive_frames(Demuxer& d, VideoFacts& facts) {
  while (avcodec_receive_frame(d.decoder, d.frame) == 0) {
    facts.frames.push_back(frame_to_rgb(d));
    av_frame_unref(d.frame);
  }
}

}  // namespace

VideoFacts read_video(const std::string& path) {
  VideoFacts facts;
  Demuxer d;
  if (avformat_open_input(&d.format, path.c_str(), nullptr, nullptr) < 0) {
    ADD_FAILURE() << path << ": libavformat cannot open it";
    return facts;
  }
  if (avformat_find_stream_info(d.format, nullptr) < 0 || d.format->nb_streams != 1) {
    ADD_FAILURE() << path << ": expected exactly one readable stream";
    return facts;
  }
  const AVStream* stream = d.format->streams[0];
  const AVCodecParameters* par = stream->codecpar;
  facts.codec = avcodec_get_name(par->codec_id);
  const char* pixel_format = av_get_pix_fmt_name(AVPixelFormat(par->format));
  facts.pixel_format = pixel_format ? pixel_format : "unknown";
  facts.width = par->width;
  facts.height = par->height;
  facts.fps_num = stream->avg_frame_rate.num;
  facts.fps_den = stream->avg_frame_rate.den;
  facts.frames_in_index = stream->nb_frames;

  const AVCodec* codec = avcodec_find_decoder(par->codec_id);
  d.decoder = codec ? avcodec_alloc_context3(codec) : nullptr;
  if (!d.decoder || avcodec_parameters_to_context(d.decoder, par) < 0 ||
      avcodec_open2(d.decoder, codec, nullptr) < 0) {
    ADD_FAILURE() << path << ": cannot open a decoder for " << facts.codec;
    return facts;
  }
  while (av_read_frame(d.format, d.packet) >= 0) {
    const int sent = avcodec_send_packet(d.decoder, d.packet);
    av_packet_unref(d.packet);
    if (sent < 0) {
      ADD_FAILURE() << path << ": decoding failed";
      return facts;
    }
    receive_frames(d, facts);
  }
  avcodec_send_packet(d.decoder, nullptr);
  receive_frames(d, facts);
  return facts;
}

}  // namespace tissu::test
