// Tests of the bending term (src/physics/bending.h): derivatives against finite differences,
// invariants (flat sheet and affine maps in the kernel, rigid motions), and the known answer
// of a sheet rolled on a cylinder, E = B/2 k^2 A, on irregular meshes built here.
#include "physics/bending.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/error.h"
#include "mesh/generate.h"
#include "physics/block_triplets.h"

namespace tissu {
namespace {

struct Sheet {
  TriList triangles;
  Vec2List uv;           // m
  double area = 0.0;     // m^2
  double spacing = 0.0;  // typical edge length, m
};

double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

void finish(Sheet& s) {
  s.area = 0.0;
  for (const Tri& t : s.triangles) {
    const double a = signed_area(s.uv[t[0]], s.uv[t[1]], s.uv[t[2]]);
    if (!(a > 0.0)) throw std::logic_error("test mesh has an inverted triangle");
    s.area += a;
  }
}

// Rectangle [0, W] x [0, H] (plus `origin`) cut into nx x ny cells. Interior vertices are
// moved by up to `jitter` cell sizes in u and v; each cell is split along a random
// diagonal when `random_diagonals`, else along the same diagonal.
Sheet grid_sheet(int nx, int ny, double W, double H, double jitter, bool random_diagonals,
                 uint64_t seed, Vec2 origin = Vec2::Zero()) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Sheet s;
  const double hx = W / nx, hy = H / ny;
  s.spacing = std::min(hx, hy);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      Vec2 p(i * hx, j * hy);
      if (i > 0 && i < nx && j > 0 && j < ny) p += jitter * Vec2(hx * uni(rng), hy * uni(rng));
      s.uv.push_back(origin + p);
    }
  }
  std::bernoulli_distribution coin(0.5);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (!random_diagonals || coin(rng)) {
        s.triangles.emplace_back(a, b, c);
        s.triangles.emplace_back(a, c, d);
      } else {
        s.triangles.emplace_back(a, b, d);
        s.triangles.emplace_back(b, c, d);
      }
    }
  }
  finish(s);
  return s;
}

// Rectangle [0, W] x [0, H] covered by rows of nearly equilateral triangles: rows of points
// alternately offset by half a spacing (odd rows get the two corner points too), adjacent
// rows zipped together; interior points moved by up to `jitter` spacings.
Sheet lattice_sheet(int nx, int ny, double W, double H, double jitter, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Sheet s;
  const double hx = W / nx, hy = H / ny;
  s.spacing = std::min(hx, hy);
  std::vector<std::vector<int>> rows(ny + 1);
  for (int j = 0; j <= ny; ++j) {
    std::vector<double> xs;
    if (j % 2 == 0) {
      for (int i = 0; i <= nx; ++i) xs.push_back(i * hx);
    } else {
      xs.push_back(0.0);
      for (int i = 0; i < nx; ++i) xs.push_back((i + 0.5) * hx);
      xs.push_back(W);
    }
    for (size_t i = 0; i < xs.size(); ++i) {
      Vec2 p(xs[i], j * hy);
      const bool interior = i > 0 && i + 1 < xs.size() && j > 0 && j < ny;
      if (interior) p += jitter * Vec2(hx * uni(rng), hy * uni(rng));
      rows[j].push_back(static_cast<int>(s.uv.size()));
      s.uv.push_back(p);
    }
  }
  for (int j = 0; j < ny; ++j) {
    const std::vector<int>& A = rows[j];
    const std::vector<int>& B = rows[j + 1];
    size_t a = 0, b = 0;
    while (a + 1 < A.size() || b + 1 < B.size()) {
      // Advance along the row whose next point comes first in u, unless that would make
      // an inverted triangle.
      bool lower =
          b + 1 == B.size() || (a + 1 < A.size() && s.uv[A[a + 1]].x() < s.uv[B[b + 1]].x());
      if (a + 1 < A.size() && b + 1 < B.size()) {
        const double lower_area = signed_area(s.uv[A[a]], s.uv[A[a + 1]], s.uv[B[b]]);
        const double upper_area = signed_area(s.uv[A[a]], s.uv[B[b + 1]], s.uv[B[b]]);
        if (lower && lower_area <= 0.0) lower = false;
        if (!lower && upper_area <= 0.0) lower = true;
      }
      if (lower) {
        s.triangles.emplace_back(A[a], A[a + 1], B[b]);
        ++a;
      } else {
        s.triangles.emplace_back(A[a], B[b + 1], B[b]);
        ++b;
      }
    }
  }
  finish(s);
  return s;
}

