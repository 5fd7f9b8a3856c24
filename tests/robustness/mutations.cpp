#include "mutations.h"

#include <algorithm>
#include <vector>

namespace pvrt::robustness {

namespace {

// Values that have broken parsers and renderers before: non-numbers, non-finite numbers,
// the edges of the allowed range, signs and zeros, wrong arity, XML-level trouble.
const char* const kHostile[] = {
    "nan",  "inf",     "-inf",    "-1",   "0",     "-0",      "1e308", "-1e308", "1e15",  "-1e15",
    "1e16", "1e-300",  "5e-324",  "1e-8", "1e9",   "abc",     "",      "1 2",    "0 0 0", "1 1 1 1",
    "0,0",  "65536",   "65537",   "2147483648",    "-2147483649",      "1.5",    "true",  "false",
    "&#0;", "&lt;",    "\xff",    "1e-15", "179.9999999", "90.0001", "256", "1024", "0 0 1e15",
    "1e15 1e15 1e15",  "-1e15 0 1e15", "1e-300 0 0", "0 1e-160 0"};

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find('\n', start), text.size());
    out.push_back(text.substr(start, end - start + 1));
    start = end + 1;
  }
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += s;
  return out;
}

// The [begin, end) of every attribute value (between the quotes).
std::vector<std::pair<size_t, size_t>> values(const std::string& text) {
  std::vector<std::pair<size_t, size_t>> out;
  for (size_t i = text.find("=\""); i != std::string::npos; i = text.find("=\"", i + 1)) {
    const size_t end = text.find('"', i + 2);
    if (end == std::string::npos) break;
    out.emplace_back(i + 2, end);
  }
  return out;
}

std::string once(std::string t, Rng& rng, std::string& what) {
  if (t.empty()) return t;
  switch (rng.below(9)) {
    case 0: {  // flip one bit
      const size_t i = rng.below(t.size());
      t[i] = char(t[i] ^ (1 << rng.below(8)));
      what += "bitflip ";
      return t;
    }
    case 1: {  // replace one byte by any byte
      t[rng.below(t.size())] = char(rng.below(256));
      what += "byte ";
      return t;
    }
    case 2:
      what += "truncate ";
      return t.substr(0, rng.below(t.size()));
    case 3:
    case 4:
    case 5: {  // attribute value: a hostile one, or one from elsewhere in the file
      const auto v = values(t);
      if (v.empty()) return t;
      const auto [b, e] = v[rng.below(v.size())];
      std::string value = kHostile[rng.below(std::size(kHostile))];
      if (rng.below(4) == 0) {
        const auto [ob, oe] = v[rng.below(v.size())];
        value = t.substr(ob, oe - ob);
      }
      what += "value=" + value + " ";
      return t.substr(0, b) + value + t.substr(e);
    }
    case 6: {  // duplicate a line (an element, a child, an attribute line)
      auto l = lines(t);
      const size_t i = rng.below(l.size());
      l.insert(l.begin() + std::ptrdiff_t(i), l[i]);
      what += "dup-line ";
      return join(l);
    }
    case 7: {  // delete a line
      auto l = lines(t);
      l.erase(l.begin() + std::ptrdiff_t(rng.below(l.size())));
      what += "del-line ";
      return join(l);
    }
    default: {  // swap two lines
      auto l = lines(t);
      std::swap(l[rng.below(l.size())], l[rng.below(l.size())]);
      what += "swap-lines ";
      return join(l);
    }
  }
}

}  // namespace

std::string mutate(const std::string& text, Rng& rng, std::string& what) {
  std::string t = text;
  const size_t n = 1 + rng.below(3);
  for (size_t i = 0; i < n; ++i) t = once(std::move(t), rng, what);
  return t;
}

}  // namespace pvrt::robustness
