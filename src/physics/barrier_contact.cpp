#include "physics/barrier_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/cloth_contact.h"
#include "physics/system_matrix.h"

namespace tissu {

double barrier_energy(double d, double dhat, double kappa) {
  if (d <= 0.0) return std::numeric_limits<double>::infinity();
  if (d >= dhat) return 0.0;
  const double e = d - dhat;
  return -kappa * e * e * std::log(d / dhat);
}

double barrier_derivative(double d, double dhat, double kappa) {
  if (d >= dhat) return 0.0;
  const double e = d - dhat;
  return -kappa * (2.0 * e * std::log(d / dhat) + e * e / d);
}

double barrier_second_derivative(double d, double dhat, double kappa) {
  if (d >= dhat) return 0.0;
  const double e = d - dhat;
  return -kappa * (2.0 * std::log(d / dhat) + 4.0 * e / d - e * e / (d * d));
}

double barrier_stiffness(double mass, double dt) { return mass / (dt * dt); }

namespace {

// The step in kappa = m / dt^2, s.
double stiffness_step(const Model& model) {
  return model.implicit.barrier_stiffness_dt > 0.0 ? model.implicit.barrier_stiffness_dt
                                                   : model.dt;
}

// kappa of a mesh feature pair or self pair: that of the mean mass of its free vertices,
// kg/s^2, for the step dt (s).
double pair_stiffness(const Model& model, const PairGap& g, double dt) {
  double mass = 0.0;
  int free = 0;
  for (int k = 0; k < g.count; ++k) {
    if (model.pinned[g.vertices[k]]) continue;
    mass += model.mass[g.vertices[k]];
    ++free;
  }
  return free > 0 ? barrier_stiffness(mass / free, dt) : 0.0;
}

// Times make_feasible draws the guess back before it gives up on the mesh feature pairs
// (each round stops short of the first touch, so one usually suffices).
constexpr int kFeasibleRounds = 4;

// Rounds of hold_touching_pairs: each holds at x_n the vertices of the pairs whose paths
// still touch, which can leave a pair of one held vertex and moving ones touching. (Drawn
// back to 0.9 of each pair's touch instead, with x_n in the last round, the thrown sheet
// of docs/implicit.md took 3% fewer Newton iterations at 1/60 s, 12% more at 1/30 s and
// the silk fold 54% more.)
constexpr int kHoldRounds = 8;

// Rounds of separate_laid_layers: each opens the pairs found at its start as far as their
// paths allow; the next finds those still closer than dhat.
constexpr int kSeparationRounds = 8;

}  // namespace

double barrier_distance(const Model& model) {
  if (model.implicit.barrier_distance > 0.0) return model.implicit.barrier_distance;
  return kBarrierEdgeFraction * mean_rest_edge(model);
}

double gap_distance(const PlacedObstacle& obstacle, const Vec3& p, double reach) {
  const Obstacle& ob = *obstacle.obstacle;
  Vec3 normal;
  return ob.signed_distance_from(p, obstacle.center, &normal, obstacle.rotation,
                                 reach + ob.thickness) -
         ob.thickness;
}

Gap obstacle_gap(const PlacedObstacle& obstacle, const Vec3& p) {
  const Obstacle& ob = *obstacle.obstacle;
  const SurfacePoint s = obstacle.closest(p);
  Gap g;
  g.d = s.distance - ob.thickness;
  g.normal = s.normal;
  g.surface_velocity = s.velocity;
  const Mat3 across = Mat3::Identity() - s.normal * s.normal.transpose();
  switch (ob.kind) {
    case ObstacleKind::Sphere: {
      // distance |p - c| - R: Hessian (I - n n^T) / |p - c|.
      const double r = (p - obstacle.center).norm();
      if (r > 0.0) g.curvature = across / r;
      break;
    }
    case ObstacleKind::Cylinder: {
      const Vec3 q = p - obstacle.center;
      const double z = q.dot(ob.axis);
      const Vec3 radial = q - z * ob.axis;
      const double rho = radial.norm();
      if (rho <= 0.0 || s.distance <= 0.0) break;
      const Vec3 t = ob.axis.cross(radial / rho);  // the circle's tangent
      if (std::fabs(z) <= ob.half_length) {
        // Side: distance rho - R, Hessian t t^T / rho.
        g.curvature = t * t.transpose() / rho;
      } else if (rho > ob.radius) {
        // Rim: distance to the rim circle, Hessian (I - n n^T - (R / rho) t t^T) / dist.
        g.curvature = (across - (ob.radius / rho) * t * t.transpose()) / s.distance;
      }  // cap: a plane, no curvature
      break;
    }
    case ObstacleKind::Plane:
    case ObstacleKind::Mesh:
      break;
  }
  return g;
}

BarrierTerm vertex_barrier(const PlacedObstacle& obstacle, const Vec3& p, double kappa,
                           double dhat, bool psd) {
  BarrierTerm term;
  if (gap_distance(obstacle, p, dhat) >= dhat) return term;
  const Gap g = obstacle_gap(obstacle, p);
  term.energy = barrier_energy(g.d, dhat, kappa);
  if (g.d <= 0.0) return term;
  const double slope = barrier_derivative(g.d, dhat, kappa);  // N, negative
  term.gradient = slope * g.normal;
  term.hessian = barrier_second_derivative(g.d, dhat, kappa) * g.normal * g.normal.transpose();
  if (!psd) term.hessian += slope * g.curvature;
  return term;
}

Vec3 NormalDamping::force(const Vec3& v) const {
  return -coefficient * (v - surface_velocity).dot(normal) * normal;
}

Mat3 NormalDamping::velocity_jacobian() const {
  return -coefficient * normal * normal.transpose();
}

double NormalDamping::dissipation(const Vec3& v) const {
  return -force(v).dot(v - surface_velocity);
}

double NormalDamping::potential(const Vec3& v) const {
  const double approach = (v - surface_velocity).dot(normal);  // m/s
  return 0.5 * coefficient * approach * approach;
}

NormalDamping vertex_damping(const PlacedObstacle& obstacle, const Vec3& p, double kappa,
                             double mass, double dhat, double zeta) {
  const double d = gap_distance(obstacle, p, dhat);
  if (d <= 0.0 || d >= dhat) return NormalDamping{};
  const Gap g = obstacle_gap(obstacle, p);
  NormalDamping damping{g.normal, g.surface_velocity, 0.0};
  const double stiffness = barrier_second_derivative(g.d, dhat, kappa);  // N/m
  damping.coefficient = 2.0 * zeta * std::sqrt(mass * std::max(0.0, stiffness));
  return damping;
}

double first_touch(const PlacedObstacle& obstacle, const Vec3& p, const Vec3& u) {
  const Obstacle& ob = *obstacle.obstacle;
  const double d0 = gap_distance(obstacle, p, u.norm());
  if (d0 <= 0.0) return 0.0;
  switch (ob.kind) {
    case ObstacleKind::Plane: {
      const double approach = -u.dot(ob.axis);  // m per unit of t
      return approach > d0 ? d0 / approach : 1.0;
    }
    case ObstacleKind::Sphere: {
      // |q + t u| = R + thickness: a t^2 + b t + c = 0 with c > 0 outside.
      const Vec3 q = p - obstacle.center;
      const double reach = ob.radius + ob.thickness;
      const double a = u.squaredNorm(), b = 2.0 * q.dot(u), c = q.squaredNorm() - reach * reach;
      const double disc = b * b - 4.0 * a * c;
      if (b >= 0.0 || disc < 0.0) return 1.0;
      return std::min(1.0, 2.0 * c / (-b + std::sqrt(disc)));  // the smaller root, stably
    }
    default: {
      // Conservative advancement: the gap falls by at most |u| per unit of t.
      const double speed = u.norm();
      double t = 0.0, d = d0;
      for (int k = 0; k < 100 && d > 1e-3 * d0; ++k) {
        t += d / speed;
        if (t >= 1.0) return 1.0;
        d = gap_distance(obstacle, p + t * u, speed);
      }
      return std::max(0.0, t);
    }
  }
}

void BarrierContact::begin(const Model& model, const Vec3List& x_n, const Vec3List& x_end_base,
                           double beta, double beta_end, double t, double t_end) {
  const bool obstacles = model.implicit.contact == ContactModel::Barrier;
  // Under either model it takes what the collision stage handles: the cloth against itself
  // and a mesh's corners and edges.
  enabled_ = obstacles || needs_cloth_contact(model);
  takes_obstacles_ = obstacles;
  placed_.clear();
  placed_start_.clear();
  friction_.clear();
  pair_friction_.clear();
  damping_.clear();
  if (!enabled_) return;
  model_ = &model;
  x_start_ = &x_n;
  x_end_base_ = &x_end_base;
  beta_ = beta;
  beta_end_ = beta_end;
  dhat_ = barrier_distance(model);
  const int n = model.num_vertices();
  kappa_.resize(n);
  stiffness_dt_ = stiffness_step(model);
  for (int i = 0; i < n; ++i) kappa_[i] = barrier_stiffness(model.mass[i], stiffness_dt_);
  features_.begin(model, t, t_end);
  self_.begin(model);
  coupling_.clear();
  pair_friction_.clear();
  // Lagged friction of a pair within dhat at x_n: mu times its normal force there over the
  // step, on its relative velocity against `surface` (m/s).
  const auto add_pair_friction = [&](const PairGap& g, double mu, const Vec3& surface) {
    if (mu == 0.0 || g.d <= 0.0 || g.d >= dhat_) return;
    const double kappa = pair_stiffness(model, g, stiffness_step(model));
    const double normal_impulse =
        -beta_ * edge_mollifier(g) * barrier_derivative(g.d, dhat_, kappa);  // kg*m/s
    pair_friction_.push_back({g, SlidingFriction{g.normal, surface, mu * normal_impulse}});
  };
  if (self_.active() && model.self_collision->friction > 0.0) {
    // Between layers: relative velocities, no surface.
    self_.find_pairs(x_n, x_n, dhat_);
    const double mu = model.self_collision->friction;
    self_.for_each_gap(x_n, [&](const PairGap& g) { add_pair_friction(g, mu, Vec3::Zero()); });
  }
  if (obstacles && features_.active()) {
    // On a mesh's corners and edges, where the barrier holds the cloth against them (the
    // constraints' own friction acts at the vertices there), with the obstacles where they
    // start the step.
    features_.find_pairs(x_n, x_n, dhat_, /*from_start=*/true);
    features_.for_each_contact_at_start(x_n, t, [&](const PairGap& g, int o, const Vec3& surface) {
      add_pair_friction(g, model.obstacles[o].friction, surface);
    });
  }
  for (const Obstacle& ob : model.obstacles) {
    if (!obstacles) break;
    placed_.push_back(place_obstacle(ob, t_end));
    placed_start_.push_back(place_obstacle(ob, t));
    if (ob.friction == 0.0) continue;
    // Lagged friction: the barrier's normal force at x_n, and the damping's that stopped a
    // landing in the last step, over the step, as J_n.
    const PlacedObstacle& start = placed_start_.back();
    const int o = static_cast<int>(placed_.size()) - 1;
    landing_scratch_.assign(landings_.empty() ? 0 : n, 0.0);
    for (const LandingImpulse& l : landings_) {
      if (l.obstacle == o && l.vertex < n) landing_scratch_[l.vertex] = l.impulse;
    }
    for (int i = 0; i < n; ++i) {
      if (model.pinned[i]) continue;
      const double d = gap_distance(start, x_n[i], dhat_);
      if (d <= 0.0 || d >= dhat_) continue;
      const Gap g = obstacle_gap(start, x_n[i]);
      const double landing = landing_scratch_.empty() ? 0.0 : landing_scratch_[i];  // kg*m/s
      const double normal_impulse =
          std::max(0.0, landing - beta_ * barrier_derivative(g.d, dhat_, kappa_[i]));  // kg*m/s
      friction_.push_back({i, SlidingFriction{g.normal, g.surface_velocity,
                                              ob.friction * normal_impulse}});
    }
  }
  if (placed_.empty() && !has_pairs()) enabled_ = false;
}

double holding_gap(double force, double dhat, double kappa) {
  if (!(force > 0.0)) return dhat;
  double below = 0.0, above = dhat;  // -b'(below) > force >= -b'(above)
  for (int k = 0; k < 50; ++k) {
    const double d = 0.5 * (below + above);
    (-barrier_derivative(d, dhat, kappa) > force ? below : above) = d;
  }
  return above;
}

int lift_to_holding_gaps(const Model& model, Vec3List& x, const Vec3List& f, double t) {
  const double dhat = barrier_distance(model), dt = stiffness_step(model);
  int lifted = 0;
  for (const Obstacle& ob : model.obstacles) {
    const PlacedObstacle placed = place_obstacle(ob, t);
    for (int i = 0; i < model.num_vertices(); ++i) {
      if (model.pinned[i] || gap_distance(placed, x[i], dhat) >= dhat) continue;
      const Gap g = obstacle_gap(placed, x[i]);
      const double hold =
          holding_gap(-f[i].dot(g.normal), dhat, barrier_stiffness(model.mass[i], dt));
      if (g.d >= hold) continue;
      x[i] += (hold - g.d) * g.normal;
      ++lifted;
    }
  }
  return lifted;
}

int separate_laid_layers(const Model& model, Vec3List& x, double t) {
  SelfBarrier self;
  self.begin(model);
  if (!self.active()) return 0;
  const double dhat = barrier_distance(model);
  const int n = model.num_vertices();
  std::vector<PlacedObstacle> placed;
  for (const Obstacle& ob : model.obstacles) placed.push_back(place_obstacle(ob, t));
  std::vector<double> support(n);  // each vertex's gap to the nearest obstacle, m
  Vec3List move(n), target(n);     // m
  int opened = 0;
  for (int round = 0; round < kSeparationRounds; ++round) {
    for (int i = 0; i < n; ++i) {
      support[i] = INFINITY;
      for (const PlacedObstacle& o : placed) support[i] = std::min(support[i], gap_distance(o, x[i]));
    }
    // Each vertex takes the largest of the moves its pairs ask of it (all from the same x).
    std::fill(move.begin(), move.end(), Vec3::Zero());
    self.find_pairs(x, x, dhat);
    int open = 0;
    self.for_each_gap(x, [&](const PairGap& g) {
      if (g.d >= dhat) return;
      // The piece farther from the obstacles moves, or both where they are as far; a piece
      // with a pinned vertex stays. A piece moved as a whole by delta along the normal
      // changes the gap by delta (its weights sum to +1, the second's to -1).
      double nearest[2] = {INFINITY, INFINITY}, mass[2] = {0.0, 0.0};
      bool pinned[2] = {false, false};
      for (int k = 0; k < g.count; ++k) {
        const int piece = k < g.split ? 0 : 1, i = g.vertices[k];
        nearest[piece] = std::min(nearest[piece], support[i]);
        mass[piece] += model.mass[i];
        pinned[piece] = pinned[piece] || model.pinned[i];
      }
      bool moves[2] = {!pinned[0] && !(nearest[0] < nearest[1]),
                       !pinned[1] && !(nearest[1] < nearest[0])};
      if (!moves[0] && !moves[1]) return;
      const double opening = dhat - g.d;  // m
      const double share0 = !moves[1] ? 1.0 : !moves[0] ? 0.0 : mass[1] / (mass[0] + mass[1]);
      for (int k = 0; k < g.count; ++k) {
        const int piece = k < g.split ? 0 : 1, i = g.vertices[k];
        if (!moves[piece]) continue;
        const Vec3 m = (piece == 0 ? share0 * opening : -(1.0 - share0) * opening) * g.normal;
        if (m.squaredNorm() > move[i].squaredNorm()) move[i] = m;
      }
      ++open;
    });
    if (open == 0) break;
    opened += open;
    // The moves stop short of the first touch of the cloth with itself or an obstacle on
    // their straight paths, as the solve's line search does.
    for (int i = 0; i < n; ++i) target[i] = x[i] + move[i];
    self.find_pairs(x, target, dhat);
    double reach = self.first_touch(x, target);
    for (int i = 0; i < n; ++i) {
      if (move[i].isZero()) continue;
      for (const PlacedObstacle& o : placed) {
        if (gap_distance(o, x[i], dhat) > 0.0) reach = std::min(reach, first_touch(o, x[i], move[i]));
      }
    }
    const double length = reach < 1.0 ? kBarrierStepFraction * reach : 1.0;
    if (!(length > 0.0)) break;
    for (int i = 0; i < n; ++i) x[i] += length * move[i];
  }
  return opened;
}

void BarrierContact::push_out(Vec3List& v, const Vec3List& v_base,
                              const std::function<const Vec3List&()>& forces,
                              const Vec3List*& f) const {
  const double keep = 0.5 * dhat_;  // m
  for (int i = 0; i < model_->num_vertices(); ++i) {
    if (model_->pinned[i]) continue;
    for (size_t o = 0; o < placed_.size(); ++o) {
      const Vec3 x = end_position(v, i);
      if (gap_distance(placed_[o], x, keep) >= keep) continue;
      const Gap g = obstacle_gap(placed_[o], x);
      if (!f) f = &forces();
      // The impulse the barrier must give over the step for the vertex to end moving with
      // the surface along the normal (kg*m/s), and the gap where it pushes that hard.
      const double press = model_->mass[i] * (g.surface_velocity - v_base[i]).dot(g.normal) -
                           beta_ * (*f)[i].dot(g.normal);
      const double balance = holding_gap(press / beta_, dhat_, kappa_[i]);
      const double start = gap_distance(placed_start_[o], (*x_start_)[i], keep);
      const double target = std::min(keep, std::max(start, balance));
      if (g.d < target) v[i] += ((target - g.d) / beta_end_) * g.normal;
    }
  }
}

void BarrierContact::make_feasible(Vec3List& v, const Vec3List& v_base,
                                   const std::function<const Vec3List&()>& forces) {
  if (!enabled_) return;
  const Vec3List* f = nullptr;  // N, at the first close vertex: before any v changes
  push_out(v, v_base, forces, f);
  if (!has_pairs()) return;
  // Each pair's path runs from x_n, where its obstacle starts the step, to the guess, where
  // the obstacle ends it. A guess whose paths touch is drawn back toward x_n, carried by the
  // first touching obstacle's motion where x_n is near it (a still obstacle, or the cloth
  // itself: x_n).
  const Vec3List& x_n = *x_start_;
  bool paths_found = false;  // self_ holds the pairs of the paths from x_n to the guess
  for (int round = 0;; ++round) {
    const Vec3List& x_end = end_positions(v);
    features_.find_pairs(x_n, x_end, dhat_, /*from_start=*/true);
    int mesh = -1;
    double touch = features_.first_touch_over_step(x_n, x_end, &mesh);
    self_.find_pairs(x_n, x_end, dhat_);
    const double self_touch = self_.first_touch(x_n, x_end);
    if (self_touch < touch) {
      touch = self_touch;
      mesh = -1;
    }
    paths_found = touch >= 1.0;
    if (paths_found) break;
    const double keep = kBarrierStepFraction * touch;
    for (int i = 0; i < model_->num_vertices(); ++i) {
      if (model_->pinned[i]) continue;
      const Vec3 target = mesh >= 0 ? features_.carried(mesh, x_n[i], dhat_) : x_n[i];  // m
      const Vec3 stay = (target - (*x_end_base_)[i]) / beta_end_;                   // m/s
      v[i] = stay + keep * (v[i] - stay);
    }
    // Out of the obstacles again after every draw-back, the last one included: a draw-back
    // toward x_n (a self pair's) ignores a moving obstacle, and a vertex the guess leaves
    // inside one would hold the line search at length 0. A pair this push leaves crossed
    // after the last round is left out of the step (find_pairs) instead.
    push_out(v, v_base, forces, f);
    if (round + 1 == kFeasibleRounds) break;
  }
  paths_found = hold_touching_pairs(v, paths_found);
  // The pairs about the guess, for the solve's first evaluations. Self pairs found on the
  // paths to it hold every pair within dhat there unless some were left out (not apart at
  // x_n): a pair's gap falls on its path by no more than its closing bound.
  const Vec3List& x_end = end_positions(v);
  features_.find_pairs(x_end, x_end, dhat_);
  if (!paths_found || self_.left_out() > 0) self_.find_pairs(x_end, x_end, dhat_);
}

bool BarrierContact::hold_touching_pairs(Vec3List& v, bool paths_found) {
  if (!self_.active()) return paths_found;
  const Vec3List& x_n = *x_start_;
  const auto clear = [&](const Vec3& x) {
    for (const PlacedObstacle& o : placed_) {
      if (!(gap_distance(o, x) > 0.0)) return false;
    }
    return true;
  };
  for (int round = 0; round < kHoldRounds; ++round) {
    const Vec3List& x_end = end_positions(v);
    if (round > 0 || !paths_found) self_.find_pairs(x_n, x_end, dhat_);
    bool held = false;
    for (const std::array<int, 4>& pair : self_.touching_pairs(x_n, x_end)) {
      for (const int i : pair) {
        if (model_->pinned[i] || !clear(x_n[i])) continue;
        const Vec3 stay = (x_n[i] - (*x_end_base_)[i]) / beta_end_;  // m/s
        held = held || v[i] != stay;
        v[i] = stay;
      }
    }
    if (!held) return true;
  }
  return false;
}

void BarrierContact::freeze_damping(const Vec3List& v, const Vec3List& v_n) {
  damping_.clear();
  v_start_ = &v_n;
  const double zeta = enabled_ ? model_->implicit.barrier_damping : 0.0;
  if (zeta <= 0.0) return;
  for (int i = 0; i < model_->num_vertices(); ++i) {
    if (model_->pinned[i]) continue;
    const Vec3 x = end_position(v, i);
    const double largest = kMaxStepDamping * model_->mass[i] / beta_end_;  // kg/s
    for (size_t o = 0; o < placed_.size(); ++o) {
      NormalDamping law = vertex_damping(placed_[o], x, kappa_[i], model_->mass[i], dhat_, zeta);
      law.coefficient = std::min(law.coefficient, largest);
      if (law.coefficient > 0.0) damping_.push_back({i, static_cast<int>(o), law});
    }
  }
}

void BarrierContact::remember_landings(const Vec3List& v) {
  landings_.clear();
  for (const Damping& d : damping_) {
    const double force = d.law.normal.dot(d.law.force(end_velocity(v, d.vertex)));  // N
    if (force != 0.0) landings_.push_back({d.vertex, d.obstacle, beta_ * force});
  }
}

const Vec3List& BarrierContact::end_positions(const Vec3List& v) const {
  // As the step's own end positions: pinned vertices stay at x_n.
  x_end_.resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    const int k = static_cast<int>(i);
    x_end_[i] = model_->pinned[k] ? (*x_start_)[i] : end_position(v, k);
  }
  return x_end_;
}

