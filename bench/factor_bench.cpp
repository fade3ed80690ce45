// Sparse Cholesky factorizations of an implicit step's matrix, CHOLMOD supernodal against
// simplicial, with AMD and nested-dissection orderings: non-zeros of L, flops, and
// processor milliseconds per numeric factorization and per solve (median of repeats), the
// two operations each Newton iteration of an implicit step pays for (docs/implicit.md).
// The matrix is M - beta df/dv - beta^2 df/dx (beta = 1/60 s) of the scene's cloth at its
// start, without bending (the preconditioner drops bending's second-ring couplings, so its
// pattern is the membrane's), over the free vertices.
//   ./build/bench/tissu_factor_bench [SCENE] [--repeats N]     (default scenes/demo.json, 30)
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>
#include <memory>
#include <vector>

#include "physics/block_triplets.h"
#include "physics/forces.h"
#include "physics/serial_openmp.h"
#include "scene/scene.h"

using namespace tissu;
using Sparse = Eigen::SparseMatrix<double>;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double ms_since(std::clock_t t0) { return 1e3 * static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC; }

// The step's matrix for beta = dt, lower triangle, free coordinates only.
Sparse step_matrix(const Model& model, const State& state) {
  Model membrane_only = model;
  membrane_only.bending = nullptr;
  BlockTriplets dfdx, dfdv;
  compute_force_jacobian(membrane_only, state.x, state.v, state.t, /*project_psd=*/true, dfdx,
                         dfdv);
  const int n = model.num_vertices();
  const double beta = 1.0 / 60.0;  // s
  Sparse A = -beta * beta * dfdx.to_sparse(n) - beta * dfdv.to_sparse(n);
  std::vector<int> index(3 * n, -1);
  int free = 0;
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3 && !model.pinned[i]; ++c) index[3 * i + c] = free++;
  }
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < A.outerSize(); ++k) {
    for (Sparse::InnerIterator it(A, k); it; ++it) {
      const int r = index[it.row()], c = index[it.col()];
      if (r >= 0 && c >= 0 && r >= c) entries.emplace_back(r, c, it.value());
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3 && !model.pinned[i]; ++c) {
      entries.emplace_back(index[3 * i + c], index[3 * i + c], model.mass[i]);
    }
  }
  Sparse lower(free, free);
  lower.setFromTriplets(entries.begin(), entries.end());
  return lower;
}

// One factor kind and ordering, timed in turn with the others (so that a change of the
// machine's load falls on all of them alike).
struct Variant {
  const char* name;
  int ordering;
  virtual ~Variant() = default;
  virtual cholmod_common& common() = 0;
  virtual void analyze(const Sparse& lower) = 0;
  virtual void factorize(const Sparse& lower) = 0;
  virtual bool ok() const = 0;
  virtual Eigen::VectorXd solve(const Eigen::VectorXd& b) const = 0;
  std::vector<double> factor_ms, solve_ms;
};

template <class Factor>
struct VariantOf : Variant {
  Factor factor;
  cholmod_common& common() override { return factor.cholmod(); }
  void analyze(const Sparse& lower) override { factor.analyzePattern(lower); }
  void factorize(const Sparse& lower) override { factor.factorize(lower); }
  bool ok() const override { return factor.info() == Eigen::Success; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return factor.solve(b); }
};

template <class Factor>
std::unique_ptr<Variant> variant(const char* name, int ordering) {
  auto v = std::make_unique<VariantOf<Factor>>();
  v->name = name;
  v->ordering = ordering;
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = "scenes/demo.json";
  int repeats = 30;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (!a.empty() && a[0] != '-') {
      path = a;
    } else {
      std::fprintf(stderr, "usage: %s [SCENE] [--repeats N]\n", argv[0]);
      return 2;
    }
  }
  Simulation sim;
  try {
    sim = build_simulation(load_scene(path, {}));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  const SerialOpenMpScope on_this_thread;  // CHOLMOD as the solver runs it
  const Sparse lower = step_matrix(sim.model, sim.state);
  std::printf("%s: %ld unknowns, %ld non-zeros in the lower triangle\n", path.c_str(),
              static_cast<long>(lower.rows()), static_cast<long>(lower.nonZeros()));
  std::printf("%-12s %-8s %10s %10s %10s %10s\n", "factor", "ordering", "nnz(L)", "Mflop",
              "factor ms", "solve ms");
  using Supernodal = Eigen::CholmodSupernodalLLT<Sparse, Eigen::Lower>;
  using Simplicial = Eigen::CholmodSimplicialLLT<Sparse, Eigen::Lower>;
  std::vector<std::unique_ptr<Variant>> variants;
  for (int ordering : {CHOLMOD_AMD, CHOLMOD_NESDIS}) {
    variants.push_back(variant<Supernodal>("supernodal", ordering));
    variants.push_back(variant<Simplicial>("simplicial", ordering));
  }
  for (auto& v : variants) {
    v->common().nmethods = 1;
    v->common().method[0].ordering = v->ordering;
    v->analyze(lower);
  }
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(lower.rows());
  for (int k = 0; k < repeats; ++k) {
    for (auto& v : variants) {
      std::clock_t t0 = std::clock();
      v->factorize(lower);
      v->factor_ms.push_back(ms_since(t0));
      for (int s = 0; s < 5; ++s) {
        t0 = std::clock();
        const Eigen::VectorXd x = v->solve(b);
        v->solve_ms.push_back(ms_since(t0));
      }
    }
  }
  for (auto& v : variants) {
    const char* ordering = v->ordering == CHOLMOD_AMD ? "AMD" : "NESDIS";
    if (!v->ok()) {
      std::printf("%-12s %-8s failed\n", v->name, ordering);
      continue;
    }
    std::printf("%-12s %-8s %10.0f %10.1f %10.2f %10.3f\n", v->name, ordering, v->common().lnz,
                v->common().fl / 1e6, median(v->factor_ms), median(v->solve_ms));
  }
  return 0;
}
