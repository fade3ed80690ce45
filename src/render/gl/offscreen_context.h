// A window-less OpenGL core-profile context (OSMesa, llvmpipe) with its own
// framebuffer: multisampled colour + depth renderbuffers, resolved into a
// single-sample framebuffer and read back as RGB8 rows from top to bottom.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tissu {

class PassTimer;

class OffscreenContext {
 public:
  // msaa: samples per pixel requested (1, 2 or 4). Throws RenderError with the
  // reason when OSMesa cannot give a 3.3+ core context or the framebuffer is incomplete.
  OffscreenContext(int width, int height, int msaa);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  // Makes this context current on the calling thread (needed when several exist).
  void make_current();
  // Binds the (multisampled) framebuffer that frames are drawn into, and sets the viewport.
  void bind_draw_target();
  // Resolves the samples and reads the image: width*height*3 bytes, first row at the top.
  // `timer`, when given, times the resolve, the read-back and the conversion.
  void read_rgb(std::vector<uint8_t>& out, PassTimer* timer = nullptr);

  int width() const { return width_; }
  int height() const { return height_; }
  // Samples per pixel the driver allocated (llvmpipe rounds a request of 2 up to 4).
  int samples() const { return samples_; }
  int gl_major() const { return gl_major_; }
  int gl_minor() const { return gl_minor_; }
  bool core_profile() const { return core_profile_; }
  std::string gl_version() const;   // GL_VERSION string
  std::string gl_renderer() const;  // GL_RENDERER string

 private:
  struct Framebuffers;
  void create_context();
  void create_framebuffers(int msaa);

  int width_, height_;
  int samples_ = 1;
  int gl_major_ = 0, gl_minor_ = 0;
  bool core_profile_ = false;
  void* context_ = nullptr;                 // OSMesaContext
  std::vector<unsigned char> dummy_buffer_;  // OSMesa's own colour buffer (unused; we draw to FBOs)
  std::unique_ptr<Framebuffers> fbo_;
  std::vector<uint8_t> rgba_;  // read-back buffer, reused
};

}  // namespace tissu
