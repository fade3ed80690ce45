#include "physics/contact.h"

#include <algorithm>
#include <cmath>

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
// first holds the second; otherwise it slides with friction mu times the first against the
// sliding. The solve then checks the mode (switch_modes); a good first guess saves the
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
  c.friction_impulse = -(c.friction * mass * approach / speed) * sliding;
}

}  // namespace

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
      c.friction_impulse = last.friction_impulse;
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

void ContactSet::add_friction(Eigen::VectorXd& rhs) const {
  for (const VertexContact& c : contacts_) {
    if (c.mode == ContactMode::Slide) rhs.segment<3>(3 * c.vertex) += c.friction_impulse;
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

int ContactSet::switch_modes(const Vec3List& v) {
  constexpr int kMaxSwitches = 2;
  int switched = 0;
  for (VertexContact& c : contacts_) {
    if (c.friction == 0.0 || c.switches >= kMaxSwitches) continue;
    const double limit = c.friction * c.normal_impulse;
    if (c.mode == ContactMode::Stick) {
      const double needed = c.tangential_impulse.norm();
      if (needed <= limit) continue;
      // Friction resists the motion the tangential impulse held back: it acts along it.
      c.mode = ContactMode::Slide;
      c.friction_impulse = c.tangential_impulse * (limit / needed);
    } else {
      const Vec3 relative = v[c.vertex] - c.surface_velocity;
      const Vec3 sliding = relative - c.normal.dot(relative) * c.normal;
      if (sliding.dot(c.friction_impulse) <= 0.0) continue;
      c.mode = ContactMode::Stick;  // its friction turned it back: it should have stopped
    }
    c.switches += 1;
    ++switched;
  }
  return switched;
}

void ContactSet::remember(const Vec3List& v, const std::vector<double>& release) {
  for (Memory& m : memory_) m = Memory{};
  for (const VertexContact& c : contacts_) {
    Memory& m = memory_[c.vertex];
    if (c.pull > release[c.vertex]) {
      m.released = true;
      continue;
    }
    m.in_contact = true;
    const double limit = c.friction * c.normal_impulse;
    if (c.mode == ContactMode::Slide) {
      const Vec3 relative = v[c.vertex] - c.surface_velocity;
      const Vec3 sliding = relative - c.normal.dot(relative) * c.normal;
      const double speed = sliding.norm();
      // Still sliding (without friction, or against its friction): it slides on, friction
      // now against this sliding; stopped or turned back by its friction: it sticks.
      if (c.friction == 0.0 || (speed > 0.0 && sliding.dot(c.friction_impulse) <= 0.0)) {
        m.mode = ContactMode::Slide;
        if (speed > 0.0) m.friction_impulse = -(limit / speed) * sliding;
      }
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
