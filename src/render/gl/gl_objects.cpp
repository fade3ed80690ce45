#include "render/gl/gl_objects.h"

#include <cstdio>
#include <string>

#include "render/render_error.h"

namespace tissu {

namespace {

const char* gl_error_name(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "unknown";
  }
}

}  // namespace

void check_gl(const char* where) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }  // GL keeps one flag per error kind: clear the rest so the next check starts clean
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", error);
  throw RenderError(std::string(where) + ": OpenGL error " + code + " (" + gl_error_name(error) +
                    ")");
}

}  // namespace tissu