// A deliberately bad mesh: a "union jack" grid (diagonals alternating from cell to cell)
// whose middle column of cells is 1/100 as wide as the others (needle triangles, edges in
// the ratio 1:100), and three valence-4 vertices pushed almost onto the edge opposite
// them ("caps": an angle near 180 degrees, 1/1000 of the normal area).
Sheet sliver_sheet(int nx, int ny, double W, double H) {
  Sheet s;
  std::vector<double> xs(1, 0.0);
  for (int i = 0; i < nx; ++i) xs.push_back(xs.back() + (i == nx / 2 ? 0.01 : 1.0));
  const double hy = H / ny;
  for (double& x : xs) x *= W / xs.back();
  s.spacing = std::min(W / (nx - 1), hy);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) s.uv.emplace_back(xs[i], j * hy);
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {
        s.triangles.emplace_back(a, b, c);
        s.triangles.emplace_back(a, c, d);
      } else {
        s.triangles.emplace_back(a, b, d);
        s.triangles.emplace_back(b, c, d);
      }
    }
  }
  // Caps: vertices (i, j) with i + j odd have valence 4; move three of them (away from the
  // thin column) to within 1/1000 of the midpoint of the edge (i+1, j)-(i, j+1).
  const int caps[3][2] = {{2, 3}, {nx - 3, 2}, {3, ny - 2}};
  for (const auto& cap : caps) {
    const int i = cap[0], j = cap[1];
    const Vec2 mid = 0.5 * (s.uv[id(i + 1, j)] + s.uv[id(i, j + 1)]);
    s.uv[id(i, j)] += (1.0 - 1e-3) * (mid - s.uv[id(i, j)]);
  }
  finish(s);
  return s;
}

// Orthonormal frame of the 3D placement of the rest plane.
struct Frame {
  Vec3 origin = Vec3(0.3, -0.2, 1.0);
  Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
};

// The sheet rolled (isometrically) onto a cylinder of curvature k (1/m): the sheet curves
// along the unit rest direction d = (cos phi, sin phi) and keeps straight the lines along
// a = (-sin phi, cos phi), the cylinder's axis. k = 0 leaves the sheet flat.
Vec3List roll(const Sheet& s, double k, double phi, const Frame& frame = Frame()) {
  const Vec2 d(std::cos(phi), std::sin(phi)), a(-std::sin(phi), std::cos(phi));
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : s.uv) c += p;
  c /= static_cast<double>(s.uv.size());
  Vec3List x;
  for (const Vec2& p : s.uv) {
    const double sd = d.dot(p - c), sa = a.dot(p - c);
    const double along = k == 0.0 ? sd : std::sin(k * sd) / k;
    const double up = k == 0.0 ? 0.0 : (1.0 - std::cos(k * sd)) / k;
    // Local frame: d -> e_x, a -> e_y, normal -> e_z.
    x.push_back(frame.origin + frame.R * Vec3(along, sa, up));
  }
  return x;
}

Vec3List add_noise(Vec3List x, double amplitude, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (Vec3& p : x) p += amplitude * Vec3(uni(rng), uni(rng), uni(rng));
  return x;
}

Vec3List forces(const BendingModel& m, const Vec3List& x) {
  Vec3List f(x.size(), Vec3::Zero());
  add_bending_forces(m, x, bending_origin(x), 0, static_cast<int>(x.size()), VertexForces::of(f));
  return f;
}

Eigen::VectorXd flatten(const Vec3List& v) {
  Eigen::VectorXd out(3 * v.size());
  for (size_t i = 0; i < v.size(); ++i) out.segment<3>(3 * i) = v[i];
  return out;
}

Eigen::MatrixXd dense_jacobian(const BendingModel& m, const Vec3List& x) {
  BlockTriplets t;
  TripletSink sink(1.0, 0.0, t);
  add_bending_jacobian(m, sink);
  return Eigen::MatrixXd(t.to_sparse(static_cast<int>(x.size())));
}

double relative_energy_error(const BendingModel& m, const Sheet& s, double B, double k,
                             double phi) {
  const double exact = 0.5 * B * k * k * s.area;
  return (bending_energy(m, roll(s, k, phi)) - exact) / exact;
}

// ---------------------------------------------------------------------------------------
// Derivatives.