Vec3 BarrierContact::PairFriction::relative(const Vec3List& v) const {
  Vec3 u = Vec3::Zero();
  for (int k = 0; k < pair.count; ++k) u += pair.weights[k] * v[pair.vertices[k]];
  return u;
}

void BarrierContact::add_pair_blocks(const PairGap& g, const Mat3& block, SystemMatrix& system) {
  PairMatrix hessian = PairMatrix::Zero();
  for (int k = 0; k < g.count; ++k) {
    for (int l = 0; l < g.count; ++l) {
      hessian.block<3, 3>(3 * k, 3 * l) = (g.weights[k] * g.weights[l]) * block;
    }
  }
  add_pair_hessian(g, hessian, system);
}

void BarrierContact::add_pair_hessian(const PairGap& g, const PairMatrix& hessian,
                                      SystemMatrix& system) {
  for (int k = 0; k < g.count; ++k) {
    if (model_->pinned[g.vertices[k]]) continue;
    for (int l = 0; l < g.count; ++l) {
      if (model_->pinned[g.vertices[l]]) continue;
      const Mat3 b = hessian.block<3, 3>(3 * k, 3 * l);
      if ((b.array() == 0.0).all()) continue;  // a vertex the closest points do not weigh
      const int i = g.vertices[k], j = g.vertices[l];
      if (!system.add_block_if_held(i, j, b) && k < l) {
        coupling_.add(i, j, b);  // with its transpose at (j, i)
      }
    }
  }
}

