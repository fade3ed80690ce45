#include "physics/contact.h"

#include <algorithm>
#include <cmath>

#include "physics/system_matrix.h"

namespace tissu {

void ContactSet::clear(int num_vertices) {
  contacts_.clear();
  of_vertex_.assign(num_vertices, -1);
  if (memory_.size() != static_cast<size_t>(num_vertices)) memory_.assign(num_vertices, Memory{});
}

namespace {

// Coulomb's law at a new contact, from the vertex's velocity v when it was caught: the
// impulse that stops its approach (and gravity's push into the surface over beta) against
// the one that stops its sliding (and gravity's pull along it). It sticks when mu times the
// first holds the second; otherwise it slides with friction of at most mu times the first.
// The solve then checks a sticking guess (switch_modes); a good first guess saves the
// Newton iterations of a switch.
void predict_mode(VertexContact& c, const Vec3& v, double mass, const Vec3& gravity,
                  double beta) {
  const Vec3 relative = v - c.surface_velocity;
  const double approach = std::max(0.0, -c.normal.dot(relative)) +
                          beta * std::max(0.0, -c.normal.dot(gravity));  // m/s
  Vec3 sliding = relative + beta * gravity;
  sliding -= c.normal.dot(sliding) * c.normal;  // m/s
  const double speed = sliding.norm();
  if (speed <= c.friction * approach || speed == 0.0) {
    c.mode = ContactMode::Stick;
    return;
  }
  c.mode = ContactMode::Slide;
  c.friction_limit = c.friction * mass * approach;
}

// f1(y) / y of the smoothed friction (y = sliding speed, m/s), 1/(m/s).
double friction_ratio(double y) {
  constexpr double eps = kSlidingSpeed;
  return y < eps ? 2.0 / eps - y / (eps * eps) : 1.0 / y;
}

bool has_sliding_friction(const VertexContact& c) {
  return c.mode == ContactMode::Slide && c.friction_limit != 0.0;
}

}  // namespace

SlidingFriction friction_of(const VertexContact& c) {
  return SlidingFriction{c.normal, c.surface_velocity, c.friction_limit};
}

Vec3 SlidingFriction::sliding(const Vec3& v) const {
  const Vec3 relative = v - surface_velocity;
  return relative - normal.dot(relative) * normal;
}

Vec3 SlidingFriction::impulse(const Vec3& v) const {
  const Vec3 u = sliding(v);
  return -(limit * friction_ratio(u.norm())) * u;
}

double SlidingFriction::potential(const Vec3& v) const {
  constexpr double eps = kSlidingSpeed;
  const double y = sliding(v).norm();
  // f0(y) = y^2 / eps - y^3 / (3 eps^2) below eps, y - eps / 3 above.
  const double f0 = y < eps ? y * y / eps - y * y * y / (3.0 * eps * eps) : y - eps / 3.0;
  return limit * f0;
}

Mat3 SlidingFriction::jacobian(const Vec3& v) const {
  constexpr double eps = kSlidingSpeed;
  const Vec3 u = sliding(v);
  const double y = u.norm();
  // d(f1(y) u / y)/du = f1/y (P - t t^T) + f1'(y) t t^T on the tangent plane (P its
  // projector, t = u / y); f1' = 2 / eps - 2 y / eps^2 below eps, 0 above. Both terms
  // are positive semi-definite.
  const Mat3 tangent = Mat3::Identity() - normal * normal.transpose();
  const double ratio = friction_ratio(y);
  Mat3 block = ratio * tangent;
  if (y > 0.0) {
    const Vec3 t = u / y;
    const double slope = y < eps ? 2.0 / eps - 2.0 * y / (eps * eps) : 0.0;
    block += (slope - ratio) * (t * t.transpose());
  }
  return limit * block;
}

int ContactSet::detect(const Model& model, const std::vector<PlacedObstacle>& placed,
                       const Vec3List& x_end, double margin, double remembered_margin,
                       const Vec3List* velocities, double beta) {
  const Vec3 gravity = model.gravity ? *model.gravity : Vec3::Zero();
  int added = 0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i] || of_vertex_[i] >= 0) continue;
    int best = -1;
    // A vertex released at the end of the last step is caught only once it is inside.
    double best_gap = memory_[i].released    ? std::min(margin, 0.0)
                      : memory_[i].in_contact ? std::max(margin, remembered_margin)
                                              : margin;
    SurfacePoint best_point;
    for (size_t o = 0; o < placed.size(); ++o) {
      const SurfacePoint s = placed[o].closest(x_end[i]);
      const double gap = s.distance - placed[o].obstacle->thickness;
      if (gap < best_gap) {
        best_gap = gap;
        best = static_cast<int>(o);
        best_point = s;
      }
    }
    if (best < 0) continue;
    const Obstacle& ob = *placed[best].obstacle;
    VertexContact c;
    c.vertex = i;
    c.obstacle = best;
    c.normal = best_point.normal;
    // The tangent plane at the closest surface point, moved out by the thickness.
    c.offset = c.normal.dot(x_end[i]) - best_point.distance + ob.thickness;
    c.surface_velocity = best_point.velocity;
    c.friction = ob.friction;
    const Memory& last = memory_[i];
    if (ob.friction == 0.0) {
      c.mode = ContactMode::Slide;
    } else if (last.in_contact) {
      c.mode = last.mode;
      c.friction_limit = last.friction_force * beta;
    } else if (velocities) {
      predict_mode(c, (*velocities)[i], model.mass[i], gravity, beta);
    } else {
      c.mode = ContactMode::Stick;
    }
    of_vertex_[i] = static_cast<int>(contacts_.size());
    contacts_.push_back(c);
    ++added;
  }
  return added;
}

