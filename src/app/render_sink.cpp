#include "app/render_sink.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace tissu {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Cloth resting on an obstacle has its vertices on the surface and its flat triangles
// inside it (by the sagitta L^2 / (8 R) of an edge of length L): drawn at full size the
// obstacle would show through. Obstacles are drawn inset by twice that sagitta plus 0.5%.
double draw_inset(double radius, double edge_length) {
  return std::min(0.2 * radius, 0.005 * radius + edge_length * edge_length / (4.0 * radius));
}

double mean_edge_length(const Model& model, const Vec3List& x) {
  double sum = 0.0;
  for (const Tri& t : model.triangles) {
    sum += (x[t[0]] - x[t[1]]).norm() + (x[t[1]] - x[t[2]]).norm() + (x[t[2]] - x[t[0]]).norm();
  }
  return model.triangles.empty() ? 0.0 : sum / (3.0 * model.triangles.size());
}

ObstacleShape shape_of(const Obstacle& ob, double t, double edge_length) {
  ObstacleShape s;
  switch (ob.kind) {
    case ObstacleKind::Sphere: s.kind = ObstacleShape::Kind::Sphere; break;
    case ObstacleKind::Cylinder: s.kind = ObstacleShape::Kind::Cylinder; break;
    case ObstacleKind::Plane: s.kind = ObstacleShape::Kind::Plane; break;
  }
  s.center = ob.center_at(t);
  s.axis = ob.axis;
  const double inset = draw_inset(ob.radius, edge_length);
  s.radius = ob.radius - inset;
  s.half_length = ob.half_length - inset;
  if (ob.kind == ObstacleKind::Plane) s.center -= 0.002 * ob.axis;  // m
  return s;
}

std::string numbered_png(const std::string& dir, long long index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06lld.png", index);
  return (std::filesystem::path(dir) / name).string();
}

}  // namespace

RenderSettings render_settings_of(const Scene& scene) {
  if (scene.render.is_null()) return RenderSettings{};
  JsonReader reader(scene.render, "render");
  return parse_render_settings(reader);
}

double frames_per_simulated_second(const RenderSettings& settings) {
  return settings.fps * settings.slow_motion;
}

RenderSink::RenderSink(const RenderSettings& settings, const RenderOutputs& outputs)
    : settings_(settings), outputs_(outputs), renderer_(settings) {
  std::unique_ptr<Mp4Writer> video;
  if (!outputs_.mp4_path.empty()) {
    video = std::make_unique<Mp4Writer>(outputs_.mp4_path, settings.width, settings.height,
                                        FrameRate(settings.fps));
  }
  pipeline_ = std::make_unique<FrameEncoderPipeline>(std::move(video));
}

bool RenderSink::wants_more() const {
  return outputs_.max_frames < 0 || frame_index_ < outputs_.max_frames;
}

void RenderSink::frame(const Model& model, const State& state, const FrameStats& stats) {
  if (!wants_more()) return;
  if (content_.triangles.empty()) {  // constant parts, once
    content_.triangles = model.triangles;
    content_.rest_uv = model.rest_uv;
    edge_length_ = mean_edge_length(model, state.x);
  }
  content_.positions = state.x;
  content_.obstacles.clear();
  for (const Obstacle& ob : model.obstacles) content_.obstacles.push_back(shape_of(ob, state.t, edge_length_));
  if (settings_.info) {
    content_.overlay_lines =
        info_overlay_lines(integrator_name(model.integrator), model.triangles.size(), stats.time);
  }

  auto t0 = std::chrono::steady_clock::now();
  renderer_.draw(content_);
  render_s_ += seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  Image image = pipeline_->take_frame_buffer(renderer_.width(), renderer_.height());
  renderer_.read_rgb(image.rgb);
  readback_s_ += seconds_since(t0);

  // One push per frame: the video frame, plus its PNG (sequence or still) if any.
  std::string png;
  if (!outputs_.png_dir.empty()) {
    png = numbered_png(outputs_.png_dir, frame_index_);
  } else if (std::find(outputs_.still_frames.begin(), outputs_.still_frames.end(),
                       frame_index_) != outputs_.still_frames.end()) {
    png = numbered_png(outputs_.stills_dir, frame_index_);
  }
  t0 = std::chrono::steady_clock::now();
  if (!outputs_.mp4_path.empty() || !png.empty()) pipeline_->push(std::move(image), png);
  push_wait_s_ += seconds_since(t0);
  ++frame_index_;
}

void RenderSink::finish() { pipeline_->finish(); }

void RenderSink::abort() noexcept { pipeline_->abort(); }

void RenderSink::add_times(StageTimes& times) const {
  times.render += render_s_;
  times.readback += readback_s_;
  times.encode += pipeline_->encode_seconds() + pipeline_->png_seconds();
  times.encode_wait += push_wait_s_;
}

}  // namespace tissu