double BarrierContact::potential(const Vec3List& v) const {
  if (!enabled_) return 0.0;
  double total = 0.0;
  for (int i = 0; i < model_->num_vertices(); ++i) {
    if (model_->pinned[i]) continue;
    const Vec3 x = end_position(v, i);
    for (const PlacedObstacle& o : placed_) {
      total += barrier_energy(gap_distance(o, x, dhat_), dhat_, kappa_[i]);
    }
  }
  if (has_pairs()) {
    for_each_pair(end_positions(v), [&](const PairGap& g, double kappa) {
      total += edge_mollifier(g) * barrier_energy(g.d, dhat_, kappa);
    });
  }
  total *= beta_ / beta_end_;
  for (const Friction& f : friction_) total += f.law.potential(v[f.vertex]);
  for (const PairFriction& f : pair_friction_) total += f.law.potential(f.relative(v));
  const double weight = beta_ * beta_ / beta_end_;  // beta / a, s
  for (const Damping& d : damping_) total += weight * d.law.potential(end_velocity(v, d.vertex));
  return total;
}

template <typename Visit>
void BarrierContact::for_each_pair(const Vec3List& x, Visit visit) const {
  const auto with_stiffness = [&](const PairGap& g) {
    visit(g, pair_stiffness(*model_, g, stiffness_dt_));
  };
  features_.for_each_gap(x, with_stiffness);
  self_.for_each_gap(x, with_stiffness);
}

