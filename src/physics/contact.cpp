#include "physics/contact.h"

#include <algorithm>
#include <cmath>

#include "physics/system_matrix.h"

namespace tissu {

void ContactSet::clear(int num_vertices) {
  contacts_.clear();
  of_vertex_.assign(num_vertices, -1);
  second_of_vertex_.assign(num_vertices, -1);
  if (memory_.size() != static_cast<size_t>(num_vertices)) {
    memory_.assign(num_vertices, Memory{});
    second_memory_.assign(num_vertices, Memory{});
  }
}

ConstrainedDirections ContactSet::constrained_at(int vertex) const {
  const int c = of_vertex_[vertex];
  if (c < 0) return ConstrainedDirections::None;
  if (second_of_vertex_[vertex] >= 0) return ConstrainedDirections::TwoNormals;
  return contacts_[c].mode == ContactMode::Stick ? ConstrainedDirections::All
                                                 : ConstrainedDirections::Normal;
}

namespace {

// The coefficients (a, b) of along_two_normals.
Eigen::Vector2d two_normal_coefficients(const Vec3& n_a, const Vec3& n_b, double r_a,
                                        double r_b) {
  const double c = n_a.dot(n_b);
  const double det = 1.0 - c * c;  // > 0: the normals are more than kCornerCosine apart
  return {(r_a - c * r_b) / det, (r_b - c * r_a) / det};
}

}  // namespace

Vec3 along_two_normals(const Vec3& n_a, const Vec3& n_b, double r_a, double r_b) {
  const Eigen::Vector2d k = two_normal_coefficients(n_a, n_b, r_a, r_b);
  return k[0] * n_a + k[1] * n_b;
}

namespace {

// The part of a vertex's velocity v (m/s) into c's surface that the step's unknown must
// stop: `share` of it (1, or 1/2 for the midpoint rule, whose end velocity 2 w - v_n
// doubles every impulse on its unknown w).
double impact_speed(const VertexContact& c, const Vec3& v, double share) {
  return share * std::max(0.0, -c.normal.dot(v - c.surface_velocity));
}

// The speed (m/s) at which a vertex caught at velocity v approaches c's surface, for the
// step's unknown (share, above), gravity's push into it over beta (s) included.
double approach_speed(const VertexContact& c, const Vec3& v, const Vec3& gravity, double beta,
                      double share) {
  return impact_speed(c, v, share) + beta * std::max(0.0, -c.normal.dot(gravity));
}

// Coulomb's law at a new contact, from the vertex's velocity v when it was caught: the
// impulse that stops its approach (and gravity's push into the surface over beta) against
// the one that stops its sliding (and gravity's pull along it), both on the step's unknown
// (share). It sticks when mu times the first holds the second; otherwise it slides with
// friction of at most mu times the first. The solve then checks a sticking guess
// (switch_modes); a good first guess saves the Newton iterations of a switch.
void predict_mode(VertexContact& c, const Vec3& v, double mass, const Vec3& gravity,
                  double beta, double share) {
  const double approach = approach_speed(c, v, gravity, beta, share);  // m/s
  Vec3 sliding = share * (v - c.surface_velocity) + beta * gravity;
  sliding -= c.normal.dot(sliding) * c.normal;  // m/s
  const double speed = sliding.norm();
  c.mode = speed <= c.friction * approach || speed == 0.0 ? ContactMode::Stick
                                                         : ContactMode::Slide;
  // Coulomb's limit for the impact: a slide's friction, or what a stick holds while its J_n
  // has stopped only part of the impact (switch_modes); either takes it whole.
  c.friction_limit = c.friction * mass * approach;
  c.unabsorbed_impact = mass * impact_speed(c, v, share);
}

// Takes a normal impulse (kg*m/s) against what is left of a contact's impact, `unabsorbed`,
// and returns the part it absorbs: none of a pull, at most what is left.
double absorb_impact(double& unabsorbed, double impulse) {
  const double absorbed = std::clamp(impulse, 0.0, unabsorbed);
  unabsorbed -= absorbed;
  return absorbed;
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

void ContactSet::add_contact(const Model& model, const PlacedObstacle& placed, int o, int i,
                             const SurfacePoint& p, const Vec3List& x_end, const Memory& last,
                             const Vec3List* velocities, double beta, double share) {
  const Obstacle& ob = *placed.obstacle;
  VertexContact c;
  c.vertex = i;
  c.obstacle = o;
  c.normal = p.normal;
  // The tangent plane at the closest surface point, moved out by the thickness.
  c.offset = c.normal.dot(x_end[i]) - p.distance + ob.thickness;
  c.surface_velocity = p.velocity;
  c.friction = ob.friction;
  if (ob.friction == 0.0) {
    c.mode = ContactMode::Slide;
  } else if (last.in_contact) {
    c.mode = last.mode;
    c.friction_limit = last.friction_force * beta;
    c.unabsorbed_impact = last.unabsorbed_impact;
  } else if (velocities) {
    predict_mode(c, (*velocities)[i], model.mass[i],
                 model.gravity ? *model.gravity : Vec3::Zero(), beta, share);
  } else {
    c.mode = ContactMode::Stick;
  }
  contacts_.push_back(c);
}

int ContactSet::detect(const Model& model, const std::vector<PlacedObstacle>& placed,
                       const Vec3List& x_end, double margin, double remembered_margin,
                       const Vec3List* velocities, double beta, double share) {
  const Vec3 gravity = model.gravity ? *model.gravity : Vec3::Zero();
  // How close a vertex is caught: a vertex released at the end of the last step only once
  // it is inside.
  const auto catch_gap = [&](const Memory& last) {
    return last.released ? std::min(margin, 0.0)
           : last.in_contact ? std::max(margin, remembered_margin)
                             : margin;
  };
  static const Memory kNone;
  int added = 0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i] || second_of_vertex_[i] >= 0) continue;
    // The obstacle closest within its catch gap (limit(o), m), other than `except` and,
    // given a normal, more than kCornerCosine from it; at equal gaps the first listed.
    SurfacePoint best_point;
    const auto closest = [&](int except, const Vec3* normal, auto limit) {
      int best = -1;
      double best_gap = INFINITY;
      for (size_t o = 0; o < placed.size(); ++o) {
        const int ob = static_cast<int>(o);
        if (ob == except) continue;
        const SurfacePoint p = placed[o].closest(x_end[i]);
        const double gap = p.distance - placed[o].obstacle->thickness;
        if (gap >= limit(ob) || gap >= best_gap) continue;
        if (normal && std::abs(p.normal.dot(*normal)) >= kCornerCosine) continue;
        best_gap = gap;
        best = ob;
        best_point = p;
      }
      return best;
    };
    if (of_vertex_[i] < 0) {
      const double limit = catch_gap(memory_[i]);
      const int best = closest(-1, nullptr, [&](int) { return limit; });
      if (best < 0) continue;
      of_vertex_[i] = static_cast<int>(contacts_.size());
      add_contact(model, placed[best], best, i, best_point, x_end, memory_[i], velocities, beta,
                  share);
      ++added;
    }
    if (placed.size() < 2) continue;
    // A second obstacle this close, on another side: the vertex is in a corner.
    const int first = of_vertex_[i];
    const Vec3 first_normal = contacts_[first].normal;
    const auto remembered = [&](int o) -> const Memory& {
      return second_memory_[i].obstacle == o ? second_memory_[i] : kNone;
    };
    const int best = closest(contacts_[first].obstacle, &first_normal,
                             [&](int o) { return catch_gap(remembered(o)); });
    if (best < 0) continue;
    second_of_vertex_[i] = static_cast<int>(contacts_.size());
    add_contact(model, placed[best], best, i, best_point, x_end, remembered(best), velocities,
                beta, share);
    ++added;
    // Both slide: a stick of one would hold the vertex against the other's motion. A
    // sticking one takes the friction of the impulse it needed, or of its approach.
    for (const int k : {first, second_of_vertex_[i]}) {
      VertexContact& c = contacts_[k];
      if (c.mode != ContactMode::Stick) continue;
      c.mode = ContactMode::Slide;
      const double impulse =
          std::max(c.normal_impulse,
                   velocities
                       ? model.mass[i] * approach_speed(c, (*velocities)[i], gravity, beta, share)
                       : 0.0);  // kg*m/s
      c.friction_limit = c.friction * impulse;
    }
  }
  return added;
}

