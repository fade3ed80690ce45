// Move-only owners of OpenGL object names, deleted in the destructor.
// The GL context that created them must be current when they are destroyed.
#pragma once

#include <utility>

#include "render/gl/gl.h"

namespace tissu {

template <void (*Delete)(GLuint)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint name) : name_(name) {}
  ~GlName() { reset(); }
  GlName(GlName&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  GlName& operator=(GlName&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = std::exchange(other.name_, 0);
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;

  GLuint get() const { return name_; }
  void reset() {
    if (name_ != 0) Delete(name_);
    name_ = 0;
  }

 private:
  GLuint name_ = 0;
};

namespace gl_delete {
inline void buffer(GLuint n) { glDeleteBuffers(1, &n); }
inline void vertex_array(GLuint n) { glDeleteVertexArrays(1, &n); }
inline void texture(GLuint n) { glDeleteTextures(1, &n); }
inline void framebuffer(GLuint n) { glDeleteFramebuffers(1, &n); }
inline void renderbuffer(GLuint n) { glDeleteRenderbuffers(1, &n); }
inline void program(GLuint n) { glDeleteProgram(n); }
inline void shader(GLuint n) { glDeleteShader(n); }
}  // namespace gl_delete

using GlBuffer = GlName<gl_delete::buffer>;
using GlVertexArray = GlName<gl_delete::vertex_array>;
using GlTexture = GlName<gl_delete::texture>;
using GlFramebuffer = GlName<gl_delete::framebuffer>;
using GlRenderbuffer = GlName<gl_delete::renderbuffer>;
using GlProgram = GlName<gl_delete::program>;
using GlShader = GlName<gl_delete::shader>;

// Creation helpers (GL 3.3 core: objects exist once first bound).
inline GlBuffer make_buffer() { GLuint n = 0; glGenBuffers(1, &n); return GlBuffer(n); }
inline GlVertexArray make_vertex_array() { GLuint n = 0; glGenVertexArrays(1, &n); return GlVertexArray(n); }
inline GlTexture make_texture() { GLuint n = 0; glGenTextures(1, &n); return GlTexture(n); }
inline GlFramebuffer make_framebuffer() { GLuint n = 0; glGenFramebuffers(1, &n); return GlFramebuffer(n); }
inline GlRenderbuffer make_renderbuffer() { GLuint n = 0; glGenRenderbuffers(1, &n); return GlRenderbuffer(n); }

// Throws RenderError "<where>: OpenGL error 0x0502 (GL_INVALID_OPERATION)" if GL reported one.
void check_gl(const char* where);

}  // namespace tissu