template <typename Visit>
void BarrierContact::for_each_term(const Vec3List& v, Visit visit) const {
  for (int i = 0; i < model_->num_vertices(); ++i) {
    if (model_->pinned[i]) continue;
    const Vec3 x = end_position(v, i);
    for (const PlacedObstacle& o : placed_) {
      const BarrierTerm b = vertex_barrier(o, x, kappa_[i], dhat_, true);
      if (b.energy > 0.0) visit(i, b);
    }
  }
}

void BarrierContact::add_impulses(const Vec3List& v, Eigen::VectorXd& rhs) const {
  if (!enabled_) return;
  for_each_term(v, [&](int i, const BarrierTerm& b) { rhs.segment<3>(3 * i) -= beta_ * b.gradient; });
  if (has_pairs()) {
    for_each_pair(end_positions(v), [&](const PairGap& g, double kappa) {
      if (g.d <= 0.0 || g.d >= dhat_) return;
      const double slope = barrier_derivative(g.d, dhat_, kappa);  // N
      // Nearly parallel edges: the mollified barrier's whole gradient (only they need it).
      const bool mollified = is_mollified(g);
      PairVector gradient;  // N
      if (mollified) gradient = mollified_gradient(g, barrier_energy(g.d, dhat_, kappa), slope);
      for (int k = 0; k < g.count; ++k) {
        if (model_->pinned[g.vertices[k]]) continue;
        rhs.segment<3>(3 * g.vertices[k]) -=
            mollified ? Vec3(beta_ * gradient.segment<3>(3 * k))
                      : Vec3((beta_ * slope * g.weights[k]) * g.normal);
      }
    });
  }
  for (const Friction& f : friction_) rhs.segment<3>(3 * f.vertex) += f.law.impulse(v[f.vertex]);
  for (const PairFriction& f : pair_friction_) {
    const Vec3 impulse = f.law.impulse(f.relative(v));  // on the relative velocity, kg*m/s
    for (int k = 0; k < f.pair.count; ++k) {
      if (model_->pinned[f.pair.vertices[k]]) continue;
      rhs.segment<3>(3 * f.pair.vertices[k]) += f.pair.weights[k] * impulse;
    }
  }
  for (const Damping& d : damping_) {
    rhs.segment<3>(3 * d.vertex) += beta_ * d.law.force(end_velocity(v, d.vertex));
  }
}

