#include "render/passes.h"

#include <algorithm>
#include <cmath>


namespace pvrt {

namespace {
// Beyond the latest pass, a sample costs at least this share of that pass's cost per sample
// (as for the pilots: two close passes on a shared machine can give any slope).
constexpr double kMinSlopeShare = 0.5;
}  // namespace

int wholePassEnd(int done) {
  constexpr int kLongest = 64;  // kMaxPacket: a pixel's packets start at its multiples
  if (done >= kLongest) return (done / kLongest + 1) * kLongest;
  int next = 1;
  while (next <= done) next *= 2;
  return next;
}

double predictPassSeconds(const std::vector<PassRecord>& passes, int samples) {
  if (passes.empty()) return 0;
  const PassRecord& last = passes.back();
  const double lastSize = last.last - last.first;
  const double perSample = last.seconds / lastSize;
  const PassRecord* before = nullptr;
  for (auto it = passes.rbegin() + 1; it != passes.rend() && !before; ++it)
    if (it->last - it->first != last.last - last.first) before = &*it;
  if (!before) return perSample * samples;
  const double beforeSize = before->last - before->first;
  const double slope =
      std::clamp((last.seconds - before->seconds) / (lastSize - beforeSize), kMinSlopeShare * perSample, perSample);
  return last.seconds + slope * (samples - lastSize);
}

int nextPassEnd(const PassBudget& budget, const PassesSoFar& so) {
  if (so.done == 0) return 1;
  const int done = so.done;
  if (done >= budget.maxSamples) return done;
  const double left = budget.budgetSeconds - budget.spentSeconds - so.seconds - budget.writeSeconds;
  const int whole = std::min(wholePassEnd(done), budget.maxSamples);
  if (predictPassSeconds(so.passes, whole - done) <= left) return whole;
  // A shorter pass: the most samples that fit, or one more when that ends nearer the budget
  // (and not too far over it).
  int lo = 0, hi = whole - done - 1;  // predicted to fit: lo; the whole pass does not
  while (lo < hi) {
    const int mid = lo + (hi - lo + 1) / 2;
    if (predictPassSeconds(so.passes, mid) <= left)
      lo = mid;
    else
      hi = mid - 1;
  }
  const double under = left - (lo > 0 ? predictPassSeconds(so.passes, lo) : 0.0);
  const double over = predictPassSeconds(so.passes, lo + 1) - left;
  if (over < under && over <= kMaxOvershoot * budget.budgetSeconds) ++lo;
  return done + lo;
}

}  // namespace pvrt
