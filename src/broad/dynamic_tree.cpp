#include <collide/broad/dynamic_tree.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace collide {

namespace {

/// Depth-first stack of node indices: on the call stack up to a depth no balanced tree of
/// 2^31 objects reaches, spilling to the heap only for a degenerate tree.
class NodeStack {
 public:
  void push(int node) {
    if (count_ < kInline) {
      inline_[count_] = node;
    } else {
      spill_.push_back(node);
    }
    ++count_;
  }
  [[nodiscard]] bool empty() const noexcept { return count_ == 0; }
  int pop() {
    --count_;
    if (count_ < kInline) return inline_[count_];
    const int node = spill_.back();
    spill_.pop_back();
    return node;
  }

 private:
  static constexpr int kInline = 128;
  std::array<int, kInline> inline_;
  std::vector<int> spill_;
  int count_ = 0;
};

}  // namespace

template <int D>
DynamicTreeN<D>::DynamicTreeN(Options options) : options_(options) {
  if (!std::isfinite(options.margin) || options.margin < 0.0f) {
    throw InvalidInput("DynamicTree options margin: negative or not finite");
  }
  if (!std::isfinite(options.margin_fraction) || options.margin_fraction < 0.0f) {
    throw InvalidInput("DynamicTree options margin_fraction: negative or not finite");
  }
}

template <int D>
AabbN<D> DynamicTreeN<D>::fat_box(const AabbN<D>& box) const noexcept {
  const VecN<D> s = box.size();
  float largest = s[0];
  for (int k = 1; k < D; ++k) largest = std::max(largest, s[k]);
  return fatten(box, options_.margin + options_.margin_fraction * largest);
}

template <int D>
int DynamicTreeN<D>::allocate_node() {
  if (free_list_ >= 0) {
    const int node = free_list_;
    free_list_ = nodes_[node].object;
    nodes_[node] = Node{};
    return node;
  }
  nodes_.push_back(Node{});
  return static_cast<int>(nodes_.size()) - 1;
}

template <int D>
void DynamicTreeN<D>::free_node(int node) noexcept {
  nodes_[node].object = free_list_;
  nodes_[node].height = -1;
  free_list_ = node;
}

template <int D>
void DynamicTreeN<D>::insert_leaf(int leaf) {
  if (root_ < 0) {
    root_ = leaf;
    nodes_[leaf].parent = -1;
    return;
  }
  // Descend while pushing the leaf into a child is cheaper than making it a sibling here. The
  // cost of a choice is the surface metric it adds: the new parent's, plus the growth of every
  // ancestor ("inherited" cost).
  const AabbN<D> box = nodes_[leaf].box;
  int index = root_;
  while (nodes_[index].child1 >= 0) {
    const Node& node = nodes_[index];
    const float area = surface_metric(node.box);
    const float combined = surface_metric(merge(node.box, box));
    const float cost_here = 2.0f * combined;
    const float inherited = 2.0f * (combined - area);
    const auto child_cost = [&](int child) {
      const Node& c = nodes_[child];
      const float grown = surface_metric(merge(box, c.box));
      return (c.child1 < 0 ? grown : grown - surface_metric(c.box)) + inherited;
    };
    const float cost1 = child_cost(node.child1);
    const float cost2 = child_cost(node.child2);
    if (cost_here < cost1 && cost_here < cost2) break;
    index = cost1 <= cost2 ? node.child1 : node.child2;
  }

  const int sibling = index;
  const int old_parent = nodes_[sibling].parent;
  const int parent = allocate_node();
  Node& p = nodes_[parent];
  p.parent = old_parent;
  p.box = merge(box, nodes_[sibling].box);
  p.height = nodes_[sibling].height + 1;
  p.child1 = sibling;
  p.child2 = leaf;
  nodes_[sibling].parent = parent;
  nodes_[leaf].parent = parent;
  if (old_parent < 0) {
    root_ = parent;
  } else if (nodes_[old_parent].child1 == sibling) {
    nodes_[old_parent].child1 = parent;
  } else {
    nodes_[old_parent].child2 = parent;
  }
  refit_upwards(parent);
}

