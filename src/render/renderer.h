// Draws frames of a run into an offscreen image: background, optional ground with
// the key light's shadow, obstacles, the two-sided patterned cloth, then text.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/frame_content.h"
#include "render/render_settings.h"

namespace tissu {

// Time spent in one part of drawing and reading back frames, summed over the frames
// drawn since pass timing was switched on (Renderer::set_pass_timing).
struct RenderPassTime {
  std::string pass;
  double cpu_s = 0.0;   // CPU time of the whole process (llvmpipe rasterizes on its own threads)
  double wall_s = 0.0;
  long long count = 0;  // times the pass ran
};

class Renderer {
 public:
  // Creates the GL context and compiles the shaders (looked up in
  // `shader_dir_override` first when given). Throws RenderError.
  explicit Renderer(const RenderSettings& settings, const std::string& shader_dir_override = "");
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Fixes the camera (in the scene's coordinates, like everything given to the renderer).
  // Without it, fit_camera() or eye and target in the settings, the first draw() frames
  // its content with auto_camera and keeps that camera.
  void set_camera(const Camera& camera);
  std::optional<Camera> camera() const;
  // Fixes the automatic camera that frames `shown` (the bounds of what a run shows: cloth
  // and finite obstacles, all frames) with the plane `obstacles`; keeps the settings' eye
  // or target when given.
  void fit_camera(const Eigen::AlignedBox3d& shown, const std::vector<ObstacleShape>& obstacles);

  void draw(const FrameContent& content);
  // The last frame drawn: width*height*3 bytes, RGB, first row at the top.
  void read_rgb(std::vector<uint8_t>& out);

  // Profiling: with pass timing on, every pass ends with glFinish() and its time is
  // recorded (this serializes llvmpipe's work, so a frame takes somewhat longer).
  void set_pass_timing(bool on);
  std::vector<RenderPassTime> pass_times() const;

  int width() const;
  int height() const;
  int samples() const;           // samples per pixel the driver gave (1 or 4 on llvmpipe)
  std::string gl_version() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissu
