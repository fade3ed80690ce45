#include "render/gl/offscreen_context.h"

// render/gl/gl.h first: it must define GL_GLEXT_PROTOTYPES before osmesa.h pulls in GL/gl.h.
#include "render/gl/gl.h"

#include <GL/osmesa.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "render/gl/gl_objects.h"
#include "render/gl/pass_timer.h"
#include "render/image/pixel_simd.h"
#include "render/render_error.h"

namespace tissu {

namespace {

constexpr int kMinMajor = 3, kMinMinor = 3;

std::string size_text(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// Environment variables that change which Mesa driver OSMesa uses, for error messages.
std::string driver_environment() {
  std::string text;
  for (const char* name : {"GALLIUM_DRIVER", "LIBGL_ALWAYS_SOFTWARE", "MESA_GL_VERSION_OVERRIDE"}) {
    if (const char* value = std::getenv(name)) {
      text += std::string(text.empty() ? "" : ", ") + name + "=" + value;
    }
  }
  return text.empty() ? "" : " (environment: " + text + ")";
}

// Called after a core-profile request failed: tells whether OSMesa works at all.
std::string why_no_core_context() {
  OSMesaContext probe = OSMesaCreateContextExt(OSMESA_RGBA, 0, 0, 0, nullptr);
  if (probe == nullptr) {
    return "OSMesa cannot create any OpenGL context" + driver_environment();
  }
  std::vector<unsigned char> pixel(4);
  std::string version = "unknown";
  if (OSMesaMakeCurrent(probe, pixel.data(), GL_UNSIGNED_BYTE, 1, 1)) {
    if (const GLubyte* v = glGetString(GL_VERSION)) version = reinterpret_cast<const char*>(v);
  }
  OSMesaDestroyContext(probe);
  return "this Mesa offers no OpenGL " + std::to_string(kMinMajor) + "." +
         std::to_string(kMinMinor) + " core profile; its default context is OpenGL " + version +
         driver_environment();
}

}  // namespace

struct OffscreenContext::Framebuffers {
  GlFramebuffer draw;     // where frames are drawn (multisampled when samples > 1)
  GlRenderbuffer draw_color, draw_depth;
  GlFramebuffer resolve;  // single-sample copy that is read back (== draw when samples == 1)
  GlRenderbuffer resolve_color;
};

OffscreenContext::OffscreenContext(int width, int height, int msaa)
    : width_(width), height_(height) {
  if (width < 1 || height < 1) {
    throw RenderError("offscreen context: invalid size " + size_text(width, height));
  }
  if (msaa != 1 && msaa != 2 && msaa != 4) {
    throw RenderError("offscreen context: msaa must be 1, 2 or 4, got " + std::to_string(msaa));
  }
  create_context();
  try {
    create_framebuffers(msaa);
  } catch (...) {
    fbo_.reset();
    OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
    throw;
  }
}

OffscreenContext::~OffscreenContext() {
  make_current();
  fbo_.reset();  // GL objects go while their context is current
  OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

void OffscreenContext::create_context() {
  const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA,
                            OSMESA_DEPTH_BITS, 0,  // depth lives in our own framebuffer
                            OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, kMinMajor,
                            OSMESA_CONTEXT_MINOR_VERSION, kMinMinor,
                            0};
  OSMesaContext context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (context == nullptr) {
    throw RenderError("offscreen context: OSMesaCreateContextAttribs failed: " +
                      why_no_core_context());
  }
  context_ = context;
  // OSMesa needs a client buffer to make the context current; frames go to FBOs instead.
  dummy_buffer_.assign(4, 0);
  if (!OSMesaMakeCurrent(context, dummy_buffer_.data(), GL_UNSIGNED_BYTE, 1, 1)) {
    OSMesaDestroyContext(context);
    throw RenderError("offscreen context: OSMesaMakeCurrent failed" + driver_environment());
  }
  GLint profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &gl_major_);
  glGetIntegerv(GL_MINOR_VERSION, &gl_minor_);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  core_profile_ = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  if (gl_major_ * 10 + gl_minor_ < kMinMajor * 10 + kMinMinor || !core_profile_) {
    const std::string version = gl_version();
    OSMesaDestroyContext(context);
    throw RenderError("offscreen context: got OpenGL " + version + ", need " +
                      std::to_string(kMinMajor) + "." + std::to_string(kMinMinor) +
                      " core profile" + driver_environment());
  }
}

void OffscreenContext::create_framebuffers(int msaa) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (width_ > max_size || height_ > max_size) {
    throw RenderError("offscreen context: " + size_text(width_, height_) +
                      " exceeds the largest renderbuffer, " + std::to_string(max_size));
  }
  fbo_ = std::make_unique<Framebuffers>();
  Framebuffers& f = *fbo_;

