#include "stability_text.hpp"

#include <cmath>
#include <cstdio>

namespace mh::cli {
namespace {

// A time step in ms with 3 significant digits.
std::string ms(double seconds) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.3g ms", 1e3 * seconds);
  return buf;
}

std::string number(double v) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.4g", v);
  return buf;
}

}  // namespace

std::string stability_text(const ExplicitStability& s) {
  if (s.checks == 0) return "";
  std::string text = s.unstable ? "unstable: " : "stable: ";
  text += "dt = " + ms(s.h) + ", |R| = " + number(s.amplification) +
          " (lambda = " + number(s.eigenvalue.real()) +
          (s.eigenvalue.imag() < 0.0 ? " - " : " + ") + number(std::abs(s.eigenvalue.imag())) +
          "i 1/s";
  if (s.unstable) text += ", at t = " + number(s.t) + " s";
  text += "), ";
  text += std::isinf(s.stable_dt) ? "stable at every dt" : "stable below ~ " + ms(s.stable_dt);
  return text;
}

std::string stability_cost_text(const ExplicitStability& s) {
  return std::to_string(s.checks) + (s.checks == 1 ? " check, " : " checks, ") +
         (s.skipped > 0 ? std::to_string(s.skipped) + " skipped (a rate solve failed), " : "") +
         number(1e3 * s.cpu_seconds) + " ms CPU";
}

}  // namespace mh::cli
