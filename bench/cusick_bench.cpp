// Cusick's drape test (tests/physics/cusick.h, the tests' nine-fold run of isotropic cotton)
// with one thing changed at a time, to find what moves the drape coefficient under mesh
// refinement (docs/bending.md, "Cusick's drape test"). One run per call:
//
//   tissu_cusick_bench TRIANGLES [--no-clamp] [--shear F] [--bending F] [--strict-rest]
//                      [--trace STEPS] [--resample] [--graded RATIO] [--band M]
//                      [--turn RAD] [--membrane F] [--ring-membrane F] [--dt S]
//                      [--transition M]
//
// --no-clamp     the support's triangles are not a clamp in the bending model (pins only)
// --shear F      shear stiffness times F;  --bending F  B times F
// --strict-rest  at rest below 0.01 mm/s for 1 s (the tests: 1 mm/s for 0.2 s), 6 s at most
// --trace STEPS  prints DC and the kinetic energy every STEPS steps
// --graded RATIO  the graded disc of the tests (cusick.h, cusick_grading), edges RATIO
//                times the others just beyond the support's edge
// --band M      with --graded (given before): the fine band ends M from the centre
// --transition M  with --graded (given before): the band blends into the coarse edge over M
// --turn RAD     the mesh turned by RAD about the vertical axis
// --membrane F   tensile and shear stiffness times F
// --ring-membrane F  membrane stiffness times F in the triangles with pinned and free corners
// --dt S         backward Euler's step, s (the tests: 0.02)
// --resample     samples the drape at rest on the coarser disc meshes (1500 triangles and
//                up, same seed) and prints their bending energy of it by distance from
//                the centre
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "physics/cusick.h"