// Central differences of the energy reproduce -f. The energy is quadratic in x, so the
// central-difference truncation error is identically zero and only round-off remains
// (it grows as the step shrinks); the forward difference has truncation error s/2 e^T Q e,
// which must shrink linearly with the step, as a check that the harness resolves steps.
TEST(Bending, ForcesAreMinusEnergyGradient) {
  const Sheet s = grid_sheet(6, 5, 0.3, 0.25, 0.2, true, 11);
  const BendingModel m = build_bending(s.triangles, s.uv, 2e-4, 5e-4);
  const Vec3List x0 = add_noise(roll(s, 6.0, 0.4), 0.2 * s.spacing, 12);
  const Eigen::VectorXd f = flatten(forces(m, x0));
  const double E0 = bending_energy(m, x0);
  ASSERT_GT(E0, 0.0);

  double previous_forward = 0.0;
  for (double rel_step : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    const double h = rel_step * s.spacing;
    Eigen::VectorXd central(f.size()), forward(f.size());
    for (int i = 0; i < f.size(); ++i) {
      Vec3List xp = x0, xm = x0;
      xp[i / 3][i % 3] += h;
      xm[i / 3][i % 3] -= h;
      const double Ep = bending_energy(m, xp), Em = bending_energy(m, xm);
      central[i] = -(Ep - Em) / (2 * h);
      forward[i] = -(Ep - E0) / h;
    }
    const double err_c = (central - f).norm() / f.norm();
    const double err_f = (forward - f).norm() / f.norm();
    std::printf("  FD step %.0e h: central rel. error %.2e, forward rel. error %.2e\n", rel_step,
                err_c, err_f);
    EXPECT_LT(err_c, 1e-6) << "step " << rel_step;
    if (rel_step >= 1e-4) {
      if (previous_forward > 0.0) {
        EXPECT_NEAR(previous_forward / err_f, 10.0, 1.0) << "forward error not O(step)";
      }
      previous_forward = err_f;
    }
  }
}

// Central differences of the forces reproduce the Jacobian; it is symmetric and negative
// semi-definite, and exactly constant.
TEST(Bending, JacobianMatchesForceDifferences) {
  const Sheet s = lattice_sheet(5, 4, 0.3, 0.25, 0.3, 21);
  const BendingModel m = build_bending(s.triangles, s.uv, 1e-4, 3e-4);
  const Vec3List x0 = add_noise(roll(s, 8.0, 1.1), 0.2 * s.spacing, 22);
  const Eigen::MatrixXd J = dense_jacobian(m, x0);
  for (double rel_step : {1e-2, 1e-4, 1e-6}) {
    const double h = rel_step * s.spacing;
    Eigen::MatrixXd J_fd(J.rows(), J.cols());
    for (int i = 0; i < J.cols(); ++i) {
      Vec3List xp = x0, xm = x0;
      xp[i / 3][i % 3] += h;
      xm[i / 3][i % 3] -= h;
      J_fd.col(i) = (flatten(forces(m, xp)) - flatten(forces(m, xm))) / (2 * h);
    }
    const double err = (J_fd - J).norm() / J.norm();
    std::printf("  Jacobian FD step %.0e h: rel. error %.2e\n", rel_step, err);
    EXPECT_LT(err, 1e-6);
  }
  EXPECT_LT((J - J.transpose()).norm(), 1e-14 * J.norm());
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(J).eigenvalues();
  EXPECT_LT(eig.maxCoeff(), 1e-12 * std::abs(eig.minCoeff()));
  // The Jacobian does not depend on the configuration.
  EXPECT_EQ((dense_jacobian(m, roll(s, 0.0, 0.0)) - J).norm(), 0.0);
}

// ---------------------------------------------------------------------------------------
// Invariants.

// The kernel of Q is exactly the affine functions of (u, v): 3 zero eigenvalues, and no
// other soft (spurious zero-energy) mode.
TEST(Bending, KernelIsExactlyAffine) {
  struct Case {
    const char* name;
    Sheet sheet;
  };
  // The last mesh has slivers: many triangles use fallback stencils there.
  const Case cases[] = {{"regular grid", grid_sheet(7, 6, 0.35, 0.3, 0.0, false, 1)},
                        {"jittered grid", grid_sheet(7, 6, 0.35, 0.3, 0.2, true, 2)},
                        {"jittered lattice", lattice_sheet(7, 6, 0.35, 0.3, 0.3, 3)},
                        {"strongly jittered lattice", lattice_sheet(14, 12, 0.35, 0.3, 0.45, 4)}};
  for (const Case& c : cases) {
    const BendingModel m = build_bending(c.sheet.triangles, c.sheet.uv, 1e-3, -1.0);
    const Eigen::MatrixXd Q(m.stiffness);
    EXPECT_LT((Q - Q.transpose()).norm(), 1e-14 * Q.norm());
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Q).eigenvalues();
    const double top = eig.maxCoeff();
    std::printf(
        "  %s: %d vertices, %d fallback stencils, eigenvalues/max: %.1e %.1e %.1e | "
        "%.2e (4th)\n",
        c.name, m.num_vertices, m.fallback_stencils, eig[0] / top, eig[1] / top, eig[2] / top,
        eig[3] / top);
    EXPECT_GT(eig[0], -1e-12 * top);
    EXPECT_LT(eig[2], 1e-12 * top);
    EXPECT_GT(eig[3], 1e-6 * top) << c.name;
    // The affine functions 1, u, v are in the kernel.
    Eigen::VectorXd one = Eigen::VectorXd::Ones(m.num_vertices), u(m.num_vertices),
                    v(m.num_vertices);
    for (int i = 0; i < m.num_vertices; ++i) {
      u[i] = c.sheet.uv[i].x();
      v[i] = c.sheet.uv[i].y();
    }
    EXPECT_LT((Q * one).norm(), 1e-12 * top);
    EXPECT_LT((Q * u).norm(), 1e-12 * top);
    EXPECT_LT((Q * v).norm(), 1e-12 * top);
  }
  EXPECT_GT(
      build_bending(cases[3].sheet.triangles, cases[3].sheet.uv, 1e-3, -1.0).fallback_stencils, 0);
}

