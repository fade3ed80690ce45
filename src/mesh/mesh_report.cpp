// Prints the quality and generation time of generated 1 m x 1 m rectangles.
// Usage: tissu_mesh_report [triangles...]   (default: 961 990 4847 50000)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "mesh/generate.h"
#include "mesh/quality.h"

int main(int argc, char** argv) {
  std::vector<int> counts;
  for (int i = 1; i < argc; ++i) counts.push_back(std::atoi(argv[i]));
  if (counts.empty()) counts = {961, 990, 4847, 50000};
  std::printf("%-9s %8s %8s %9s %9s %9s %9s %7s %9s\n", "kind", "request", "actual",
              "min_angle", "max_angle", "max_aspect", "mean_dev", "val6", "time_ms");
  for (bool irregular : {false, true}) {
    for (int count : counts) {
      const auto start = std::chrono::steady_clock::now();
      const tissu::TriMesh mesh = tissu::generate_rectangle(1.0, 1.0, count, irregular, 1);
      const double ms = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - start).count();
      const tissu::MeshQuality q = tissu::measure_quality(mesh);
      std::printf("%-9s %8d %8d %9.2f %9.2f %9.2f %9.2f %7.2f %9.1f\n",
                  irregular ? "irregular" : "regular", count, q.triangle_count, q.min_angle_deg,
                  q.max_angle_deg, q.max_aspect_ratio, q.mean_angle_deviation_deg,
                  q.interior_valence6_fraction, ms);
    }
  }
  return 0;
}
