#include "render/gl/shader_program.h"

#include <glm/gtc/type_ptr.hpp>

#include "render/gl/shader_files.h"
#include "render/render_error.h"

namespace tissu {

namespace {

std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log.c_str();
}

std::string program_log(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  return log.c_str();
}

GlShader compile(GLenum stage, const std::string& name, const std::vector<std::string>& dirs,
                 const std::vector<std::string>& defines) {
  const ShaderSource source = load_shader_source(name, dirs, defines);
  GlShader shader(glCreateShader(stage));
  const char* text = source.text.c_str();
  glShaderSource(shader.get(), 1, &text, nullptr);
  glCompileShader(shader.get());
  GLint ok = GL_FALSE;
  glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    throw RenderError("shader compile error: " +
                      describe_shader_log(shader_log(shader.get()), source.files));
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::string& vertex, const std::string& fragment,
                             const std::vector<std::string>& dirs,
                             const std::vector<std::string>& defines) {
  const GlShader vs = compile(GL_VERTEX_SHADER, vertex, dirs, defines);
  const GlShader fs = compile(GL_FRAGMENT_SHADER, fragment, dirs, defines);
  program_ = GlProgram(glCreateProgram());
  glAttachShader(program_.get(), vs.get());
  glAttachShader(program_.get(), fs.get());
  glLinkProgram(program_.get());
  GLint ok = GL_FALSE;
  glGetProgramiv(program_.get(), GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    std::string log = program_log(program_.get());
    const size_t end = log.find('\n');
    if (end != std::string::npos) log.resize(end);
    throw RenderError("shader link error: " + find_shader(vertex, dirs) + " + " +
                      find_shader(fragment, dirs) + ": " + log);
  }
  glDetachShader(program_.get(), vs.get());
  glDetachShader(program_.get(), fs.get());
}

GLint ShaderProgram::location(const char* name) const {
  auto it = locations_.find(name);
  if (it == locations_.end()) {
    it = locations_.emplace(name, glGetUniformLocation(program_.get(), name)).first;
  }
  return it->second;
}

void ShaderProgram::set(const char* name, int value) const { glUniform1i(location(name), value); }
void ShaderProgram::set(const char* name, float value) const { glUniform1f(location(name), value); }
void ShaderProgram::set(const char* name, const glm::vec2& v) const {
  glUniform2fv(location(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, const glm::vec3& v) const {
  glUniform3fv(location(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, const glm::vec4& v) const {
  glUniform4fv(location(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, const glm::mat3& m) const {
  glUniformMatrix3fv(location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::set(const char* name, const glm::mat4& m) const {
  glUniformMatrix4fv(location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::set(const char* name, const std::vector<glm::vec3>& values) const {
  if (values.empty()) return;
  glUniform3fv(location(name), static_cast<GLsizei>(values.size()), glm::value_ptr(values[0]));
}

}  // namespace tissu