void ContactSet::set_targets(const Vec3List& x_end_base, double beta_end) {
  for (VertexContact& c : contacts_) {
    c.target = (c.offset - c.normal.dot(x_end_base[c.vertex])) / beta_end;
  }
}

void ContactSet::project(Vec3List& v) const {
  for (const VertexContact& c : contacts_) {
    Vec3& vi = v[c.vertex];
    if (c.mode == ContactMode::Stick) {
      vi = c.surface_velocity + (c.target - c.normal.dot(c.surface_velocity)) * c.normal;
    } else {
      vi += (c.target - c.normal.dot(vi)) * c.normal;
    }
  }
}

void ContactSet::filter(Eigen::VectorXd& y) const {
  for (const VertexContact& c : contacts_) {
    auto yi = y.segment<3>(3 * c.vertex);
    if (c.mode == ContactMode::Stick) {
      yi.setZero();
    } else {
      yi -= c.normal.dot(Vec3(yi)) * c.normal;
    }
  }
}

void ContactSet::add_friction(const Vec3List& v, Eigen::VectorXd& rhs) const {
  for (const VertexContact& c : contacts_) {
    if (has_sliding_friction(c)) rhs.segment<3>(3 * c.vertex) += friction_of(c).impulse(v[c.vertex]);
  }
}

double ContactSet::friction_potential(const Vec3List& v) const {
  double total = 0.0;
  for (const VertexContact& c : contacts_) {
    if (has_sliding_friction(c)) total += friction_of(c).potential(v[c.vertex]);
  }
  return total;
}

void ContactSet::add_friction_jacobian(const Vec3List& v, SystemMatrix& system) const {
  for (const VertexContact& c : contacts_) {
    if (has_sliding_friction(c)) system.add_diagonal(c.vertex, friction_of(c).jacobian(v[c.vertex]));
  }
}

void ContactSet::update(const Eigen::VectorXd& reaction) {
  for (VertexContact& c : contacts_) {
    const Vec3 impulse = reaction.segment<3>(3 * c.vertex);
    c.pull = std::max(0.0, -c.normal.dot(impulse));
    c.normal_impulse = std::max(0.0, c.normal.dot(impulse));
    if (c.mode == ContactMode::Stick) {
      c.tangential_impulse = impulse - c.normal.dot(impulse) * c.normal;
    }
  }
}

int ContactSet::switch_modes() {
  int switched = 0;
  for (VertexContact& c : contacts_) {
    if (c.friction == 0.0 || c.switched || c.mode != ContactMode::Stick) continue;
    const double limit = c.friction * c.normal_impulse;
    if (c.tangential_impulse.norm() <= limit) continue;
    c.mode = ContactMode::Slide;
    c.friction_limit = limit;
    c.switched = true;
    ++switched;
  }
  return switched;
}

void ContactSet::remember(const Vec3List& v, const std::vector<double>& release, double beta) {
  std::vector<double>& last_speed = last_sliding_speed_;  // m/s, per vertex
  last_speed.resize(memory_.size());
  for (size_t i = 0; i < memory_.size(); ++i) last_speed[i] = memory_[i].sliding_speed;
  for (Memory& m : memory_) m = Memory{};
  for (const VertexContact& c : contacts_) {
    Memory& m = memory_[c.vertex];
    if (c.pull > release[c.vertex]) {
      m.released = true;
      continue;
    }
    m.in_contact = true;
    if (c.mode != ContactMode::Slide) continue;
    // A sliding contact slides on while it is fast (its friction at full strength, mu J_n),
    // gaining speed, or just let go by a stick that needed more than mu J_n in this step.
    // Otherwise its smoothed friction, less than mu J_n, holds the load: Coulomb's law
    // sticks it, where sliding on would creep at that speed forever (a sheet on an incline
    // with friction above tan(a)). A margin of a hundredth of that speed per step keeps
    // rounding from reading as a gain.
    const double speed = c.friction == 0.0 ? INFINITY : friction_of(c).sliding(v[c.vertex]).norm();
    const bool gaining = speed > last_speed[c.vertex] + 0.01 * kSlidingSpeed;
    if (speed >= kSlidingSpeed || gaining || c.switched) {
      m.mode = ContactMode::Slide;
      m.friction_force = c.friction * c.normal_impulse / beta;
      m.sliding_speed = speed;
    }
  }
}

int ContactSet::stuck() const {
  int count = 0;
  for (const VertexContact& c : contacts_) {
    count += c.mode == ContactMode::Stick ? 1 : 0;
  }
  return count;
}

}  // namespace tissu