// A flat sheet anywhere in its plane (in-plane rotation and translation), in any plane of
// space, and under an affine in-plane stretch, has zero energy and feels zero force.
TEST(Bending, FlatSheetHasNoEnergyAndNoForce) {
  const Sheet s = grid_sheet(9, 7, 0.45, 0.35, 0.2, true, 31);
  const double B = 1e-3;
  const BendingModel m = build_bending(s.triangles, s.uv, B, 2.5 * B);
  // Scales: energy and largest force of the sheet rolled with curvature 5 1/m.
  const Vec3List bent = roll(s, 5.0, 0.3);
  const double E_ref = bending_energy(m, bent);
  double f_ref = 0.0;
  for (const Vec3& f : forces(m, bent)) f_ref = std::max(f_ref, f.norm());
  ASSERT_GT(E_ref, 0.0);
  ASSERT_GT(f_ref, 0.0);

  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    // In-plane rigid motion of the rest plane (rotation theta, translation t), optionally
    // with an affine stretch/shear, then a rigid placement in space.
    const double theta = kPi * uni(rng);
    Eigen::Matrix2d A = Eigen::Rotation2Dd(theta).toRotationMatrix();
    if (trial >= 3) A = A * (Eigen::Matrix2d() << 1.2, 0.3 * uni(rng), 0.0, 0.9).finished();
    const Vec2 t(5.0 * uni(rng), 5.0 * uni(rng));
    const Mat3 R =
        trial % 2 == 0
            ? Mat3::Identity()
            : Eigen::AngleAxisd(kPi * uni(rng), Vec3(uni(rng), uni(rng), uni(rng)).normalized())
                  .toRotationMatrix();
    const Vec3 offset(uni(rng), uni(rng), uni(rng));
    Vec3List x;
    for (const Vec2& p : s.uv) {
      const Vec2 q = A * p + t;
      x.push_back(R * Vec3(q.x(), q.y(), 0.0) + offset);
    }
    const double E = bending_energy(m, x);
    double f_max = 0.0;
    for (const Vec3& f : forces(m, x)) f_max = std::max(f_max, f.norm());
    EXPECT_LT(std::abs(E), 1e-12 * E_ref) << "trial " << trial;
    EXPECT_LT(f_max, 1e-10 * f_ref) << "trial " << trial;
  }
}

// Rigid 3D rotation and translation of a bent configuration change neither the energy nor
// the forces (which rotate with the sheet).
TEST(Bending, RigidMotionInvariance) {
  const Sheet s = lattice_sheet(8, 6, 0.4, 0.3, 0.3, 41);
  const BendingModel m = build_bending(s.triangles, s.uv, 3e-4, 1e-4);
  const Vec3List x = add_noise(roll(s, 7.0, 0.8), 0.1 * s.spacing, 42);
  const double E = bending_energy(m, x);
  const Vec3List f = forces(m, x);
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 R =
        Eigen::Quaterniond(uni(rng), uni(rng), uni(rng), uni(rng)).normalized().toRotationMatrix();
    const Vec3 t(10 * uni(rng), 10 * uni(rng), 10 * uni(rng));
    Vec3List y;
    for (const Vec3& p : x) y.push_back(R * p + t);
    EXPECT_NEAR(bending_energy(m, y), E, 1e-10 * E);
    const Vec3List g = forces(m, y);
    double err = 0.0, scale = 0.0;
    for (size_t i = 0; i < f.size(); ++i) {
      err = std::max(err, (g[i] - R * f[i]).norm());
      scale = std::max(scale, f[i].norm());
    }
    EXPECT_LT(err, 1e-9 * scale);
  }
}

