// Deterministic mutations of scene text for the mutation test: byte flips, truncation,
// attribute values replaced by hostile ones, lines duplicated, deleted or swapped.
#pragma once

#include <cstdint>
#include <string>

namespace pvrt::robustness {

// A small portable generator (splitmix64): the same seed gives the same mutants everywhere.
class Rng {
 public:
  explicit Rng(uint64_t seed) : s_(seed) {}
  uint64_t next() {
    uint64_t z = (s_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  size_t below(size_t n) { return n == 0 ? 0 : size_t(next() % n); }

 private:
  uint64_t s_;
};

// `text` with one to three mutations applied; `what` receives their names.
std::string mutate(const std::string& text, Rng& rng, std::string& what);

}  // namespace pvrt::robustness