  auto attach = [&](GlRenderbuffer& rb, GLenum format, GLenum attachment, int samples) {
    rb = make_renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, rb.get());
    if (samples > 1) {
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width_, height_);
    } else {
      glRenderbufferStorage(GL_RENDERBUFFER, format, width_, height_);
    }
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb.get());
  };
  auto require_complete = [&](const char* which) {
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      char code[16];
      std::snprintf(code, sizeof code, "0x%04X", status);
      throw RenderError(std::string("offscreen context: ") + which +
                        " framebuffer incomplete, status " + code);
    }
  };

  f.draw = make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, f.draw.get());
  attach(f.draw_color, GL_RGBA8, GL_COLOR_ATTACHMENT0, msaa);
  attach(f.draw_depth, GL_DEPTH_COMPONENT24, GL_DEPTH_ATTACHMENT, msaa);
  require_complete("draw");
  GLint granted = 1;
  glBindRenderbuffer(GL_RENDERBUFFER, f.draw_color.get());
  glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_SAMPLES, &granted);
  samples_ = granted > 1 ? granted : 1;

  if (samples_ > 1) {
    f.resolve = make_framebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, f.resolve.get());
    attach(f.resolve_color, GL_RGBA8, GL_COLOR_ATTACHMENT0, 1);
    require_complete("resolve");
  }
  check_gl("offscreen context: creating framebuffers");
  bind_draw_target();
}

void OffscreenContext::make_current() {
  OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), dummy_buffer_.data(), GL_UNSIGNED_BYTE,
                    1, 1);
}

void OffscreenContext::bind_draw_target() {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_->draw.get());
  glViewport(0, 0, width_, height_);
}

void OffscreenContext::read_rgb(std::vector<uint8_t>& out, PassTimer* timer) {
  const GLuint source = samples_ > 1 ? fbo_->resolve.get() : fbo_->draw.get();
  if (samples_ > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_->draw.get());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_->resolve.get());
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    if (timer) timer->lap("MSAA resolve");
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  // RGBA is the framebuffer's own layout (a straight copy in Mesa); RGB would take a
  // slow per-pixel conversion path, so the alpha byte is dropped here instead.
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  const size_t width = static_cast<size_t>(width_);
  rgba_.resize(width * height_ * 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data());
  check_gl("offscreen context: reading pixels");
  if (timer) timer->lap("glReadPixels");
  // GL's first row is the bottom one; images are stored top row first.
  out.resize(width * height_ * 3);
  for (int y = 0; y < height_; ++y) {
    const uint8_t* from = rgba_.data() + width * 4 * (height_ - 1 - y);
    rgba_to_rgb(from, out.data() + width * 3 * y, width);
  }
  if (timer) timer->lap("RGBA to RGB, flip (CPU)");
  bind_draw_target();
}

std::string OffscreenContext::gl_version() const {
  const GLubyte* v = glGetString(GL_VERSION);
  return v ? reinterpret_cast<const char*>(v) : "unknown";
}

std::string OffscreenContext::gl_renderer() const {
  const GLubyte* v = glGetString(GL_RENDERER);
  return v ? reinterpret_cast<const char*>(v) : "unknown";
}

}  // namespace tissu
