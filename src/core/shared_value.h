// A value that copies share: an immutable T behind a reference count, so that a million
// objects with the same finish hold one FinishDesc between them (16 bytes each, not 200).
// It reads like a pointer to const T and compares by value; changing it makes a new T for
// this copy alone, so sharing is never visible.
#pragma once

#include <memory>
#include <utility>

namespace pvrt {

template <class T>
class SharedValue {
 public:
  SharedValue() : p_(defaultValue()) {}                                   // T{}, shared by all defaults
  SharedValue(T value) : p_(std::make_shared<const T>(std::move(value))) {}  // NOLINT: a T is a SharedValue

  const T& operator*() const { return *p_; }
  const T* operator->() const { return p_.get(); }

  // Changes this copy only: `f` edits a fresh T, which then replaces the shared one.
  template <class F>
  void edit(F&& f) {
    T value = *p_;
    std::forward<F>(f)(value);
    p_ = std::make_shared<const T>(std::move(value));
  }

  bool sharesWith(const SharedValue& other) const { return p_ == other.p_; }
  bool operator==(const SharedValue& other) const { return p_ == other.p_ || *p_ == *other.p_; }

 private:
  static const std::shared_ptr<const T>& defaultValue() {
    static const std::shared_ptr<const T> value = std::make_shared<const T>();
    return value;
  }
  std::shared_ptr<const T> p_;
};

// Hands out SharedValues so that equal values share one T: a loader keeps one and passes
// each value it reads through it. It remembers the last few distinct values only (a scene
// has few finishes, and a generated one repeats them in any order), so it costs a handful
// of comparisons a value and never grows.
template <class T, int kRemembered = 16>
class SharingPool {
 public:
  SharedValue<T> share(T value) {
    for (int i = 0; i < count_; ++i)
      if (*recent_[i] == value) return recent_[i];
    SharedValue<T> made(std::move(value));
    recent_[next_] = made;
    next_ = (next_ + 1) % kRemembered;
    if (count_ < kRemembered) ++count_;
    return made;
  }

 private:
  SharedValue<T> recent_[kRemembered];
  int count_ = 0, next_ = 0;
};

}  // namespace pvrt
