#include "render/gl/shader_files.h"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/executable_dir.h"
#include "render/render_error.h"

#ifndef TISSU_SHADER_DIR
#define TISSU_SHADER_DIR ""
#endif

namespace tissu {

namespace {

bool read_file(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  text = s.str();
  return true;
}

}  // namespace

std::vector<std::string> shader_search_dirs(const std::string& explicit_dir) {
  std::vector<std::string> dirs;
  auto add = [&](const std::string& dir) {
    if (!dir.empty() && std::find(dirs.begin(), dirs.end(), dir) == dirs.end()) dirs.push_back(dir);
  };
  add(explicit_dir);
  const std::string exe = executable_dir();
  if (!exe.empty()) {
    add(exe + "/shaders");
    add(exe + "/../shaders");
  }
  add(TISSU_SHADER_DIR);
  return dirs;
}

std::string find_shader(const std::string& name, const std::vector<std::string>& dirs) {
  std::string tried;
  for (const std::string& dir : dirs) {
    const std::string path = dir + "/" + name;
    if (std::ifstream(path).good()) return path;
    tried += (tried.empty() ? "" : ", ") + path;
  }
  throw RenderError("shader " + name + " not found; searched " +
                    (tried.empty() ? std::string("no directories") : tried));
}

ShaderSource load_shader_source(const std::string& name, const std::vector<std::string>& dirs,
                                const std::vector<std::string>& defines) {
  ShaderSource source;
  source.files.push_back(find_shader(name, dirs));
  std::string main_text;
  if (!read_file(source.files[0], main_text)) {
    throw RenderError(source.files[0] + ": cannot read shader");
  }
  static const std::regex include_line(R"re(^\s*#\s*include\s+"([^"]+)"\s*$)re");
  std::istringstream lines(main_text);
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    std::smatch match;
    if (line.rfind("#version", 0) == 0 && !defines.empty()) {
      source.text += line + "\n";
      for (const std::string& define : defines) source.text += "#define " + define + "\n";
      source.text += "#line " + std::to_string(line_number + 1) + " 0\n";
      continue;
    }
    if (!std::regex_match(line, match, include_line)) {
      source.text += line + "\n";
      continue;
    }
    const std::string path = find_shader(match[1].str(), dirs);
    std::string included;
    if (!read_file(path, included)) throw RenderError(path + ": cannot read shader");
    const size_t index = source.files.size();
    source.files.push_back(path);
    source.text += "#line 1 " + std::to_string(index) + "\n" + included + "\n#line " +
                   std::to_string(line_number + 1) + " 0\n";
  }
  return source;
}

std::string describe_shader_log(const std::string& log, const std::vector<std::string>& files) {
  std::vector<std::string> messages;
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) messages.push_back(line);
  }
  const std::string main_file = files.empty() ? std::string("shader") : files[0];
  if (messages.empty()) return main_file + ": failed with an empty log";
  // Mesa writes "SOURCE:LINE(COLUMN): error: text".
  static const std::regex located(R"(^\s*(\d+):(\d+)\((\d+)\):\s*(.*)$)");
  std::smatch match;
  std::string first;
  if (std::regex_match(messages[0], match, located)) {
    const size_t index = std::stoul(match[1].str());
    const std::string file = index < files.size() ? files[index] : main_file;
    first = file + ":" + match[2].str() + ":" + match[3].str() + ": " + match[4].str();
  } else {
    first = main_file + ": " + messages[0];
  }
  // Count only further error lines; continuation lines add nothing countable.
  size_t more = 0;
  for (size_t i = 1; i < messages.size(); ++i) {
    if (messages[i].find("error") != std::string::npos) ++more;
  }
  if (more > 0) first += " (+" + std::to_string(more) + " more)";
  return first;
}

}  // namespace tissu