void ContactSet::set_targets(const Vec3List& x_end_base, double beta_end) {
  for (VertexContact& c : contacts_) {
    c.target = (c.offset - c.normal.dot(x_end_base[c.vertex])) / beta_end;
  }
}

template <typename Visit>
void ContactSet::for_each_vertex(Visit visit) const {
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const VertexContact& c = contacts_[k];
    const int second = second_of_vertex_[c.vertex];
    if (second == static_cast<int>(k)) continue;  // with the first
    visit(c, second >= 0 ? &contacts_[second] : nullptr);
  }
}

void ContactSet::project(Vec3List& v) const {
  for_each_vertex([&](const VertexContact& c, const VertexContact* b) {
    Vec3& vi = v[c.vertex];
    if (b) {  // both slide
      vi += along_two_normals(c.normal, b->normal, c.target - c.normal.dot(vi),
                              b->target - b->normal.dot(vi));
    } else if (c.mode == ContactMode::Stick) {
      vi = c.surface_velocity + (c.target - c.normal.dot(c.surface_velocity)) * c.normal;
    } else {
      vi += (c.target - c.normal.dot(vi)) * c.normal;
    }
  });
}

void ContactSet::filter(Eigen::VectorXd& y) const {
  for_each_vertex([&](const VertexContact& c, const VertexContact* b) {
    auto yi = y.segment<3>(3 * c.vertex);
    if (b) {
      yi -= along_two_normals(c.normal, b->normal, c.normal.dot(Vec3(yi)),
                              b->normal.dot(Vec3(yi)));
    } else if (c.mode == ContactMode::Stick) {
      yi.setZero();
    } else {
      yi -= c.normal.dot(Vec3(yi)) * c.normal;
    }
  });
}

