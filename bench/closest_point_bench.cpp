// Closest-point queries against a triangle surface, the choice behind mesh obstacles:
// Tissu's own hierarchy (collision/closed_surface.h) against CGAL's AABB tree and, when
// built with it, Embree's point queries. Each query returns the closest point (and, for
// Tissu, the signed distance). Points: near the surface (within 2 cm, as cloth resting on
// it) and at 2-20 cm, queried in Morton order (neighbours after each other, as a cloth's
// vertices are numbered). CPU time per query, best of 3 repeats.
//   ./build/bench/tissu_closest_point_bench MESH.off [height_m]
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <random>

#include "collision/closed_surface.h"
#include "collision/primitive_distance.h"
#include "mesh/load.h"

#ifdef TISSU_BENCH_EMBREE
#include <embree3/rtcore.h>
#endif

using namespace tissu;

namespace {

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

template <class F>
double best_us_per_query(const Vec3List& points, const std::vector<int>& hints, F&& query) {
  double best = 1e30;
  double sink = 0;
  for (int r = 0; r < 3; ++r) {
    const double t0 = cpu_seconds();
    for (size_t i = 0; i < points.size(); ++i) sink += query(points[i], hints[i]);
    best = std::min(best, (cpu_seconds() - t0) / points.size());
  }
  if (sink == 12345.678) std::printf(" ");
  return 1e6 * best;
}

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalTriangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, CgalTriangles::const_iterator>;
using CgalTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

#ifdef TISSU_BENCH_EMBREE
struct EmbreeQuery {
  const ClosedSurface* surface;
  double best2;
};

bool embree_visit(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<EmbreeQuery*>(args->userPtr);
  const Tri& t = q->surface->triangles()[args->primID];
  const Vec3 p(args->query->x, args->query->y, args->query->z);
  const Vec3List& v = q->surface->vertices();
  const double d2 = (p - closest_on_triangle(p, v[t[0]], v[t[1]], v[t[2]]).point).squaredNorm();
  if (d2 < q->best2) {
    q->best2 = d2;
    args->query->radius = std::nextafter(static_cast<float>(std::sqrt(d2)), 1e30f);
    return true;
  }
  return false;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MESH [height_m]\n", argv[0]);
    return 2;
  }
  const double height = argc > 2 ? std::atof(argv[2]) : 1.75;
  SurfaceFile file = load_surface(argv[1]);
  Box3 box;
  for (const Vec3& p : file.positions) box.extend(p);
  const double scale = height / box.sizes().z();
  for (Vec3& p : file.positions) p = scale * (p - box.center());

  double t0 = cpu_seconds();
  const ClosedSurface surface(file.positions, file.triangles, argv[1]);
  const double build_s = cpu_seconds() - t0;
  std::printf("%s: %zu triangles, %.2f m tall; ClosedSurface built in %.3f s (checks, tree, "
              "self-crossing check, far grid)\n",
              argv[1], surface.triangles().size(), height, build_s);

  // Query points: random surface points moved along the normal.
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(surface.triangles().size()) - 1);
  std::uniform_real_distribution<double> unit(0, 1);
  auto points_at = [&](double lo, double hi) {
    Vec3List points;
    for (int i = 0; i < 20000; ++i) {
      const int t = pick(rng);
      double a = unit(rng), b = unit(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Tri& tri = surface.triangles()[t];
      const Vec3List& v = surface.vertices();
      const Vec3 on = v[tri[0]] + a * (v[tri[1]] - v[tri[0]]) + b * (v[tri[2]] - v[tri[0]]);
      points.push_back(on + (lo + (hi - lo) * unit(rng)) * surface.face_normals()[t]);
    }
    const Box3 b = surface.bounds();
    auto morton = [&](const Vec3& p) {
      const Vec3 g = 1023.0 * (p - b.min()).cwiseQuotient(b.sizes()).cwiseMax(0.0).cwiseMin(1.0);
      uint64_t code = 0;
      for (int bit = 9; bit >= 0; --bit) {
        for (int a = 0; a < 3; ++a) code = (code << 1) | ((static_cast<uint64_t>(g[a]) >> bit) & 1);
      }
      return code;
    };
    std::sort(points.begin(), points.end(),
              [&](const Vec3& x, const Vec3& y) { return morton(x) < morton(y); });
    return points;
  };
  const Vec3List near = points_at(-0.005, 0.02), mid = points_at(0.02, 0.2);
  // Hints: the closest triangle of each point moved by up to 2 mm (a cloth vertex a step
  // or a few steps before).
  std::vector<int> near_hint, mid_hint;
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);
  for (const Vec3& p : near) near_hint.push_back(surface.closest(p + Vec3(jitter(rng), jitter(rng), jitter(rng))).triangle);
  for (const Vec3& p : mid) mid_hint.push_back(surface.closest(p + Vec3(jitter(rng), jitter(rng), jitter(rng))).triangle);

  CgalTriangles triangles;
  for (const Tri& t : surface.triangles()) {
    const Vec3List& v = surface.vertices();
    auto P = [&](int i) { return Kernel::Point_3(v[i].x(), v[i].y(), v[i].z()); };
    triangles.emplace_back(P(t[0]), P(t[1]), P(t[2]));
  }
  t0 = cpu_seconds();
  CgalTree cgal(triangles.begin(), triangles.end());
  cgal.accelerate_distance_queries();
  const double cgal_build = cpu_seconds() - t0;

