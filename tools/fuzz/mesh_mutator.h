#pragma once
// Small meshes as OBJ (with its MTL), PLY and STL text, written here and then damaged the way
// exporters and truncated downloads damage them (issue 19): numbers that are not numbers or are
// huge, indices out of range, headers that lie about their counts, cut files, slivers.
#include <string>

#include "ldraw_mutator.h"  // Rng

namespace lego::fuzz {

enum class MeshFormat { Obj, Ply, Stl };
inline constexpr int kMeshFormats = 3;
const char* name(MeshFormat format);

struct MeshFile {
  std::string extension;  // ".obj", ".ply", ".stl"
  std::string text;
  std::string mtl;  // OBJ only: the material library it names ("mesh.mtl"), or empty
};

MeshFile mutated_mesh(MeshFormat format, Rng& rng);

}  // namespace lego::fuzz