// ---------------------------------------------------------------------------------------
// Known answer: a sheet rolled on a cylinder of curvature k has energy B/2 k^2 A.

struct Roll {
  const char* name;
  double phi;  // direction of curvature in the rest plane, rad from u
};
const Roll kRolls[] = {{"along u", 0.0},
                       {"along v", kPi / 2},
                       {"diagonal", kPi / 4},
                       {"anti-diagonal", 3 * kPi / 4},
                       {"30 deg", kPi / 6}};

TEST(Bending, CylinderEnergyOnIrregularMeshes) {
  const double B = 2e-5;  // N*m
  struct Case {
    const char* name;
    Sheet sheet;
  };
  const Case cases[] = {
      {"jittered grid 24x16, random diagonals", grid_sheet(24, 16, 0.6, 0.4, 0.2, true, 51)},
      {"jittered lattice 24x18", lattice_sheet(24, 18, 0.6, 0.4, 0.3, 52)},
      {"regular grid 24x16, one diagonal", grid_sheet(24, 16, 0.6, 0.4, 0.0, false, 53)}};
  for (const Case& c : cases) {
    const BendingModel m = build_bending(c.sheet.triangles, c.sheet.uv, B, -1.0);
    std::printf("  %s (%zu triangles, h = %.3f m, %d boundary / %d fallback stencils)\n", c.name,
                c.sheet.triangles.size(), c.sheet.spacing, m.boundary_stencils,
                m.fallback_stencils);
    for (double k : {2.0, 5.0, 10.0}) {  // 1/m; k = 10 rolls the 0.6 m side over 344 deg
      std::printf("    k = %4.1f 1/m (k h = %.2f):", k, k * c.sheet.spacing);
      for (const Roll& r : kRolls) {
        const double err = relative_energy_error(m, c.sheet, B, k, r.phi);
        std::printf("  %s %+.2f%%", r.name, 100 * err);
        EXPECT_LT(std::abs(err), 0.03) << c.name << ", " << r.name << ", k = " << k;
      }
      std::printf("\n");
    }
  }
}

// A uniformly bent sheet with free edges: the whole sheet, its boundary triangles included,
// rolled onto a cylinder of radius R holds B/(2 R^2) times its area, on each kind of mesh a
// scene gets: union jack (Tissu's regular rectangle), one diagonal, and Tissu's irregular
// Delaunay rectangle.
Sheet sheet_of(const TriMesh& mesh) {
  Sheet s;
  s.triangles = mesh.triangles;
  s.uv = mesh.rest_uv;
  double edges = 0.0;
  for (const Tri& t : s.triangles) {
    for (int k = 0; k < 3; ++k) edges += (s.uv[t[k]] - s.uv[t[(k + 1) % 3]]).norm();
  }
  s.spacing = edges / (3.0 * s.triangles.size());
  finish(s);
  return s;
}

TEST(Bending, UniformlyBentSheetWithFreeEdges) {
  const double B = 2e-5;  // N*m
  struct Case {
    const char* name;
    Sheet sheet;
  };
  const Case cases[] = {
      {"union jack", sheet_of(generate_rectangle(0.6, 0.4, 1200, false, 0))},
      {"one diagonal", grid_sheet(30, 20, 0.6, 0.4, 0.0, false, 0)},
      {"irregular", sheet_of(generate_rectangle(0.6, 0.4, 1200, true, 3))}};
  for (const Case& c : cases) {
    const BendingModel m = build_bending(c.sheet.triangles, c.sheet.uv, B, -1.0);
    std::printf("  %-12s (%zu triangles, mean edge %.3f m):", c.name, c.sheet.triangles.size(),
                c.sheet.spacing);
    for (double R : {0.5, 0.2, 0.1}) {  // m
      for (const Roll& r : kRolls) {
        const double E = bending_energy(m, roll(c.sheet, 1.0 / R, r.phi));
        const double exact = B / (2 * R * R) * c.sheet.area;
        if (r.phi == 0.0) std::printf("  R = %.1f m %+.2f%%", R, 100 * (E - exact) / exact);
        EXPECT_NEAR(E, exact, 0.03 * exact) << c.name << ", " << r.name << ", R = " << R;
      }
    }
    std::printf("\n");
  }
}

