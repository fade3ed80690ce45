#include "collision/bvh.h"

#include <algorithm>

namespace tissu {

namespace {


// Single precision below and above x: one part in 2^22 beyond the nearest float (more than
// its rounding error), and a little more near zero.
float round_down(double x) {
  const float f = static_cast<float>(x);
  return f - (std::fabs(f) * 2.4e-7f + 1e-30f);
}

float round_up(double x) {
  const float f = static_cast<float>(x);
  return f + (std::fabs(f) * 2.4e-7f + 1e-30f);
}

}  // namespace

void Bvh::build(const std::vector<Box3>& boxes, int leaf_size) {
  leaf_size = std::clamp(leaf_size, 1, 7);
  nodes_.clear();
  order_.resize(boxes.size());
  slot_.resize(boxes.size());
  leaf_boxes_.resize(boxes.size());
  bounds_.setEmpty();
  if (boxes.empty()) return;
  std::vector<Vec3> centres(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    order_[i] = static_cast<int>(i);
    centres[i] = boxes[i].center();
  }
  nodes_.reserve(boxes.size() / leaf_size + 1);
  root_ = build_node(order_, centres, boxes, 0, static_cast<int>(boxes.size()), &bounds_, leaf_size);
  for (size_t k = 0; k < boxes.size(); ++k) {
    slot_[order_[k]] = static_cast<int>(k);
    leaf_boxes_[k] = boxes[order_[k]];
  }
}

int Bvh::build_node(std::vector<int>& ids, const std::vector<Vec3>& centres,
                    const std::vector<Box3>& boxes, int begin, int end, Box3* box, int leaf_size) {
  Box3 centre_box;
  box->setEmpty();
  for (int k = begin; k < end; ++k) {
    box->extend(boxes[ids[k]]);
    centre_box.extend(centres[ids[k]]);
  }
  const int count = end - begin;
  if (count <= leaf_size) return ~(begin * 8 + count);
  // Surface area heuristic over kBins bins of the centres along each axis: the split that
  // minimises area(left) * count(left) + area(right) * count(right). Median split when all
  // centres coincide along every axis.
  constexpr int kBins = 16;
  auto area = [](const Box3& b) {
    if (b.isEmpty()) return 0.0;
    const Vec3 s = b.sizes();
    return s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
  };
  int best_axis = -1, best_split = 0;
  double best_cost = INFINITY;
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = centre_box.min()[axis], extent = centre_box.max()[axis] - lo;
    if (!(extent > 0.0)) continue;
    Box3 bin_box[kBins];
    int bin_count[kBins] = {};
    for (int k = begin; k < end; ++k) {
      const int b = std::min(kBins - 1, static_cast<int>(kBins * (centres[ids[k]][axis] - lo) / extent));
      bin_box[b].extend(boxes[ids[k]]);
      ++bin_count[b];
    }
    double right_area[kBins];
    int right_count[kBins];
    Box3 acc;
    int n = 0;
    for (int b = kBins - 1; b > 0; --b) {
      acc.extend(bin_box[b]);
      n += bin_count[b];
      right_area[b] = area(acc);
      right_count[b] = n;
    }
    acc.setEmpty();
    n = 0;
    for (int b = 0; b + 1 < kBins; ++b) {
      acc.extend(bin_box[b]);
      n += bin_count[b];
      if (n == 0 || right_count[b + 1] == 0) continue;
      const double cost = area(acc) * n + right_area[b + 1] * right_count[b + 1];
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = b + 1;
      }
    }
  }
  int mid = (begin + end) / 2;
  if (best_axis >= 0) {
    const double lo = centre_box.min()[best_axis];
    const double extent = centre_box.max()[best_axis] - lo;
    auto left_of_split = [&](int id) {
      return std::min(kBins - 1, static_cast<int>(kBins * (centres[id][best_axis] - lo) / extent)) <
             best_split;
    };
    mid = static_cast<int>(std::stable_partition(ids.begin() + begin, ids.begin() + end,
                                                 left_of_split) - ids.begin());
  }
  if (mid == begin || mid == end) {
    int axis = 0;
    centre_box.sizes().maxCoeff(&axis);
    mid = (begin + end) / 2;
    std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                     [&](int a, int b) {
                       const double ca = centres[a][axis], cb = centres[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
  }
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{});
  Box3 left, right;
  const int l = build_node(ids, centres, boxes, begin, mid, &left, leaf_size);
  const int r = build_node(ids, centres, boxes, mid, end, &right, leaf_size);
  Node& node = nodes_[index];
  node.child[0] = l;
  node.child[1] = r;
  set_child_box(node, 0, left);
  set_child_box(node, 1, right);
  return index;
}

void Bvh::set_child_box(Node& node, int k, const Box3& box) {
  for (int a = 0; a < 3; ++a) {
    node.lo[k][a] = round_down(box.min()[a]);
    node.hi[k][a] = round_up(box.max()[a]);
  }
}

Box3 Bvh::child_box(const Node& node, int k) const {
  return Box3(Vec3(node.lo[k][0], node.lo[k][1], node.lo[k][2]),
              Vec3(node.hi[k][0], node.hi[k][1], node.hi[k][2]));
}

Bvh::FloatBox Bvh::subtree_box(int ref) const {
  Box3 box;
  if (ref == root_) {
    box = bounds_;
  } else {
    for (int k = leaf_first(ref); k < leaf_first(ref) + leaf_count(ref); ++k) box.extend(leaf_boxes_[k]);
  }
  FloatBox f;
  for (int a = 0; a < 3; ++a) {
    f.lo[a] = round_down(box.min()[a]);
    f.hi[a] = round_up(box.max()[a]);
  }
  return f;
}

void Bvh::refit(const std::vector<Box3>& boxes) {
  for (size_t k = 0; k < order_.size(); ++k) leaf_boxes_[k] = boxes[order_[k]];
  if (!order_.empty()) bounds_ = refit_node(root_);
}

Box3 Bvh::refit_node(int ref) {
  if (is_leaf(ref)) {
    Box3 box;
    for (int k = leaf_first(ref); k < leaf_first(ref) + leaf_count(ref); ++k) box.extend(leaf_boxes_[k]);
    return box;
  }
  const Box3 left = refit_node(nodes_[ref].child[0]);
  const Box3 right = refit_node(nodes_[ref].child[1]);
  set_child_box(nodes_[ref], 0, left);
  set_child_box(nodes_[ref], 1, right);
  return left.merged(right);
}

}  // namespace tissu
