#include "log_text.hpp"

#include <cstdio>
#include <cstring>

namespace mh {
namespace {

// The length of the UTF-8 sequence at `s` (at most `left` bytes), 0 when
// the bytes there are not one (RFC 3629: no overlong form, no surrogate,
// nothing above U+10FFFF).
std::size_t utf8_length(const unsigned char* s, std::size_t left) {
  const unsigned char c = s[0];
  std::size_t n = 0;
  unsigned char lo = 0x80;
  unsigned char hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (n > left) return 0;
  if (s[1] < lo || s[1] > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (s[i] < 0x80 || s[i] > 0xBF) return 0;
  return n;
}

}  // namespace

std::string log_text(const char* message) {
  if (message == nullptr) return "";
  const std::size_t size = std::strlen(message);
  const auto* s = reinterpret_cast<const unsigned char*>(message);
  std::string out;
  out.reserve(size < kLogTextLimit ? size : kLogTextLimit);
  std::size_t i = 0;
  char hex[8];
  while (i < size && out.size() < kLogTextLimit) {
    const unsigned char c = s[i];
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      out += static_cast<char>(c);
      ++i;
    } else if (c == '\\') {
      out += "\\\\";
      ++i;
    } else if (c == '\n') {
      out += "\\n";
      ++i;
    } else if (c == '\r') {
      out += "\\r";
      ++i;
    } else if (c == '\t') {
      out += "\\t";
      ++i;
    } else if (const std::size_t n = c >= 0x80 ? utf8_length(s + i, size - i) : 0; n > 0) {
      out.append(message + i, n);
      i += n;
    } else {
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
      ++i;
    }
  }
  if (i < size) out += "... (" + std::to_string(size - i) + " more bytes)";
  return out;
}

}  // namespace mh
