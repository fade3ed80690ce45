// A linked vertex + fragment program built from shader files, with cached
// uniform locations. Compile and link errors are RenderError naming file and line.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <unordered_map>
#include <vector>

#include "render/gl/gl_objects.h"

namespace tissu {

class ShaderProgram {
 public:
  // `vertex` and `fragment` are file names (e.g. "cloth.vert") looked up in `dirs`;
  // `defines` are #define'd in both stages to select variants of one file.
  ShaderProgram(const std::string& vertex, const std::string& fragment,
                const std::vector<std::string>& dirs, const std::vector<std::string>& defines = {});

  void use() const { glUseProgram(program_.get()); }

  // Uniform setters; names the shader does not use (optimised away) are ignored.
  void set(const char* name, int value) const;
  void set(const char* name, float value) const;
  void set(const char* name, const glm::vec2& value) const;
  void set(const char* name, const glm::vec3& value) const;
  void set(const char* name, const glm::vec4& value) const;
  void set(const char* name, const glm::mat3& value) const;
  void set(const char* name, const glm::mat4& value) const;
  void set(const char* name, const std::vector<glm::vec3>& values) const;

 private:
  GLint location(const char* name) const;

  GlProgram program_;
  mutable std::unordered_map<std::string, GLint> locations_;
};

}  // namespace tissu
