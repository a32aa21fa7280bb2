// An array the host hands a plugin to write, followed by guard words the
// host sets when it sizes the array and checks after each call: a plugin
// that writes past the end is named (with the call and the array), instead
// of corrupting the host's memory after it unseen. Begin, end, size and
// indexing are the array's own; the guard is past end().
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace mh {

class GuardedArray {
 public:
  GuardedArray() { arm(); }

  // Guard words after the array: an overrun by up to this many entries
  // lands in them (and a longer one still changes them, unless it skips them).
  static constexpr size_t kGuardWords = 4;

  void resize(size_t n) {
    storage_.resize(n + kGuardWords);
    size_ = n;
    arm();
  }
  void assign(size_t n, double value) {
    resize(n);
    std::fill(storage_.begin(), storage_.begin() + static_cast<std::ptrdiff_t>(n), value);
  }
  double* data() { return storage_.data(); }
  const double* data() const { return storage_.data(); }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  double* begin() { return storage_.data(); }
  double* end() { return storage_.data() + size_; }
  const double* begin() const { return storage_.data(); }
  const double* end() const { return storage_.data() + size_; }
  double& operator[](size_t i) { return storage_[i]; }
  double operator[](size_t i) const { return storage_[i]; }

  // The guard words as set: nothing was written past the end since.
  bool intact() const {
    // Word by word, without a call: it runs after every evaluate.
    const double* guard = storage_.data() + size_;
    uint64_t differs = 0;
    for (size_t i = 0; i < kGuardWords; ++i) {
      uint64_t bits = 0;
      std::memcpy(&bits, guard + i, sizeof bits);
      differs |= bits ^ kGuard[i];
    }
    return differs == 0;
  }
  // Sets the guard words again (after an overrun was reported).
  void arm() { std::memcpy(storage_.data() + size_, kGuard, sizeof kGuard); }

 private:
  // NaNs with a payload no arithmetic produces, compared as bits.
  static constexpr uint64_t kGuard[kGuardWords] = {0x7ff4dead0bad0001, 0x7ff4dead0bad0002,
                                                   0x7ff4dead0bad0003, 0x7ff4dead0bad0004};
  std::vector<double> storage_ = std::vector<double>(kGuardWords);
  size_t size_ = 0;
};

}  // namespace mh