void BarrierContact::add_hessian(const Vec3List& v, SystemMatrix& system) {
  coupling_.clear();
  if (!enabled_) return;
  const double scale = beta_ * beta_end_;  // s^2
  for_each_term(v, [&](int i, const BarrierTerm& b) { system.add_diagonal(i, scale * b.hessian); });
  if (has_pairs()) {
    for_each_pair(end_positions(v), [&](const PairGap& g, double kappa) {
      if (g.d <= 0.0 || g.d >= dhat_) return;
      const double curvature = scale * barrier_second_derivative(g.d, dhat_, kappa);  // kg
      if (g.split == g.count) {  // a mesh feature pair: Gauss-Newton (mesh_barrier.h)
        add_pair_blocks(g, curvature * g.normal * g.normal.transpose(), system);
        return;
      }
      bool fixed[4] = {false, false, false, false};
      for (int k = 0; k < g.count; ++k) fixed[k] = model_->pinned[g.vertices[k]];
      const double slope = scale * barrier_derivative(g.d, dhat_, kappa);  // N*s^2
      const double value = scale * barrier_energy(g.d, dhat_, kappa);      // J*s^2
      add_pair_hessian(g, mollified_hessian(g, value, slope, curvature, true, fixed), system);
    });
  }
  for (const PairFriction& f : pair_friction_) {
    add_pair_blocks(f.pair, f.law.jacobian(f.relative(v)), system);
  }
  for (const Friction& f : friction_) system.add_diagonal(f.vertex, f.law.jacobian(v[f.vertex]));
  for (const Damping& d : damping_) system.add_diagonal(d.vertex, -beta_end_ * d.law.velocity_jacobian());
}

