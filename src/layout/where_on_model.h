#pragma once
// Where a brick of legolize's model is, in words a builder finds on the model rather than a voxel
// index: its layer, counted from 1 at the model's bottom (a layer is a brick high, as the voxels
// are), and its place in that layer in studs from the layer's nearest edges. Sides are those the
// booklet's pictures show (report/step_camera.h): the front is LDraw's -z side, the face on the
// pictures' left; the left is the -x end of that face. The mesh's front (+z in most formats, the
// side a modelling program shows first) is this front (layout/to_assembly.h turns it there).
#include <string>

#include "core/assembly.h"

namespace lego::layout {

// "at the front left corner of layer 4", "on the back edge of layer 2, 3 studs in from the
// right", "in layer 7, 2 studs in from the left and 5 from the front", ... Bricks on the lattice
// only (legolize's); the layer's edges are those of the bricks whose bottom is the brick's.
std::string where_on_model(const Assembly& assembly, int brick);

// What those words mean, for a reader who sees the booklet's pictures.
inline constexpr const char* kWhereOnModelKey =
    "Places are named as the pictures show the model: layers count from 1 at the bottom, the "
    "front is the face on the pictures' left and the right side the face on their right.";

}  // namespace lego::layout
