// Which joint coordinates the mechanics couple, from the topology alone: the
// structural nonzeros of the Newton tangent's mechanical block when the
// formulation's unknowns are the joint coordinates. M', K and C (Eqs. 5-12)
// couple coordinates i and j only when one joint is an ancestor of the other
// (or is the other): the body terms of a subtree enter the rows of its joint
// and of the joints above it. A cut joint's constraint terms (Sect. 2.2: Phi_z,
// Phi_z^T v and their derivatives) couple every coordinate that moves one of
// its two bodies with every other such; a subsystem's point forces likewise
// every coordinate that moves one of its points.
#pragma once

#include <utility>
#include <vector>

#include "monohydra/core/model.hpp"

namespace mh {

// The coordinates that move any of `bodies` (the joints on their paths to the
// ground), sorted, without repeats; the ground moves with none.
std::vector<int> coordinates_moving(const Model& model, const std::vector<int>& bodies);

// (row, col) pairs of the N x N mechanical block: every ancestor pair of the
// tree in both orders (the diagonal included), every pair within each of
// `groups` (each a set of coordinates that one cut joint or one subsystem's
// points couple, e.g. from coordinates_moving), and every pair within the
// coordinates each cut joint of the model moves.
std::vector<std::pair<int, int>> mechanical_coupling(const Model& model,
                                                     const std::vector<std::vector<int>>& groups);

}  // namespace mh