namespace tissu {
namespace {

// Position of the shape x (on `from`, a disc mesh) at rest point q: linear in the triangle
// containing q, or extrapolated from the nearest one (rim points outside `from`'s polygon).
Vec3 sample(const TriMesh& from, const Vec3List& x, const Vec2& q) {
  double best = -1e300;
  Vec3 at = Vec3::Zero();
  for (const Tri& t : from.triangles) {
    const Vec2 &a = from.rest_uv[t[0]], &b = from.rest_uv[t[1]], &c = from.rest_uv[t[2]];
    auto cross = [](const Vec2& p, const Vec2& r) { return p.x() * r.y() - p.y() * r.x(); };
    const double d = cross(b - a, c - a);
    const double la = cross(b - q, c - q) / d, lb = cross(c - q, a - q) / d, lc = 1.0 - la - lb;
    const double inside = std::min({la, lb, lc});
    if (inside > best) {
      best = inside;
      at = la * x[t[0]] + lb * x[t[1]] + lc * x[t[2]];
    }
  }
  return at;
}

// Bending energy (J) of x by the triangles' distance from the centre: bins edged at `radii`.
std::vector<double> energy_by_radius(const BendingModel& m, const TriMesh& mesh,
                                     const Vec3List& x, const std::vector<double>& radii) {
  std::vector<double> bins(radii.size() - 1, 0.0);
  for (size_t t = 0; t < m.stencils.size(); ++t) {
    const BendingStencil& st = m.stencils[t];
    Vec3 uu = Vec3::Zero(), vv = Vec3::Zero(), uv = Vec3::Zero();
    for (size_t j = 0; j < st.vertex.size(); ++j) {
      uu += st.w_uu[j] * x[st.vertex[j]];
      vv += st.w_vv[j] * x[st.vertex[j]];
      uv += st.w_uv[j] * x[st.vertex[j]];
    }
    const double e = 0.5 * st.area *
                     (m.bending_weft * uu.squaredNorm() + m.bending_warp * vv.squaredNorm() +
                      (m.bending_weft + m.bending_warp) * uv.squaredNorm());
    const Tri& tri = mesh.triangles[t];
    const double r =
        ((mesh.rest_uv[tri[0]] + mesh.rest_uv[tri[1]] + mesh.rest_uv[tri[2]]) / 3.0).norm();
    for (size_t b = 0; b + 1 < radii.size(); ++b) {
      if (r >= radii[b] && r < radii[b + 1]) bins[b] += e;
    }
  }
  return bins;
}

// Mean rest length (m) of the edges whose middle lies within 5 mm beyond the support's edge.
double edge_at_support(const TriMesh& mesh, double support_radius) {
  double sum = 0.0;
  int count = 0;
  for (const Tri& t : mesh.triangles) {
    for (int j = 0; j < 3; ++j) {
      const Vec2 &a = mesh.rest_uv[t[j]], &b = mesh.rest_uv[t[(j + 1) % 3]];
      const double r = (0.5 * (a + b)).norm();
      if (r > support_radius && r < support_radius + 0.005) {
        sum += (a - b).norm();
        ++count;
      }
    }
  }
  return count > 0 ? sum / count : 0.0;
}

void resample(const testing::DrapeSetup& s, const testing::DrapeResult& r) {
  const TriMesh fine = testing::drape_mesh(s);
  const std::vector<double> radii = {0.09, 0.095, 0.10, 0.11, 0.12, 0.13, 0.14, 0.1501};  // m
  std::printf("bending energy (J) by distance from the centre, bins edged at (m):");
  for (double e : radii) std::printf(" %.3f", e);
  std::printf("\n");
  for (int n = 1500; n <= s.triangles; n *= 2) {
    const TriMesh mesh = generate_disk(s.radius, n, s.irregular, s.seed, s.support_radius);
    std::vector<uint8_t> pinned(mesh.rest_uv.size(), 0);
    Vec3List x;
    for (size_t i = 0; i < mesh.rest_uv.size(); ++i) {
      pinned[i] = mesh.rest_uv[i].norm() <= s.support_radius * (1.0 + 1e-9) ? 1 : 0;
      x.push_back(sample(fine, r.x, mesh.rest_uv[i]));
    }
    const BendingModel m = build_bending(mesh.triangles, mesh.rest_uv, s.material.bending,
                                         s.material.bending_warp, pinned);
    const double total = bending_energy(m, x);
    std::printf("  on %5d triangles: %.4e J (%.3f of the drape's own), DC %.4f, bins", n, total,
                total / r.bending_energy, testing::drape_coefficient(s, x, mesh.triangles));
    for (double e : energy_by_radius(m, mesh, x, radii)) std::printf(" %.2e", e);
    std::printf("\n");
  }
}

int run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s TRIANGLES [options], see the source's header\n", argv[0]);
    return 2;
  }
  Material cotton = testing::isotropic_preset("cotton");
  testing::DrapeSetup s = testing::nine_fold_drape(cotton, std::atoi(argv[1]));
  bool resampled = false;
  std::string variant;  // the options, or "as the tests"
  for (int i = 2; i < argc; ++i) variant += (variant.empty() ? "" : " ") + std::string(argv[i]);
  if (variant.empty()) variant = "as the tests";
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--no-clamp") {
      s.clamp = false;
    } else if (a == "--shear" && has_value) {
      s.material.shear *= std::atof(argv[++i]);
    } else if (a == "--bending" && has_value) {
      const double f = std::atof(argv[++i]);
      s.material.bending *= f;
      s.material.bending_warp *= f;
    } else if (a == "--strict-rest") {
      s.rest_speed = 1e-5;
      s.rest_time = 1.0;
    } else if (a == "--trace" && has_value) {
      s.trace_every = std::atoi(argv[++i]);
    } else if (a == "--graded" && has_value) {
      s.grading = testing::cusick_grading(s, std::atof(argv[++i]));
    } else if (a == "--band" && has_value && s.grading) {
      s.grading->outer = std::atof(argv[++i]);
    } else if (a == "--transition" && has_value && s.grading) {
      s.grading->transition = std::atof(argv[++i]);
    } else if (a == "--turn" && has_value) {
      s.mesh_angle = std::atof(argv[++i]);
    } else if (a == "--membrane" && has_value) {
      const double f = std::atof(argv[++i]);
      for (double* c : {&s.material.weft, &s.material.warp, &s.material.coupling, &s.material.shear}) {
        *c *= f;
      }
    } else if (a == "--ring-membrane" && has_value) {
      s.clamp_ring_membrane = std::atof(argv[++i]);
    } else if (a == "--dt" && has_value) {
      s.dt = std::atof(argv[++i]);
    } else if (a == "--resample") {
      resampled = true;
    } else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const testing::DrapeResult r = testing::run_cusick(s);
  std::printf(
      "%d triangles (mean edge %.1f mm), %s: DC %.4f, %d folds, %s after %.2f s (%lld steps), "
      "kinetic energy %.2e J, largest force %.1e of the weight, energy %.3e J bending, "
      "%.3e J membrane, %.3e J gravity, %.0f s\n",
      r.triangles, 1e3 * r.mean_edge, variant.c_str(), r.coefficient, r.folds,
      r.at_rest ? "at rest" : "NOT at rest", r.time, r.steps, r.kinetic_energy, r.force_residual,
      r.bending_energy, r.membrane_energy, r.gravity_energy, r.seconds);
  std::printf("mean edge within 5 mm beyond the support's edge: %.2f mm\n",
              1e3 * edge_at_support(testing::drape_mesh(s), s.support_radius));
  if (resampled) resample(s, r);
  return r.at_rest ? 0 : 1;
}

}  // namespace
}  // namespace tissu

int main(int argc, char** argv) { return tissu::run(argc, argv); }