double BarrierContact::largest_step(const Vec3List& v, const Eigen::VectorXd& dv) {
  if (!enabled_) return 1.0;
  double step = 1.0;
  if (has_pairs()) {
    const Vec3List& x = end_positions(v);
    x_path_.resize(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
      x_path_[i] = model_->pinned[i] ? x[i] : Vec3(x[i] + beta_end_ * Vec3(dv.segment<3>(3 * i)));
    }
    features_.find_pairs(x, x_path_, dhat_);
    self_.find_pairs(x, x_path_, dhat_);
    double touch = self_.first_touch(x, x_path_);
    for (size_t i = 0; i < x.size(); ++i) x_path_[i] -= x[i];
    touch = std::min(touch, features_.first_touch(x, x_path_));
    if (touch < 1.0) step = kBarrierStepFraction * touch;
  }
  for (int i = 0; i < model_->num_vertices(); ++i) {
    if (model_->pinned[i]) continue;
    const Vec3 x = end_position(v, i);
    const Vec3 u = beta_end_ * Vec3(dv.segment<3>(3 * i));  // m per unit step length
    const double reach = u.norm();
    for (const PlacedObstacle& o : placed_) {
      if (gap_distance(o, x, reach) > reach) continue;  // cannot touch within the step
      const double touch = first_touch(o, x, u);
      if (touch < 1.0) step = std::min(step, kBarrierStepFraction * touch);
    }
  }
  return step;
}

