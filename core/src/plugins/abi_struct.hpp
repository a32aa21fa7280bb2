// The one versioning rule of the ABI (types.h, docs/sdk.md), enforced here and
// nowhere else: every struct that crosses the boundary begins with
// struct_size, the sizeof of its writer's SDK; the host reads a plugin's
// struct, and writes into one, only up to the smaller of that size and its
// own. Fields an older plugin does not have read as zero (NULL: "not
// supported"); fields a newer plugin has are ignored.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace mh {

// A copy of *p as this host's T: the plugin's first struct_size bytes, the
// rest zero. struct_size itself is kept as the plugin wrote it. T must begin
// with uint32_t struct_size. A size below that of struct_size reads as empty.
template <class T>
T read_struct(const T* p) {
  T out{};
  if (p == nullptr) return out;
  uint32_t size = 0;
  std::memcpy(&size, p, sizeof size);
  const size_t n = std::min<size_t>(size, sizeof(T));
  if (n >= sizeof size) std::memcpy(static_cast<void*>(&out), p, n);
  return out;
}

// Writes `value` into the plugin's *p up to the plugin's struct_size (which
// stays as the plugin set it). Returns false when p is NULL or too small to
// hold even struct_size.
template <class T>
bool write_struct(T* p, const T& value) {
  if (p == nullptr) return false;
  uint32_t size = 0;
  std::memcpy(&size, p, sizeof size);
  if (size < sizeof size) return false;
  const size_t n = std::min<size_t>(size, sizeof(T));
  std::memcpy(reinterpret_cast<unsigned char*>(p) + sizeof size,
              reinterpret_cast<const unsigned char*>(&value) + sizeof size, n - sizeof size);
  return true;
}

// Whether the plugin's struct (of struct_size `size`) has the field at
// `offset` of `field_size` bytes: how hosts test for appended fields.
inline bool has_field(uint32_t size, size_t offset, size_t field_size) {
  return offset + field_size <= size;
}

}  // namespace mh
