// Finding and reading GLSL files. Shaders ship as files in shaders/ and are looked
// up at run time, in order: an explicit directory, <executable dir>/shaders,
// <executable dir>/../shaders, then the source tree's shaders/ compiled in.
#pragma once

#include <string>
#include <vector>

namespace tissu {

// The directories searched for shaders; `explicit_dir` first when not empty.
std::vector<std::string> shader_search_dirs(const std::string& explicit_dir);

// Full path of shader `name` in the first directory that has it; throws RenderError
// naming every path tried when none has it.
std::string find_shader(const std::string& name, const std::vector<std::string>& dirs);

// Text of one shader stage with `#include "file"` lines replaced by that file.
// Each included file becomes its own GLSL source-string number (via #line), so a
// compiler message "K:LINE(COL)" points into files[K]; files[0] is the main file.
struct ShaderSource {
  std::string text;
  std::vector<std::string> files;
};
// `defines` become "#define NAME" lines right after the #version line (line numbers
// in messages stay those of the file).
ShaderSource load_shader_source(const std::string& name, const std::vector<std::string>& dirs,
                                const std::vector<std::string>& defines = {});

// Turns the first message of a GLSL info log ("0:12(5): error: ...") into
// "<file>:12:5: error: ..." using the file list of the source; adds "(+N more)".
std::string describe_shader_log(const std::string& log, const std::vector<std::string>& files);

}  // namespace tissu