int BarrierContact::active(const Vec3List& v, double* smallest_gap, int* pairs) const {
  int count = 0, within = 0;
  double smallest = std::numeric_limits<double>::infinity();
  if (enabled_) {
    for (int i = 0; i < model_->num_vertices(); ++i) {
      if (model_->pinned[i]) continue;
      bool near = false;
      for (const PlacedObstacle& o : placed_) {
        const double d = gap_distance(o, end_position(v, i), dhat_);
        smallest = std::min(smallest, d);
        near = near || d < dhat_;
      }
      count += near ? 1 : 0;
    }
    if (has_pairs()) {
      for_each_pair(end_positions(v), [&](const PairGap& g, double) {
        smallest = std::min(smallest, g.d);
        within += g.d < dhat_ ? 1 : 0;
      });
    }
  }
  if (smallest_gap) *smallest_gap = smallest;
  if (pairs) *pairs = within;
  count += within;
  return count;
}

double BarrierContact::energy_of(const Model& model, const Vec3List& x, double t) {
  const bool obstacles = model.implicit.contact == ContactModel::Barrier;
  if (!obstacles && !needs_cloth_contact(model)) return 0.0;
  const double dhat = barrier_distance(model), dt = stiffness_step(model);
  double total = 0.0;
  for (const Obstacle& ob : model.obstacles) {
    if (!obstacles) break;
    const PlacedObstacle placed = place_obstacle(ob, t);
    for (int i = 0; i < model.num_vertices(); ++i) {
      if (model.pinned[i]) continue;
      const double d = gap_distance(placed, x[i], dhat);
      total += barrier_energy(d, dhat, barrier_stiffness(model.mass[i], dt));
    }
  }
  const auto add_pair = [&](const PairGap& g) {
    total += edge_mollifier(g) * barrier_energy(g.d, dhat, pair_stiffness(model, g, dt));
  };
  energy_features_.begin(model, t, t);
  if (energy_features_.active()) {
    energy_features_.find_pairs(x, x, dhat);
    energy_features_.for_each_gap(x, add_pair);
  }
  energy_self_.begin(model);
  if (energy_self_.active()) {
    energy_self_.find_pairs(x, x, dhat);
    energy_self_.for_each_gap(x, add_pair);
  }
  return total;
}

double barrier_energy_of(const Model& model, const Vec3List& x, double t) {
  BarrierContact contact;
  return contact.energy_of(model, x, t);
}

}  // namespace tissu
