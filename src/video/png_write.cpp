// Writing PNG files: each row filtered with PNG's "up" filter, the whole image deflated at
// once by ISA-L's igzip (level 1, a zlib stream), and the chunks written around it. igzip
// deflates a 720p frame about eight times faster than zlib's level 1, to files of the same
// size (docs/performance.md, "PNG frames with ISA-L's igzip").
#include "video/png_io.h"

#include <isa-l/igzip_lib.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "core/partial_file.h"

namespace tissu {
namespace {

constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::uint8_t kFilterUp = 2;

// Reused by the frames a thread writes (the encoder thread writes them all).
struct PngScratch {
  std::vector<std::uint8_t> filtered, deflated, level_buffer;
};

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift : {24, 16, 8, 0}) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

// Appends a chunk: length, type, data, CRC of type and data.
void put_chunk(std::vector<std::uint8_t>& out, const char (&type)[5], const std::uint8_t* data,
               std::size_t size) {
  put_u32(out, static_cast<std::uint32_t>(size));
  const std::size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  const uLong crc = crc32(0L, out.data() + type_at, static_cast<uInt>(4 + size));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

// Each row as a filter byte (up) and its differences from the row above (the first row:
// from zeros, so itself).
void filter_rows(const std::uint8_t* rgb, int width, int height, std::vector<std::uint8_t>& out) {
  const std::size_t row = std::size_t(width) * 3;
  out.resize((row + 1) * std::size_t(height));
  for (int y = 0; y < height; ++y) {
    std::uint8_t* to = &out[(row + 1) * std::size_t(y)];
    const std::uint8_t* cur = rgb + row * std::size_t(y);
    to[0] = kFilterUp;
    if (y == 0) {
      std::copy(cur, cur + row, to + 1);
    } else {
      const std::uint8_t* up = cur - row;
      for (std::size_t x = 0; x < row; ++x) to[1 + x] = static_cast<std::uint8_t>(cur[x] - up[x]);
    }
  }
}

}  // namespace

std::vector<std::uint8_t> encode_png(const std::uint8_t* rgb, int width, int height) {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("PNG size must be positive, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  }
  thread_local PngScratch scratch;
  filter_rows(rgb, width, height, scratch.filtered);
  const std::size_t in = scratch.filtered.size();
  if (in > std::numeric_limits<std::uint32_t>::max() / 2) {
    throw std::invalid_argument("PNG of " + std::to_string(width) + "x" + std::to_string(height) +
                                " is too large to write");
  }
  // Room for the stored blocks igzip falls back to on data it cannot shrink.
  const std::size_t room = in + in / 64 + 1024;
  std::vector<std::uint8_t>& deflated = scratch.deflated;
  if (deflated.size() < room) deflated.resize(room);
  scratch.level_buffer.resize(ISAL_DEF_LVL1_DEFAULT);
  isal_zstream stream;
  isal_deflate_stateless_init(&stream);
  stream.level = 1;
  stream.level_buf = scratch.level_buffer.data();
  stream.level_buf_size = static_cast<std::uint32_t>(scratch.level_buffer.size());
  stream.gzip_flag = IGZIP_ZLIB;
  stream.end_of_stream = 1;
  stream.flush = NO_FLUSH;
  stream.next_in = scratch.filtered.data();
  stream.avail_in = static_cast<std::uint32_t>(in);
  stream.next_out = deflated.data();
  stream.avail_out = static_cast<std::uint32_t>(room);
  const int status = isal_deflate_stateless(&stream);
  if (status != COMP_OK) {
    throw std::runtime_error("PNG compression failed (igzip status " + std::to_string(status) + ")");
  }
  std::vector<std::uint8_t> png;
  png.reserve(stream.total_out + 64);
  png.insert(png.end(), kSignature, kSignature + 8);
  std::vector<std::uint8_t> header;
  put_u32(header, static_cast<std::uint32_t>(width));
  put_u32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, filters, no interlace
  put_chunk(png, "IHDR", header.data(), header.size());
  put_chunk(png, "IDAT", deflated.data(), stream.total_out);
  put_chunk(png, "IEND", nullptr, 0);
  return png;
}

void write_png(const std::string& path, const std::uint8_t* rgb, int width, int height) {
  std::vector<std::uint8_t> png;
  try {
    png = encode_png(rgb, width, height);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  } catch (const std::runtime_error& e) {
    throw OutputError(path + ": cannot write PNG: " + e.what());
  }
  const std::string partial_path = partial_path_for(path);
  std::FILE* file = std::fopen(partial_path.c_str(), "wb");
  if (!file) throw OutputError(path + ": cannot create PNG: " + errno_text(errno));
  const bool written = std::fwrite(png.data(), 1, png.size(), file) == png.size();
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    const int error = !written ? write_errno : errno;
    discard_partial_file(partial_path);
    throw OutputError(path + ": cannot write PNG: " + errno_text(error));
  }
  commit_partial_file(partial_path, path);
}

void write_png(const std::string& path, const Image& image) {
  if (image.rgb.size() != image.byte_size()) {
    throw std::invalid_argument(path + ": image pixel buffer does not match its width and height");
  }
  write_png(path, image.rgb.data(), image.width, image.height);
}

}  // namespace tissu
