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

#include <vector>

namespace pvrt {

// The order in which POV-Ray's heap pops `planes` equal keys pushed in order 0, 1, ... onto
// a queue that already holds `others` larger keys: element r is the plane popped r-th.
inline std::vector<int> povPlanePopOrder(int others, int planes) {
  // Only the heap's shape matters: a plane's parent is always a plane (its key is the
  // least), and a larger key sifted down passes planes by their positions alone, so the
  // others may all be given one key.
  struct Entry {
    int key, plane;
  };
  std::vector<Entry> heap(1);  // heap[0] unused: POV-Ray's queue counts from 1
  auto push = [&heap](Entry e) {  // priority_queue_insert
    heap.push_back(e);
    size_t i = heap.size() - 1;
    for (; i > 1 && e.key < heap[i / 2].key; i /= 2) heap[i] = heap[i / 2];
    heap[i] = e;
  };
  auto pop = [&heap]() {  // Priority_Queue_Delete
    const Entry top = heap[1];
    heap[1] = heap.back();
    heap.pop_back();
    const size_t size = heap.size() - 1;
    for (size_t i = 1; 2 * i <= size;) {
      const size_t j = 2 * i == size || heap[2 * i].key < heap[2 * i + 1].key ? 2 * i : 2 * i + 1;
      if (!(heap[i].key > heap[j].key)) break;
      std::swap(heap[i], heap[j]);
      i = j;
    }
    return top;
  };
  for (int k = 0; k < others; ++k) push({1, -1});
  for (int p = 0; p < planes; ++p) push({0, p});
  std::vector<int> order;
  while (int(order.size()) < planes) {
    const Entry e = pop();
    if (e.plane >= 0) order.push_back(e.plane);
  }
  return order;
}

}  // namespace pvrt
