// An SI unit's text ("Pa", "m^3/s", "N*m", "rad/s") as powers of the SI
// base units, for the BaseUnit elements of an FMU's UnitDefinitions (FMI
// 3.0, 2.4.3): what lets another tool convert a variable's unit.
#pragma once

#include <array>
#include <optional>
#include <string>

namespace mh::fmu {

// Exponents of kg, m, s, A, K, mol, cd, rad (FMI's BaseUnit attributes).
using BaseUnit = std::array<int, 8>;
inline constexpr std::array<const char*, 8> kBaseUnitNames = {"kg", "m",   "s",  "A",
                                                              "K",  "mol", "cd", "rad"};

// The powers of `unit`, or none when it is not a product of SI units and
// powers of them (it is then declared without a BaseUnit).
std::optional<BaseUnit> base_unit(const std::string& unit);

}  // namespace mh::fmu