// The same physical bend has the same energy on a coarse and a fine irregular mesh.
TEST(Bending, CylinderEnergyIsResolutionIndependent) {
  const double B = 2e-5, k = 5.0;
  const Sheet coarse = grid_sheet(9, 6, 0.6, 0.4, 0.2, true, 61);
  const Sheet fine = grid_sheet(36, 24, 0.6, 0.4, 0.2, true, 62);
  const Sheet fine_lattice = lattice_sheet(36, 27, 0.6, 0.4, 0.3, 63);
  const BendingModel mc = build_bending(coarse.triangles, coarse.uv, B, -1.0);
  const BendingModel mf = build_bending(fine.triangles, fine.uv, B, -1.0);
  const BendingModel ml = build_bending(fine_lattice.triangles, fine_lattice.uv, B, -1.0);
  for (const Roll& r : kRolls) {
    const double Ec = bending_energy(mc, roll(coarse, k, r.phi));
    const double Ef = bending_energy(mf, roll(fine, k, r.phi));
    const double El = bending_energy(ml, roll(fine_lattice, k, r.phi));
    std::printf(
        "  %-13s coarse %zu tris %.4e J, fine %zu tris %.4e J (%+.2f%%), "
        "fine lattice %.4e J (%+.2f%%)\n",
        r.name, coarse.triangles.size(), Ec, fine.triangles.size(), Ef, 100 * (Ec - Ef) / Ef, El,
        100 * (Ec - El) / El);
    EXPECT_NEAR(Ec, Ef, 0.03 * Ef) << r.name;
    EXPECT_NEAR(Ec, El, 0.03 * El) << r.name;
  }
}

// Non-uniform curvature: the sheet bent (isometrically) along an Euler spiral, curvature
// kappa(s) = k0 + k1 s along the rest direction d, straight along the other direction.
// Energy B/2 int kappa^2 dA (integrated exactly: kappa^2 is quadratic, the edge-midpoint
// rule is exact for quadratics on triangles). Checks accuracy and convergence when the
// curvature varies (and changes sign) across the sheet.
Vec3List spiral(const Sheet& s, double k0, double k1, double phi, double& exact_integral) {
  const Vec2 d(std::cos(phi), std::sin(phi)), a(-std::sin(phi), std::cos(phi));
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : s.uv) c += p;
  c /= static_cast<double>(s.uv.size());
  // Curve gamma(s) = int_0^s (cos theta, sin theta), theta = k0 s + k1 s^2 / 2, by
  // composite Simpson with 400 intervals (error far below the tested tolerance).
  auto gamma = [&](double sd) {
    const int n = 400;
    const double h = sd / n;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int i = 0; i <= n; ++i) {
      const double t = i * h, theta = k0 * t + 0.5 * k1 * t * t;
      const double wgt = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      sum += wgt * Eigen::Vector2d(std::cos(theta), std::sin(theta));
    }
    return Eigen::Vector2d(sum * h / 3.0);
  };
  Vec3List x;
  for (const Vec2& p : s.uv) {
    const Eigen::Vector2d g = gamma(d.dot(p - c));
    x.emplace_back(g.x(), a.dot(p - c), g.y());
  }
  exact_integral = 0.0;
  for (const Tri& t : s.triangles) {
    const double area = signed_area(s.uv[t[0]], s.uv[t[1]], s.uv[t[2]]);
    for (int i = 0; i < 3; ++i) {
      const Vec2 mid = 0.5 * (s.uv[t[i]] + s.uv[t[(i + 1) % 3]]);
      const double kappa = k0 + k1 * d.dot(mid - c);
      exact_integral += area / 3.0 * kappa * kappa;
    }
  }
  return x;
}

TEST(Bending, VaryingCurvatureConverges) {
  const double B = 2e-5, k0 = 4.0, k1 = 30.0;  // kappa from -5 to 13 1/m across the sheet
  double previous = 1.0;                       // the first mesh only has to be within 40%
  for (int n : {12, 24, 48}) {
    const Sheet s = grid_sheet(n, 2 * n / 3, 0.6, 0.4, 0.2, true, 100 + n);
    const BendingModel m = build_bending(s.triangles, s.uv, B, -1.0);
    double worst = 0.0;
    std::printf("  Euler spiral, %4zu triangles:", s.triangles.size());
    for (const Roll& r : kRolls) {
      double integral = 0.0;
      const Vec3List x = spiral(s, k0, k1, r.phi, integral);
      const double exact = 0.5 * B * integral;
      const double err = (bending_energy(m, x) - exact) / exact;
      std::printf("  %s %+.2f%%", r.name, 100 * err);
      worst = std::max(worst, std::abs(err));
    }
    std::printf("\n");
    // Max curvature times spacing: 0.65, 0.33, 0.16. The error must fall by at least 2.5
    // per halving of the spacing (it is second order, ~4) and be below 3% from n = 24.
    if (n >= 24) {
      EXPECT_LT(worst, 0.03) << n;
    }
    EXPECT_LT(worst, previous / 2.5) << "no convergence at n = " << n;
    previous = worst;
  }
}

