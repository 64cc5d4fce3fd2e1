#pragma once
// Steps a person can follow add a handful of parts each, close together (LEGO's booklets add a
// few, LPub3D's too): a layer of a sculpture is split into groups of nearby bricks.
#include <vector>

#include "core/assembly.h"

namespace lego::layout {

// `bricks` (indices into `assembly`) in groups of at most `at_most`, cut in halves across their
// longest extent again and again: compact groups of nearly equal size, in the order of the cuts
// (the low side first). One group when they are few or `at_most` is 0.
std::vector<std::vector<int>> nearby_groups(const Assembly& assembly,
                                            const std::vector<int>& bricks, int at_most);

}  // namespace lego::layout
