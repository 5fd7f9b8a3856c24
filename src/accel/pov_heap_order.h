// The order POV-Ray 3.7 tests its unbounded objects (planes) in, which decides which of two
// planes a ray meets at exactly one depth it shows (a ray along the line where two walls
// meet). Its bounding tree's root holds the planes in one node, entry 0, before its finite
// entries (bbox.cpp, Build_BBox_Tree). A ray's walk pushes the root's entries into its
// priority queue, the planes' node with the key -MAX_DISTANCE and each finite entry the ray's
// box test accepts with its entry depth; pops the planes' node; and pushes the planes, all
// with that one key (Check_And_Enqueue, priority_queue_insert). A binary heap does not give
// equal keys back in the order pushed (Priority_Queue_Delete moves the last element to the top
// and sifts it down to the right child of two equals), and the trace keeps a later hit only
// when strictly nearer, so the plane popped first wins the tie: with no finite entry in the
// queue, three planes come out first, third, second. Which order depends only on how many
// finite entries are in the queue beside them and on how many planes there are.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace pvrt {

// POV-Ray's priority queue of tree nodes by key (priority_queue_insert, Priority_Queue_Delete):
// a binary heap counted from 1 whose removal moves the last element to the top and sifts it
// down towards the right child of two equals.
class PovQueue {
 public:
  struct Entry {
    double key;
    int id;
  };
  void push(Entry e) {
    heap_.push_back(e);
    size_t i = heap_.size() - 1;
    for (; i > 1 && e.key < heap_[i / 2].key; i /= 2) heap_[i] = heap_[i / 2];
    heap_[i] = e;
  }
  Entry pop() {
    const Entry top = heap_[1];
    heap_[1] = heap_.back();
    heap_.pop_back();
    const size_t size = heap_.size() - 1;
    for (size_t i = 1; 2 * i <= size;) {
      const size_t j = 2 * i == size || heap_[2 * i].key < heap_[2 * i + 1].key ? 2 * i : 2 * i + 1;
      if (!(heap_[i].key > heap_[j].key)) break;
      std::swap(heap_[i], heap_[j]);
      i = j;
    }
    return top;
  }
  bool empty() const { return heap_.size() == 1; }

 private:
  std::vector<Entry> heap_ = std::vector<Entry>(1);  // heap_[0] unused
};

// The order in which POV-Ray's heap pops `planes` equal keys pushed in order 0, 1, ... onto
// a queue that already holds `others` larger keys: element r is the plane popped r-th.
inline std::vector<int> povPlanePopOrder(int others, int planes) {
  // Only the heap's shape matters: a plane's parent is always a plane (its key is the
  // least), and a larger key sifted down passes planes by their positions alone, so the
  // others may all be given one key.
  PovQueue queue;
  for (int k = 0; k < others; ++k) queue.push({1, -1});
  for (int p = 0; p < planes; ++p) queue.push({0, p});
  std::vector<int> order;
  while (int(order.size()) < planes)
    if (const PovQueue::Entry e = queue.pop(); e.id >= 0) order.push_back(e.id);
  return order;
}

}  // namespace pvrt