// Orthotropic: curving the weft (u) yarns costs B_weft, the warp (v) yarns B_warp, and a
// bend at angle phi from u costs B_weft cos^2 phi + B_warp sin^2 phi.
TEST(Bending, AnisotropicRigidities) {
  const double B_weft = 1e-5, B_warp = 5e-5, k = 4.0;
  const Sheet s = grid_sheet(24, 16, 0.6, 0.4, 0.2, true, 71);
  const BendingModel m = build_bending(s.triangles, s.uv, B_weft, B_warp);
  for (const Roll& r : kRolls) {
    const double c = std::cos(r.phi), sn = std::sin(r.phi);
    const double B_phi = B_weft * c * c + B_warp * sn * sn;
    const double err = relative_energy_error(m, s, B_phi, k, r.phi);
    std::printf("  %-13s B(phi) = %.2e N*m, energy error %+.2f%%\n", r.name, B_phi, 100 * err);
    EXPECT_LT(std::abs(err), 0.03) << r.name;
  }
  const double ratio = bending_energy(m, roll(s, k, kPi / 2)) / bending_energy(m, roll(s, k, 0));
  EXPECT_NEAR(ratio, B_warp / B_weft, 0.03 * B_warp / B_weft);
}

// Needles and caps: every patch that interpolates such a triangle's own corners has huge
// weights (a slope measured across a tiny height), which would make a few modes very
// stiff (explicit time steps collapse). Least-squares patches replace them; the kernel
// stays exactly affine, the cylinder energy stays right and the stiffest mode stays
// close to that of a regular mesh.
TEST(Bending, NeedleAndCapTriangles) {
  const double B = 1e-5;
  const Sheet bad = sliver_sheet(17, 12, 0.4, 0.3);
  const Sheet good = grid_sheet(16, 12, 0.4, 0.3, 0.0, false, 1);
  auto stiffest = [&](const Sheet& s, const BendingModel& m) {
    // Largest eigenvalue of M^-1/2 Q M^-1/2, lumped masses of unit areal density, in units
    // of B / h^4: omega_max^2 rho_A h^4 / B.
    Eigen::VectorXd mass = Eigen::VectorXd::Zero(m.num_vertices);
    for (const Tri& t : s.triangles) {
      const double a = signed_area(s.uv[t[0]], s.uv[t[1]], s.uv[t[2]]);
      for (int i = 0; i < 3; ++i) mass[t[i]] += a / 3.0;
    }
    const Eigen::VectorXd scale = mass.cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd K =
        scale.asDiagonal() * Eigen::MatrixXd(m.stiffness) * scale.asDiagonal();
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
    return std::make_pair(eig, eig.maxCoeff() * std::pow(s.spacing, 4) / B);
  };
  const BendingModel mb = build_bending(bad.triangles, bad.uv, B, -1.0);
  const BendingModel mg = build_bending(good.triangles, good.uv, B, -1.0);
  const auto [eig_bad, stiff_bad] = stiffest(bad, mb);
  const auto [eig_good, stiff_good] = stiffest(good, mg);
  std::printf(
      "  needles and caps: %d least-squares, %d fallback stencils; stiffest mode "
      "omega^2 rho h^4 / B = %.0f (regular grid: %.0f)\n",
      mb.least_squares_stencils, mb.fallback_stencils, stiff_bad, stiff_good);
  EXPECT_GT(mb.least_squares_stencils, 0);
  EXPECT_LT(stiff_bad, 3.0 * stiff_good);
  const double top = eig_bad.maxCoeff();
  EXPECT_LT(std::abs(eig_bad[2]), 1e-12 * top);
  EXPECT_GT(eig_bad[3], 1e-7 * top);
  for (const Roll& r : kRolls) {
    const double err = relative_energy_error(mb, bad, B, 5.0, r.phi);
    std::printf("    cylinder k = 5 1/m %-13s energy error %+.2f%%\n", r.name, 100 * err);
    EXPECT_LT(std::abs(err), 0.03) << r.name;
  }
}

