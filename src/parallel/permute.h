// Reordering a big array in place on several threads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/interrupt.h"
#include "parallel/parallel_for.h"

namespace pvrt {

// Reorders `a` in place so that slot j holds what slot order[j] held (`order` a permutation of
// [0, a.size())), on up to `threads` threads (0: threadBudget()), without a second copy of `a`.
// The permutation's cycles are listed first (one thread: a walk over `order`); then each
// short cycle is turned by one thread, and a long one in pieces at the same time, each piece's
// first element set aside beforehand for the piece that ends where it starts.
// A signal (core/interrupt.h) stops it early with `a` in no useful order: callers that go on
// call interrupt::check() after it.
template <class T>
void permuteInPlace(std::vector<T>& a, const std::vector<uint32_t>& order, int threads) {
  const size_t n = a.size();
  if ((threads > 0 ? threads : threadBudget()) <= 1) {
    // One thread turns each cycle as it finds it.
    std::vector<bool> done(n, false);
    for (size_t i = 0; i < n; ++i) {
      if (done[i]) continue;
      if ((i & 4095) == 0 && interrupt::requested()) return;
      T first = std::move(a[i]);
      for (size_t j = i;;) {
        done[j] = true;
        const size_t from = order[j];
        if (from == i) {
          a[j] = std::move(first);
          break;
        }
        a[j] = std::move(a[from]);
        j = from;
      }
    }
    return;
  }
  // The cycles one after another: slot seq[m] receives what slot seq[m + 1] holds, and the
  // last slot of a cycle what its first one holds.
  std::vector<uint32_t> seq;
  std::vector<size_t> cycles{0};  // where each cycle starts in seq, then its end
  {
    std::vector<uint8_t> seen(n, 0);
    for (size_t i = 0; i < n; ++i) {
      if (seen[i] || order[i] == i) continue;
      for (uint32_t j = uint32_t(i); !seen[j]; j = order[j]) {
        seen[j] = 1;
        seq.push_back(j);
      }
      cycles.push_back(seq.size());
    }
  }
  // The work: runs of whole cycles of at most kPiece slots (together about kPiece), and the
  // pieces of the longer ones.
  constexpr size_t kPiece = 4096;
  struct Work {
    size_t begin, end;   // a run: cycles [begin, end); a piece: seq[begin, end)
    size_t next = 0;     // a piece: the piece whose first element this one's last slot receives
    bool piece = false;
  };
  std::vector<Work> work;
  std::vector<size_t> pieces;  // the pieces among `work`
  for (size_t c = 0; c + 1 < cycles.size();) {
    if (cycles[c + 1] - cycles[c] <= kPiece) {
      size_t e = c + 1;
      while (e + 1 < cycles.size() && cycles[e + 1] - cycles[e] <= kPiece && cycles[e] - cycles[c] < kPiece) ++e;
      work.push_back({c, e});
      c = e;
      continue;
    }
    const size_t first = work.size();
    for (size_t p = cycles[c]; p < cycles[c + 1]; p += kPiece) {
      pieces.push_back(work.size());
      work.push_back({p, std::min(cycles[c + 1], p + kPiece), work.size() + 1, true});
    }
    work.back().next = first;  // the cycle closes with its first slot's element
    ++c;
  }
  std::vector<T> saved(work.size());
  parallelIndices(pieces.size(), threads, [&](size_t k) {
    saved[pieces[k]] = std::move(a[seq[work[pieces[k]].begin]]);
  });
  parallelIndices(work.size(), threads, [&](size_t k) {
    if (interrupt::requested()) return;
    const Work& w = work[k];
    auto shift = [&](size_t from, size_t to) {  // seq[from, to): each slot takes the next one's
      for (size_t m = from; m + 1 < to; ++m) a[seq[m]] = std::move(a[seq[m + 1]]);
    };
    if (w.piece) {
      shift(w.begin, w.end);
      a[seq[w.end - 1]] = std::move(saved[w.next]);
      return;
    }
    for (size_t c = w.begin; c < w.end; ++c) {
      T first = std::move(a[seq[cycles[c]]]);
      shift(cycles[c], cycles[c + 1]);
      a[seq[cycles[c + 1] - 1]] = std::move(first);
    }
  });
}

}  // namespace pvrt