template <int D>
void DynamicTreeN<D>::remove_leaf(int leaf) {
  if (leaf == root_) {
    root_ = -1;
    return;
  }
  const int parent = nodes_[leaf].parent;
  const int grand = nodes_[parent].parent;
  const int sibling = nodes_[parent].child1 == leaf ? nodes_[parent].child2 : nodes_[parent].child1;
  if (grand < 0) {
    root_ = sibling;
    nodes_[sibling].parent = -1;
    free_node(parent);
    return;
  }
  if (nodes_[grand].child1 == parent) {
    nodes_[grand].child1 = sibling;
  } else {
    nodes_[grand].child2 = sibling;
  }
  nodes_[sibling].parent = grand;
  free_node(parent);
  refit_upwards(grand);
}

template <int D>
void DynamicTreeN<D>::refit_upwards(int node) {
  for (int index = node; index >= 0; index = nodes_[index].parent) {
    Node& n = nodes_[index];
    n.box = merge(nodes_[n.child1].box, nodes_[n.child2].box);
    n.height = 1 + std::max(nodes_[n.child1].height, nodes_[n.child2].height);
    rotate(index);
  }
}

template <int D>
void DynamicTreeN<D>::rotate(int a) {
  // Try swapping one child of A with a grandchild under the other child; keep the swap that
  // shrinks the surface metric of the child that changes most (the other boxes stay the same).
  const int b = nodes_[a].child1;
  const int c = nodes_[a].child2;
  float best_gain = 0.0f;
  int swap_out = -1;  // the child of A that moves down
  int swap_in = -1;   // the grandchild that moves up
  const auto consider = [&](int down, int keep_parent) {
    const Node& p = nodes_[keep_parent];
    if (p.child1 < 0) return;
    const float before = surface_metric(p.box);
    for (int g : {p.child1, p.child2}) {
      const int other = g == p.child1 ? p.child2 : p.child1;
      const float gain = before - surface_metric(merge(nodes_[down].box, nodes_[other].box));
      if (gain > best_gain) {
        best_gain = gain;
        swap_out = down;
        swap_in = g;
      }
    }
  };
  consider(b, c);
  consider(c, b);
  if (swap_out < 0) return;

  const int lower = nodes_[swap_in].parent;  // the child of A that receives swap_out
  Node& an = nodes_[a];
  if (an.child1 == swap_out) {
    an.child1 = swap_in;
  } else {
    an.child2 = swap_in;
  }
  nodes_[swap_in].parent = a;
  Node& ln = nodes_[lower];
  if (ln.child1 == swap_in) {
    ln.child1 = swap_out;
  } else {
    ln.child2 = swap_out;
  }
  nodes_[swap_out].parent = lower;
  ln.box = merge(nodes_[ln.child1].box, nodes_[ln.child2].box);
  ln.height = 1 + std::max(nodes_[ln.child1].height, nodes_[ln.child2].height);
  an.height = 1 + std::max(nodes_[an.child1].height, nodes_[an.child2].height);
}

template <int D>
void DynamicTreeN<D>::build(std::span<const AabbN<D>> boxes) {
  validate_boxes(boxes);
  nodes_.clear();
  root_ = -1;
  free_list_ = -1;
  nodes_.reserve(2 * boxes.size());
  tight_.assign(boxes.begin(), boxes.end());
  leaf_.resize(boxes.size());
  for (int i = 0; i < size(); ++i) {
    const int leaf = allocate_node();
    nodes_[leaf].box = fat_box(boxes[i]);
    nodes_[leaf].object = i;
    leaf_[i] = leaf;
    insert_leaf(leaf);
  }
  reinserted_ = size();
}

template <int D>
int DynamicTreeN<D>::insert(const AabbN<D>& box) {
  validate_boxes(std::span<const AabbN<D>>(&box, 1));
  const int id = size();
  const int leaf = allocate_node();
  nodes_[leaf].box = fat_box(box);
  nodes_[leaf].object = id;
  tight_.push_back(box);
  leaf_.push_back(leaf);
  insert_leaf(leaf);
  return id;
}