// Q is assembled row by row from the stencils; it must be the matrix (same pattern, same
// bits) that a triplet list in stencil order gives, on meshes with boundaries, clamped
// triangles and anisotropic rigidities.
TEST(Bending, StiffnessIsTheSumOfTheStencilTerms) {
  const TriMesh irregular = generate_rectangle(0.5, 0.3, 900, true, 5);
  const TriMesh disk = generate_disk(0.15, 700, true, 2);
  const Sheet grid = grid_sheet(9, 7, 0.3, 0.2, 0.25, true, 17);
  struct Case {
    TriList triangles;
    Vec2List uv;
  };
  for (const Case& m : {Case{irregular.triangles, irregular.rest_uv},
                        Case{disk.triangles, disk.rest_uv}, Case{grid.triangles, grid.uv}}) {
    std::vector<uint8_t> pinned(m.uv.size(), 0);
    for (size_t v = 0; v < m.uv.size(); ++v) pinned[v] = m.uv[v].x() < m.uv[0].x() + 0.03;
    const BendingModel model = build_bending(m.triangles, m.uv, 2e-4, 5e-5, pinned);
    ASSERT_GT(model.clamped_triangles, 0);
    const double c_uu = model.bending_weft, c_vv = model.bending_warp, c_uv = 4 * model.twist;
    std::vector<Eigen::Triplet<double>> entries;
    for (const BendingStencil& st : model.stencils) {
      for (size_t a = 0; a < st.vertex.size(); ++a) {
        for (size_t b = 0; b < st.vertex.size(); ++b) {
          entries.emplace_back(st.vertex[a], st.vertex[b],
                               st.area * (c_uu * st.w_uu[a] * st.w_uu[b] +
                                          c_vv * st.w_vv[a] * st.w_vv[b] +
                                          c_uv * st.w_uv[a] * st.w_uv[b]));
        }
      }
    }
    Eigen::SparseMatrix<double, Eigen::RowMajor> expected(model.num_vertices, model.num_vertices);
    expected.setFromTriplets(entries.begin(), entries.end());
    ASSERT_EQ(model.stiffness.nonZeros(), expected.nonZeros());
    for (int r = 0; r < model.num_vertices; ++r) {
      Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator got(model.stiffness, r);
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator want(expected, r); want;
           ++want, ++got) {
        ASSERT_TRUE(got) << "row " << r;
        ASSERT_EQ(got.col(), want.col()) << "row " << r;
        ASSERT_EQ(got.value(), want.value()) << "row " << r << ", column " << want.col();
      }
    }
  }
}

TEST(Bending, NegativeWarpMeansIsotropic) {
  const Sheet s = grid_sheet(5, 4, 0.2, 0.2, 0.2, true, 81);
  const BendingModel a = build_bending(s.triangles, s.uv, 3e-4, -1.0);
  const BendingModel b = build_bending(s.triangles, s.uv, 3e-4, 3e-4);
  EXPECT_EQ(a.bending_warp, 3e-4);
  EXPECT_EQ((Eigen::MatrixXd(a.stiffness) - Eigen::MatrixXd(b.stiffness)).norm(), 0.0);
  // The energy is linear in the rigidities.
  const BendingModel c = build_bending(s.triangles, s.uv, 6e-4, -1.0);
  const Vec3List x = roll(s, 3.0, 0.2);
  EXPECT_NEAR(bending_energy(c, x), 2 * bending_energy(a, x), 1e-12 * bending_energy(c, x));
}

TEST(Bending, RejectsBadInput) {
  Sheet s = grid_sheet(2, 2, 0.1, 0.1, 0.0, false, 91);
  EXPECT_THROW(build_bending(s.triangles, s.uv, -1.0, -1.0), InputError);
  TriList bad = s.triangles;
  bad[0][1] = 100;
  EXPECT_THROW(build_bending(bad, s.uv, 1e-4, -1.0), InputError);
  Vec2List flat = s.uv;
  flat[s.triangles[0][0]] = flat[s.triangles[0][1]];  // collapse a triangle
  EXPECT_THROW(build_bending(s.triangles, flat, 1e-4, -1.0), InputError);
  const BendingModel m = build_bending(s.triangles, s.uv, 1e-4, -1.0);
  Vec3List too_short(3, Vec3::Zero());
  EXPECT_THROW(bending_energy(m, too_short), std::invalid_argument);
}

// A tiny mesh (two triangles, one hinge) cannot determine a quadratic patch: the stencils
// fall back to minimum-norm weights, which still vanish on flat configurations and resist
// folding about the hinge.
TEST(Bending, SingleHingeResistsFolding) {
  const TriList tris = {Tri(0, 1, 2), Tri(0, 2, 3)};
  const Vec2List uv = {Vec2(0, 0), Vec2(0.1, 0), Vec2(0.1, 0.1), Vec2(0, 0.1)};
  const BendingModel m = build_bending(tris, uv, 1e-4, -1.0);
  Vec3List x = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0), Vec3(0, 0.1, 0)};
  EXPECT_NEAR(bending_energy(m, x), 0.0, 1e-18);
  x[1].z() = 0.02;  // fold vertex 1 about the diagonal 0-2
  EXPECT_GT(bending_energy(m, x), 0.0);
  const Vec3List f = forces(m, x);
  EXPECT_LT(f[1].z(), 0.0);  // pushed back towards flat
}

}  // namespace
}  // namespace tissu
