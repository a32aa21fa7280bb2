#include "si_unit.hpp"

#include <cstdlib>
#include <utility>
#include <vector>

namespace mh::fmu {

namespace {

// The named SI units a model uses, in base units (kg, m, s, A, K, mol, cd, rad).
const std::vector<std::pair<std::string, BaseUnit>>& named_units() {
  static const std::vector<std::pair<std::string, BaseUnit>> units = {
      {"kg", {1, 0, 0, 0, 0, 0, 0, 0}},  {"m", {0, 1, 0, 0, 0, 0, 0, 0}},
      {"s", {0, 0, 1, 0, 0, 0, 0, 0}},   {"A", {0, 0, 0, 1, 0, 0, 0, 0}},
      {"K", {0, 0, 0, 0, 1, 0, 0, 0}},   {"mol", {0, 0, 0, 0, 0, 1, 0, 0}},
      {"cd", {0, 0, 0, 0, 0, 0, 1, 0}},  {"rad", {0, 0, 0, 0, 0, 0, 0, 1}},
      {"N", {1, 1, -2, 0, 0, 0, 0, 0}},  {"Pa", {1, -1, -2, 0, 0, 0, 0, 0}},
      {"J", {1, 2, -2, 0, 0, 0, 0, 0}},  {"W", {1, 2, -3, 0, 0, 0, 0, 0}},
      {"V", {1, 2, -3, -1, 0, 0, 0, 0}}, {"Hz", {0, 0, -1, 0, 0, 0, 0, 0}},
      {"C", {0, 0, 1, 1, 0, 0, 0, 0}},   {"ohm", {1, 2, -3, -2, 0, 0, 0, 0}},
      {"1", {0, 0, 0, 0, 0, 0, 0, 0}},
  };
  return units;
}

// One factor: a named unit with an optional integer power ("m^3", "s^-1").
bool add_factor(const std::string& factor, int sign, BaseUnit& out) {
  const std::size_t caret = factor.find('^');
  const std::string name = factor.substr(0, caret);
  int power = 1;
  if (caret != std::string::npos) {
    const std::string digits = factor.substr(caret + 1);
    char* end = nullptr;
    const long p = std::strtol(digits.c_str(), &end, 10);
    if (digits.empty() || end != digits.c_str() + digits.size()) return false;
    power = static_cast<int>(p);
  }
  for (const auto& [unit_name, dims] : named_units()) {
    if (unit_name != name) continue;
    for (std::size_t k = 0; k < out.size(); ++k) out[k] += sign * power * dims[k];
    return true;
  }
  return false;
}

}  // namespace

std::optional<BaseUnit> base_unit(const std::string& unit) {
  if (unit.empty()) return std::nullopt;
  BaseUnit out{};
  int sign = 1;
  std::string factor;
  for (std::size_t i = 0; i <= unit.size(); ++i) {
    const char c = i < unit.size() ? unit[i] : '\0';
    if (c == '*' || c == '/' || c == '.' || c == ' ' || c == '\0') {
      if (factor.empty() || !add_factor(factor, sign, out)) return std::nullopt;
      factor.clear();
      if (c == '/') sign = -1;  // everything after a '/' divides ("kg/(m*s)" is not read)
    } else if (c == '(' || c == ')') {
      return std::nullopt;
    } else {
      factor += c;
    }
  }
  return out;
}

}  // namespace mh::fmu
