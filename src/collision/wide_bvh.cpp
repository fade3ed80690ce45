#include "collision/wide_bvh.h"

namespace tissu {

WideBvh::WideBvh(const Bvh& tree) : bounds_(tree.bounds_), order_(tree.order_) {
  if (tree.order_.empty()) return;
  scale_ = std::max(bounds_.min().cwiseAbs().maxCoeff(), bounds_.max().cwiseAbs().maxCoeff());
  root_ = collapse(tree, tree.root_);
}

int WideBvh::collapse(const Bvh& tree, int ref) {
  if (Bvh::is_leaf(ref)) return ref;
  // Open the binary node and then its inner children, largest box first, up to four.
  struct Child {
    int ref;
    Box3 box;
  };
  std::vector<Child> children;
  const Bvh::Node& top = tree.nodes_[ref];
  for (int k = 0; k < 2; ++k) children.push_back({top.child[k], tree.child_box(top, k)});
  while (children.size() < 4) {
    int open = -1;
    double largest = -1;
    for (size_t i = 0; i < children.size(); ++i) {
      if (Bvh::is_leaf(children[i].ref)) continue;
      const Vec3 s = children[i].box.sizes();
      const double area = s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
      if (area > largest) {
        largest = area;
        open = static_cast<int>(i);
      }
    }
    if (open < 0) break;
    const Bvh::Node& inner = tree.nodes_[children[open].ref];
    children[open] = {inner.child[0], tree.child_box(inner, 0)};
    children.push_back({inner.child[1], tree.child_box(inner, 1)});
  }
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{});
  int refs[4];
  for (size_t i = 0; i < 4; ++i) {
    refs[i] = i < children.size() ? collapse(tree, children[i].ref) : kEmpty;
  }
  Node& node = nodes_[index];
  for (int i = 0; i < 4; ++i) {
    node.child[i] = refs[i];
    for (int a = 0; a < 3; ++a) {
      // Child boxes of the binary tree are already rounded outward to floats.
      node.lo[a][i] = i < static_cast<int>(children.size()) ? static_cast<float>(children[i].box.min()[a]) : 1e30f;
      node.hi[a][i] = i < static_cast<int>(children.size()) ? static_cast<float>(children[i].box.max()[a]) : -1e30f;
    }
  }
  return index;
}

}  // namespace tissu