void ContactSet::stop_approach(Vec3List& v) const {
  for_each_vertex([&](const VertexContact& c, const VertexContact* b) {
    Vec3& vi = v[c.vertex];
    const double along = c.normal.dot(vi - c.surface_velocity);  // m/s
    if (!b) {
      if (along < 0.0) vi -= along * c.normal;
      return;
    }
    // Both together: removing one approach alone can approach the other surface.
    const double along_b = b->normal.dot(vi - b->surface_velocity);  // m/s
    if (along >= 0.0 && along_b >= 0.0) return;
    const Vec3 single =
        along < 0.0 ? Vec3(vi - along * c.normal) : Vec3(vi - along_b * b->normal);
    if (c.normal.dot(single - c.surface_velocity) >= 0.0 &&
        b->normal.dot(single - b->surface_velocity) >= 0.0) {
      vi = single;
    } else {
      vi -= along_two_normals(c.normal, b->normal, along, along_b);
    }
  });
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
  for (size_t k = 0; k < contacts_.size(); ++k) {
    VertexContact& c = contacts_[k];
    const Vec3 impulse = reaction.segment<3>(3 * c.vertex);
    double along = c.normal.dot(impulse);  // kg*m/s
    const int first = of_vertex_[c.vertex], second = second_of_vertex_[c.vertex];
    if (second >= 0) {  // the reaction split between the corner's two normals
      const Vec3& n_first = contacts_[first].normal;
      const Vec3& n_second = contacts_[second].normal;
      const Eigen::Vector2d split = two_normal_coefficients(
          n_first, n_second, n_first.dot(impulse), n_second.dot(impulse));
      along = split[static_cast<int>(k) == first ? 0 : 1];
    }
    c.pull = std::max(0.0, -along);
    c.normal_impulse = std::max(0.0, along);
    if (c.mode == ContactMode::Stick) {
      c.tangential_impulse = impulse - c.normal.dot(impulse) * c.normal;
    }
  }
}

int ContactSet::switch_modes(bool converged) {
  int switched = 0;
  for (VertexContact& c : contacts_) {
    if (c.friction == 0.0 || c.switched || c.mode != ContactMode::Stick) continue;
    if (!converged && c.normal_impulse <= 0.0) continue;  // not loaded yet: judged later
    // A contact caught in this step holds up to Coulomb's limit for its whole impact: caught
    // before it reaches the surface, its J_n here is only part of it.
    const double limit = std::max(c.friction * c.normal_impulse, c.friction_limit);
    if (c.tangential_impulse.norm() <= limit) continue;
    c.mode = ContactMode::Slide;
    c.friction_limit = limit;
    c.switched = true;
    ++switched;
  }
  return switched;
}

