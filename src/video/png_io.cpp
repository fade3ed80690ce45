// Reading PNG files with libpng (writing: png_write.cpp). libpng reports errors by longjmp
// to a setjmp point. A longjmp must not skip C++ frames
// that own objects with destructors, so every libpng call runs inside the plain functions
// below whose frames hold only pointers and integers; the C++ wrappers own the cleanup
// and turn the recorded error text into exceptions.
#include "video/png_io.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "core/error.h"
#include "core/partial_file.h"  // errno_text

namespace tissu {
namespace {

// Larger sides are rejected when reading, so a corrupt header cannot demand terabytes.
constexpr png_uint_32 kMaxPngSide = 1u << 15;

// Shared by the libpng callbacks: what went wrong.
struct PngContext {
  char message[256] = "";
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* context = static_cast<PngContext*>(png_get_error_ptr(png));
  if (context->message[0] == '\0') std::snprintf(context->message, sizeof context->message, "%s", message);
  longjmp(png_jmpbuf(png), 1);
}

void on_png_warning(png_structp, png_const_charp) {}

bool decode_png_header(png_structp png, png_infop info, png_uint_32* width, png_uint_32* height,
                       int* passes) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_user_limits(png, kMaxPngSide, kMaxPngSide);
  png_read_info(png, info);
  png_set_expand(png);  // palette and low-bit gray to 8 bits, tRNS to alpha
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  *passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  *width = png_get_image_width(png, info);
  *height = png_get_image_height(png, info);
  if (png_get_rowbytes(png, info) != std::size_t(*width) * 3) png_error(png, "unsupported pixel layout");
  return true;
}

bool decode_png_rows(png_structp png, png_infop info, std::uint8_t* rgb, png_uint_32 width,
                     png_uint_32 height, int passes) {
  if (setjmp(png_jmpbuf(png))) return false;
  for (int pass = 0; pass < passes; ++pass) {
    for (png_uint_32 y = 0; y < height; ++y) png_read_row(png, rgb + std::size_t(y) * width * 3, nullptr);
  }
  png_read_end(png, info);
  return true;
}

struct PngReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngReadStructs() { png_destroy_read_struct(&png, &info, nullptr); }
};

struct FileCloser {
  std::FILE* file = nullptr;
  ~FileCloser() {
    if (file) std::fclose(file);
  }
};

}  // namespace

Image read_png(const std::string& path) {
  FileCloser closer{std::fopen(path.c_str(), "rb")};
  if (!closer.file) throw InputError(path + ": cannot open PNG: " + errno_text(errno));

  PngContext context;
  PngReadStructs structs;
  structs.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &context, on_png_error, on_png_warning);
  if (structs.png) structs.info = png_create_info_struct(structs.png);
  if (!structs.png || !structs.info) throw InputError(path + ": cannot read PNG: out of memory");
  png_init_io(structs.png, closer.file);

  png_uint_32 width = 0, height = 0;
  int passes = 1;
  if (!decode_png_header(structs.png, structs.info, &width, &height, &passes)) {
    throw InputError(path + ": not a readable PNG: " + context.message);
  }
  Image image(static_cast<int>(width), static_cast<int>(height));
  if (!decode_png_rows(structs.png, structs.info, image.rgb.data(), width, height, passes)) {
    throw InputError(path + ": not a readable PNG: " + context.message);
  }
  return image;
}

}  // namespace tissu
