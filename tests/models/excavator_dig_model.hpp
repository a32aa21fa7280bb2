// The load-sensing excavator (models/excavator-ls.yaml) with its bucket's
// edge in the ground, as the digging tests take it: a cohesive sand 1.9 m
// below the slew's axis (bucket-soil, docs/soil.md), the bucket's 1.2 m edge
// at its floor's front (the bucket frame's (1.25, 0, -0.58)), the floor
// behind it, the cut towards the machine (-x at slew 0); its cycle cut to
// its first 8 s (arm in, boom down, bucket curl, then boom up).
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace mh::test {

inline constexpr const char* kExcavatorSoil =
    "  - {name: soil, type: bucket-soil, width: 1.2, density: 1800, friction_angle: 0.6,\n"
    "     interface_friction: 0.4, cohesion: 10e3, adhesion: 3e3, ground_level: -1.9,\n"
    "     edge_thickness: 0.03,\n"
    "     points: {edge: {body: bucket, at: [1.25, 0, -0.58]},\n"
    "              heel: {body: bucket, at: [0.85, 0, -0.58]},\n"
    "              side: {body: bucket, at: [1.25, 0.6, -0.58]}}}\n";

// The model's text, with the soil when `digging` (the same 8 s in air without).
inline std::string excavator_dig_model(bool digging) {
  std::ifstream in(source_path("models/excavator-ls.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string model = text.str();
  const size_t nodes = model.find("\nnodes:");
  EXPECT_NE(nodes, std::string::npos);
  if (digging && nodes != std::string::npos) model.insert(nodes + 1, kExcavatorSoil);
  const size_t end = model.find("t_end: 22,");
  EXPECT_NE(end, std::string::npos);
  if (end != std::string::npos) model.replace(end, 10, "t_end: 8,");
  return model;
}

}  // namespace mh::test