namespace {

// The steps a contact slides after its k-th stick let go in a row before a slow slide
// sticks it again: 2^(k-1) - 1, at most kSlideStepsAfterLetGo.
int slide_steps_after_let_go(int k) {
  int steps = 0;
  for (int i = 1; i < k && steps < kSlideStepsAfterLetGo; ++i) steps = 2 * steps + 1;
  return std::min(steps, kSlideStepsAfterLetGo);
}

}  // namespace

void ContactSet::remember(const Vec3List& v, const std::vector<double>& release, double beta) {
  // The memories of the step that ends become the last ones, and are made anew.
  last_memory_.swap(memory_);
  last_second_memory_.swap(second_memory_);
  memory_.assign(last_memory_.size(), Memory{});
  second_memory_.assign(last_second_memory_.size(), Memory{});
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const VertexContact& c = contacts_[k];
    const bool second = second_of_vertex_[c.vertex] == static_cast<int>(k);
    Memory& m = second ? second_memory_[c.vertex] : memory_[c.vertex];
    const Memory& last = second ? last_second_memory_[c.vertex] : last_memory_[c.vertex];
    if (second) m.obstacle = c.obstacle;
    if (c.pull > release[c.vertex]) {
      m.released = true;
      continue;
    }
    m.in_contact = true;
    if (c.mode != ContactMode::Slide) continue;
    // A sliding contact slides on while it is fast (its friction at full strength, mu J_n),
    // gaining speed, or let go by a stick that needed more than mu J_n in this step or
    // still waiting after such a let-go (slide_steps_after_let_go). Otherwise its smoothed
    // friction, less than mu J_n, holds the load: Coulomb's law sticks it, where sliding on
    // would creep at that speed forever (a sheet on an incline with friction above tan(a)).
    // A margin of a hundredth of that speed per step keeps rounding from reading as a gain.
    const double speed = c.friction == 0.0 ? INFINITY : friction_of(c).sliding(v[c.vertex]).norm();
    const bool gaining = speed > last.sliding_speed + 0.01 * kSlidingSpeed;
    m.let_go = c.switched ? last.let_go + 1 : last.let_go;
    m.slide_steps_left = c.switched ? slide_steps_after_let_go(m.let_go)
                                    : std::max(0, last.slide_steps_left - 1);
    if (speed >= kSlidingSpeed || gaining || c.switched || last.slide_steps_left > 0) {
      m.mode = ContactMode::Slide;
      // Its friction for the next step, from the normal force of this one: an impact's
      // impulse is left out, its friction taken at the catch (Coulomb's law at an impact:
      // at most mu times its impulse, where carrying it on would take it twice).
      m.unabsorbed_impact = c.unabsorbed_impact;
      const double absorbed = absorb_impact(m.unabsorbed_impact, c.normal_impulse);
      m.friction_force = c.friction * (c.normal_impulse - absorbed) / beta;
      m.sliding_speed = speed;
    }
  }
}

void ContactSet::settle_stopped_normal(const Model& model, const Vec3List& v, double beta,
                                       double share, bool whole) {
  for (const VertexContact& c : contacts_) {
    if (second_of_vertex_[c.vertex] >= 0) continue;  // a corner's contacts slide apart
    Memory& m = memory_[c.vertex];
    if (!m.in_contact || m.mode != ContactMode::Slide) continue;
    // The impulse on the step's unknown that stops the end velocity's normal part: positive
    // where it stops an approach, negative where it takes back a rebound, kg*m/s.
    const double stop = -share * model.mass[c.vertex] *
                        c.normal.dot(v[c.vertex] - c.surface_velocity);
    const bool caught = c.unabsorbed_impact > 0.0;  // it came with an impact to absorb
    const double absorbed = absorb_impact(m.unabsorbed_impact, stop);
    // Without `whole` (BDF-2) only a catch's rebound is taken back from the next friction:
    // its base, extrapolating the fall, lies beyond the surface, and its J_n holds the
    // rebound that the step's end takes back.
    if (!whole && !(caught && stop < 0.0)) continue;
    m.friction_force = std::max(0.0, m.friction_force + c.friction * (stop - absorbed) / beta);
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