#ifdef TISSU_BENCH_EMBREE
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
      surface.vertices().size()));
  unsigned* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
      surface.triangles().size()));
  for (size_t i = 0; i < surface.vertices().size(); ++i) {
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(surface.vertices()[i][k]);
  }
  for (size_t i = 0; i < surface.triangles().size(); ++i) {
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = static_cast<unsigned>(surface.triangles()[i][k]);
  }
  t0 = cpu_seconds();
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  const double embree_build = cpu_seconds() - t0;
#endif

  std::printf("\n| method | build s | near (within 2 cm) us/query | 2-20 cm us/query | near, with hint | 2-20 cm, with hint |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  const std::vector<int> no_hint(near.size(), -1);
  auto row = [&](const char* name, double build, auto&& query) {
    std::printf("| %s | %.3f | %.3f | %.3f | %.3f | %.3f |\n", name, build,
                best_us_per_query(near, no_hint, query), best_us_per_query(mid, no_hint, query),
                best_us_per_query(near, near_hint, query), best_us_per_query(mid, mid_hint, query));
  };
  row("Tissu ClosedSurface::closest (signed)", build_s,
      [&](const Vec3& p, int hint) { return surface.closest(p, hint).distance; });
  row("Tissu ClosedSurface::closest_within 3 cm (signed)", build_s,
      [&](const Vec3& p, int hint) { return surface.closest_within(p, 0.03, hint).distance; });
  // CGAL's hint is a point of the surface (the closest point of the hinted triangle).
  row("CGAL AABB_tree::closest_point_and_primitive", cgal_build, [&](const Vec3& p, int hint) {
    if (hint >= 0) {
      const Tri& t = surface.triangles()[hint];
      const Vec3List& v = surface.vertices();
      const Vec3 on = closest_on_triangle(p, v[t[0]], v[t[1]], v[t[2]]).point;
      const auto hit = cgal.closest_point_and_primitive(
          Kernel::Point_3(p.x(), p.y(), p.z()),
          std::make_pair(Kernel::Point_3(on.x(), on.y(), on.z()), triangles.cbegin() + hint));
      return hit.first.x();
    }
    const auto hit = cgal.closest_point_and_primitive(Kernel::Point_3(p.x(), p.y(), p.z()));
    return hit.first.x();
  });
#ifdef TISSU_BENCH_EMBREE
  // Embree's hint: the query radius starts at the distance to the hinted triangle.
  row("Embree rtcPointQuery (float tree, double distance)", embree_build, [&](const Vec3& p, int hint) {
    RTCPointQuery query;
    query.x = static_cast<float>(p.x());
    query.y = static_cast<float>(p.y());
    query.z = static_cast<float>(p.z());
    double start2 = 1e300;
    if (hint >= 0) {
      const Tri& t = surface.triangles()[hint];
      const Vec3List& v = surface.vertices();
      start2 = (p - closest_on_triangle(p, v[t[0]], v[t[1]], v[t[2]]).point).squaredNorm();
    }
    query.radius = hint >= 0 ? std::nextafter(static_cast<float>(std::sqrt(start2)), 1e30f) : 1e30f;
    query.time = 0.0f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    EmbreeQuery q{&surface, start2 * (1 + 1e-12) + 1e-300};
    rtcPointQuery(scene, &query, &context, embree_visit, &q);
    return q.best2;
  });
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
#endif
  // Agreement: the methods find the same distance.
  double worst = 0;
  for (const Vec3& p : near) {
    const double a = std::fabs(surface.closest(p).distance);
    const auto hit = cgal.closest_point_and_primitive(Kernel::Point_3(p.x(), p.y(), p.z()));
    const Vec3 q(hit.first.x(), hit.first.y(), hit.first.z());
    worst = std::max(worst, std::fabs(a - (p - q).norm()));
  }
  std::printf("\nlargest difference Tissu - CGAL distance over the near points: %.3g m\n", worst);
  return 0;
}
