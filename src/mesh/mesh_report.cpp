// Prints the quality and generation time of generated meshes: 1 m x 1 m rectangles (regular
// and irregular, seed 1), disks of radius 0.5 m, and the sliver rectangle.
// Usage: tissu_mesh_report [triangles...]   (default: 961 990 4847 50000)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <vector>

#include "mesh/generate.h"
#include "mesh/quality.h"

namespace {

void report(const char* kind, int request, const std::function<tissu::TriMesh()>& generate) {
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  const tissu::TriMesh mesh = generate();
  const double cpu_ms = 1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const tissu::MeshQuality q = tissu::measure_quality(mesh);
  std::printf("%-16s %8d %8d %9.2f %9.2f %10.2f %9.2f %6.2f %8.1f %8.1f\n", kind, request,
              q.triangle_count, q.min_angle_deg, q.max_angle_deg, q.max_aspect_ratio,
              q.mean_angle_deviation_deg, q.interior_valence6_fraction, ms, cpu_ms);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> counts;
  for (int i = 1; i < argc; ++i) counts.push_back(std::atoi(argv[i]));
  if (counts.empty()) counts = {961, 990, 4847, 50000};
  std::printf("%-16s %8s %8s %9s %9s %10s %9s %6s %8s %8s\n", "mesh", "request", "actual",
              "min_angle", "max_angle", "max_aspect", "mean_dev", "val6", "wall_ms", "cpu_ms");
  for (int n : counts) {
    report("rectangle", n, [n] { return tissu::generate_rectangle(1, 1, n, false, 1); });
  }
  for (int n : counts) {
    report("rectangle irreg", n, [n] { return tissu::generate_rectangle(1, 1, n, true, 1); });
  }
  for (int n : counts) report("disk", n, [n] { return tissu::generate_disk(0.5, n, false, 1); });
  for (int n : counts) {
    report("disk irreg", n, [n] { return tissu::generate_disk(0.5, n, true, 1); });
  }
  for (int n : counts) report("sliver", n, [n] { return tissu::generate_sliver_rectangle(1, 1, n); });
  return 0;
}