template <int D>
void DynamicTreeN<D>::update(std::span<const AabbN<D>> boxes) {
  if (boxes.size() != tight_.size()) {
    build(boxes);
    return;
  }
  validate_boxes(boxes);
  reinserted_ = 0;
  for (int i = 0; i < size(); ++i) {
    tight_[i] = boxes[i];
    const int leaf = leaf_[i];
    if (contains(nodes_[leaf].box, boxes[i])) continue;
    remove_leaf(leaf);
    nodes_[leaf].box = fat_box(boxes[i]);
    insert_leaf(leaf);
    ++reinserted_;
  }
}

template <int D>
template <class Overlaps, class Visit>
void DynamicTreeN<D>::traverse(Overlaps&& overlaps, Visit&& visit) const {
  if (root_ < 0) return;
  NodeStack stack;
  stack.push(root_);
  while (!stack.empty()) {
    const Node& node = nodes_[stack.pop()];
    if (!overlaps(node.box)) continue;
    if (node.child1 < 0) {
      if (!visit(node.object)) return;
    } else {
      stack.push(node.child2);
      stack.push(node.child1);
    }
  }
}

template <int D>
void DynamicTreeN<D>::find_pairs(PairList& pairs) {
  pairs.clear();
  if (root_ < 0) return;
  // The tree against itself: a node's pairs are those inside each child plus those between the
  // two children; two subtrees are opened only while their boxes overlap, the larger first.
  // Each pair of leaves is met once, with no query per object. (van den Bergen, Collision
  // Detection in Interactive 3D Environments, 2004, 5.3.)
  constexpr int kSelf = -1;  // a task (node, kSelf): the pairs inside node
  pair_stack_.clear();
  pair_stack_.push_back({root_, kSelf});
  while (!pair_stack_.empty()) {
    const auto [a, b] = pair_stack_.back();
    pair_stack_.pop_back();
    const Node& na = nodes_[a];
    if (b == kSelf) {
      if (na.child1 < 0) continue;
      pair_stack_.push_back({na.child1, na.child2});
      pair_stack_.push_back({na.child2, kSelf});
      pair_stack_.push_back({na.child1, kSelf});
      continue;
    }
    const Node& nb = nodes_[b];
    if (!overlap(na.box, nb.box)) continue;
    if (na.child1 < 0 && nb.child1 < 0) {
      const int i = na.object, j = nb.object;
      if (overlap(tight_[i], tight_[j])) pairs.emplace_back(std::min(i, j), std::max(i, j));
      continue;
    }
    // Open the internal node with the larger box (a leaf never opens).
    const bool open_a =
        nb.child1 < 0 || (na.child1 >= 0 && surface_metric(na.box) >= surface_metric(nb.box));
    if (open_a) {
      pair_stack_.push_back({na.child2, b});
      pair_stack_.push_back({na.child1, b});
    } else {
      pair_stack_.push_back({a, nb.child2});
      pair_stack_.push_back({a, nb.child1});
    }
  }
}

template <int D>
void DynamicTreeN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  traverse([&](const AabbN<D>& node_box) { return overlap(box, node_box); },
           [&](int id) { return !overlap(box, tight_[id]) || callback(id); });
}

template <int D>
void DynamicTreeN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  traverse([&](const AabbN<D>& node_box) { return contains(node_box, point); },
           [&](int id) { return !contains(tight_[id], point) || callback(id); });
}

template <int D>
void DynamicTreeN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  float limit = 1.0f;
  const SlabRayN<D> slab(ray);
  traverse([&](const AabbN<D>& node_box) { return slab.fraction(node_box, limit) >= 0.0f; },
           [&](int id) {
             if (slab.fraction(tight_[id], limit) < 0.0f) return true;
             const float r = callback(id, limit);
             if (r < limit) limit = r;
             return limit > 0.0f;
           });
}

template <int D>
std::size_t DynamicTreeN<D>::memory_bytes() const noexcept {
  return nodes_.capacity() * sizeof(Node) + tight_.capacity() * sizeof(AabbN<D>) +
         leaf_.capacity() * sizeof(int) + pair_stack_.capacity() * sizeof(std::pair<int, int>);
}

template class DynamicTreeN<2>;
template class DynamicTreeN<3>;
static_assert(BroadPhase<DynamicTreeN<2>, 2> && BroadPhase<DynamicTreeN<3>, 3>);

}  // namespace collide
