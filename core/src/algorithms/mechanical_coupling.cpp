// The topological coupling of joint coordinates (mechanical_coupling.hpp): with
// it the tangent of a tree of bounded depth has O(N) entries instead of N^2,
// and its factorization costs about O(N).
#include "monohydra/core/mechanical_coupling.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace mh {

std::vector<int> coordinates_moving(const Model& model, const std::vector<int>& bodies) {
  std::vector<int> out;
  for (int body : bodies) {
    if (body != kGround && (body < 0 || body >= model.num_bodies()))
      throw std::invalid_argument("coordinates_moving: no body " + std::to_string(body));
    for (int j = body; j != kGround; j = model.bodies[static_cast<size_t>(j)].parent)
      out.push_back(j);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<std::pair<int, int>> mechanical_coupling(const Model& model,
                                                     const std::vector<std::vector<int>>& groups) {
  std::vector<std::pair<int, int>> entries;
  for (int j = 0; j < model.num_bodies(); ++j) {
    for (int i = j; i != kGround; i = model.bodies[static_cast<size_t>(i)].parent) {
      entries.emplace_back(i, j);
      if (i != j) entries.emplace_back(j, i);
    }
  }
  const auto add_group = [&entries](const std::vector<int>& group) {
    for (int i : group)
      for (int j : group) entries.emplace_back(i, j);
  };
  for (const CutJoint& joint : model.cut_joints)
    add_group(coordinates_moving(model, {joint.a.body, joint.b.body}));
  for (const auto& group : groups) add_group(group);
  return entries;
}

}  // namespace mh
