#include "app/cli.h"

#include <cerrno>
#include <filesystem>
#include <iostream>
#include <limits>
#include <unistd.h>

#include "core/error.h"
#include "core/partial_file.h"

namespace tissu {

namespace {

const char* kRunHelp =
    "usage: tissu run SCENE.json [--out DIR] [--set KEY=VALUE]... [--obj-every N]\n"
    "                 [--threads N] [--report FILE] [--check] [-y] [--quiet]\n"
    "Simulates a scene and writes DIR/report.json (and OBJ snapshots on request).\n"
    "  --out DIR          output directory (default out/<scene name>)\n"
    "  -y, --overwrite    replace the outputs of an earlier run (report, OBJ snapshots);\n"
    "                     without it, a run refuses to write over them\n"
    "  --set KEY=VALUE    override a scene value by dotted path, e.g. --set dt=1e-4,\n"
    "                     --set cloth.material.density=0.2; VALUE is JSON if it parses\n"
    "  --obj-every N      write DIR/obj/frame_NNNNNN.obj every N steps (and final.obj)\n"
    "  --threads N        simulation threads (default and most: the processors available;\n"
    "                     at most one per 2000 triangles); the results are the same bits\n"
    "                     for any N\n"
    "  --report FILE      report path (default DIR/report.json)\n"
    "  --check            check every recorded frame exactly for cloth triangles that\n"
    "                     cross each other or a mesh obstacle (report: crossings)\n"
    "  --quiet            no progress output\n"
    "Exit codes: 0 ok, 1 output error, 2 bad input, 3 diverged, 4 --check found\n"
    "crossings, 130 interrupted.\n";

const char* kRenderHelp =
    "usage: tissu render SCENE.json [--out DIR] [--set KEY=VALUE]... [--png] [--no-mp4]\n"
    "                    [--frames N] [--stills N] [--obj-every N] [--threads N]\n"
    "                    [--report FILE] [--check] [-y] [--quiet]\n"
    "Simulates a scene, renders every frame off screen and writes DIR/<name>.mp4\n"
    "(H.264, yuv420p, fps and slow motion from the scene's render block).\n"
    "  --png              also write DIR/png/frame_NNNNNN.png for every frame\n"
    "  --no-mp4           do not write the MP4\n"
    "  --frames N         stop after N frames (report status: stopped)\n"
    "  --stills N         write N PNG stills spread over the run to DIR/stills/\n"
    "  -y, --overwrite    replace the outputs of an earlier run (video, PNG frames and\n"
    "                     stills, report, OBJ snapshots); without it, a run refuses to\n"
    "                     write over them\n"
    "  (other options as for tissu run)\n"
    "Exit codes: 0 ok, 1 output error, 2 bad input, 3 diverged, 4 --check found\n"
    "crossings, 130 interrupted.\n";

}  // namespace

long long parse_count(const std::string& option, const std::string& text, long long min,
                      long long max) {
  long long value = 0;
  bool is_count = false;
  try {
    size_t used = 0;
    value = std::stoll(text, &used);
    is_count = used == text.size() && value >= min;
  } catch (const std::exception&) {
  }
  if (!is_count) {
    throw InputError(option + ": expected an integer >= " + std::to_string(min) + ", got \"" +
                     text + "\"");
  }
  if (value > max) {
    throw InputError(option + ": expected at most " + std::to_string(max) + ", got " +
                     std::to_string(value));
  }
  return value;
}

bool walk_arguments(const std::vector<std::string>& args, const std::string& command,
                    const char* help,
                    const std::function<bool(const std::string&, const OptionValue&)>& take) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      std::cout << help;
      return false;
    }
    const OptionValue value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(command + ": " + a + " needs a value");
      return args[++i];
    };
    if (take(a, value)) continue;
    if (!a.empty() && a[0] == '-') {
      throw UsageError(command + ": unknown option " + a + " (see " + command + " --help)");
    }
    throw UsageError(command + ": unexpected argument \"" + a + "\"");
  }
  return true;
}

bool parse_scene_command(const std::vector<std::string>& args, bool render,
                         SceneCommandOptions& out) {
  const std::string command = render ? "tissu render" : "tissu run";
  const bool go = walk_arguments(
      args, command, render ? kRenderHelp : kRunHelp,
      [&](const std::string& a, const OptionValue& value) {
        if (a == "--out") {
          out.out_dir = value();
        } else if (a == "--set") {
          out.overrides.push_back(value());
        } else if (a == "--obj-every") {
          out.obj_every = static_cast<int>(parse_count("--obj-every", value(), 1));
        } else if (a == "--threads") {
          out.threads = static_cast<int>(parse_count("--threads", value(), 1, kMaxThreads));
        } else if (a == "--report") {
          out.report_path = value();
        } else if (a == "--quiet") {
          out.quiet = true;
        } else if (a == "--check") {
          out.check = true;
        } else if (a == "-y" || a == "--overwrite") {
          out.overwrite = true;
        } else if (render && a == "--png") {
          out.png = true;
        } else if (render && a == "--no-mp4") {
          out.mp4 = false;
        } else if (render && a == "--stills") {
          out.stills = static_cast<int>(parse_count("--stills", value(), 1));
        } else if (render && a == "--frames") {
          out.max_frames = parse_count("--frames", value(), 1);
        } else if (a.empty() || a[0] != '-') {
          if (!out.scene_file.empty()) return false;  // a second scene
          out.scene_file = a;
        } else {
          return false;
        }
        return true;
      });
  if (!go) return false;
  if (out.scene_file.empty()) throw UsageError(command + ": missing SCENE.json (see --help)");
  if (out.out_dir.empty()) {
    out.out_dir = (std::filesystem::path("out") /
                   std::filesystem::path(out.scene_file).stem()).string();
  }
  if (out.report_path.empty()) {
    out.report_path = (std::filesystem::path(out.out_dir) / "report.json").string();
  }
  return true;
}

void prepare_output_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw OutputError(dir + ": cannot create output directory: " + ec.message());
  if (!std::filesystem::is_directory(dir)) {
    throw OutputError(dir + ": output path exists and is not a directory");
  }
  if (access(dir.c_str(), W_OK) != 0) {
    throw OutputError(dir + ": output directory is not writable: " + errno_text(errno));
  }
}

void OutputDirs::prepare(const std::string& dir) {
  namespace fs = std::filesystem;
  // The missing ancestors, found before creating anything: symlink_status, so a dangling
  // symlink counts as existing and is never taken for a directory of ours.
  std::vector<std::string> missing;
  std::error_code ec;
  for (fs::path p = fs::path(dir).lexically_normal(); !p.empty() && p != p.root_path();
       p = p.parent_path()) {
    if (p.filename().empty()) continue;  // "a/b/" -> "a/b"
    if (fs::exists(fs::symlink_status(p, ec))) break;
    missing.push_back(p.string());
  }
  created_.insert(created_.end(), missing.rbegin(), missing.rend());
  prepare_output_dir(dir);
}

void OutputDirs::remove_created_if_empty() noexcept {
  namespace fs = std::filesystem;
  for (auto it = created_.rbegin(); it != created_.rend(); ++it) {
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(*it, ec);
    if (ec || !fs::is_directory(status) || !fs::is_empty(*it, ec) || ec) continue;
    fs::remove(*it, ec);  // rmdir: fails, harmlessly, if something appeared meanwhile
  }
  created_.clear();
}

}  // namespace tissu
