// legolize: a colored mesh to a LEGO model. This version builds the voxel grid with LEGO
// proportions (paper section 3) and writes it for inspection (--voxels-only); the brick layout
// and its stability-aware refinement (sections 4-7) come next.
#include <CLI/CLI.hpp>
#include <iostream>
#include <sstream>

#include "core/brick_catalog.h"
#include "core/error.h"
#include "ldraw/writer.h"
#include "mesh/mesh.h"
#include "voxel/palette.h"
#include "voxel/voxelize.h"

using namespace lego;

namespace {

constexpr int kInsideColor = 72;  // Dark Bluish Grey: voxels whose color does not matter (IGNORE)

// One 1x1 brick per kept voxel, a build step per layer.
Assembly voxel_assembly(const voxel::VoxelGrid& g, const voxel::Palette& palette) {
  Assembly a;
  const BrickType* one = BrickCatalog::standard().find_by_size(1, 1, kPlatesPerBrick);
  for (int y = 0; y < g.height; ++y)
    for (int z = 0; z < g.depth; ++z)
      for (int x = 0; x < g.width; ++x) {
        const voxel::Cell c = g.at(x, y, z);
        if (c == voxel::Cell::Empty) continue;
        Brick b;
        b.type = one;
        // LDraw is right-handed with -y up, and the lattice maps to it as (x, -y, z): taking mesh
        // z as lattice z would mirror the model. Flipping z makes it a half turn about x.
        b.min = {x, y * kPlatesPerBrick, g.depth - 1 - z};
        b.color =
            c == voxel::Cell::Surface ? palette.nearest(g.color[g.index(x, y, z)]) : kInsideColor;
        b.source.step = y + 1;
        a.bricks.push_back(b);
      }
  return a;
}

voxel::Palette parse_palette(const std::string& spec) {
  const auto& table = ldraw::ColorTable::standard();
  if (spec == "paper") return voxel::Palette::paper(table);
  if (spec == "all") return voxel::Palette::all(table);
  std::vector<int> codes;
  std::stringstream in(spec);
  for (std::string item; std::getline(in, item, ',');) {
    auto code = ldraw::parse_color_code(item);
    if (!code) throw InputError("", 0, "--palette: '" + item + "' is not an LDraw colour code");
    codes.push_back(*code);
  }
  return voxel::Palette::of(codes, table);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"legolize: turn a colored 3D mesh into a LEGO model"};
  std::string input, output, up = "y", palette_spec = "paper";
  int height = 20, shell = 3;
  size_t max_voxels = 8'000'000;
  bool voxels_only = false, solid = false;
  app.add_option(
         "mesh", input,
         "any mesh format Assimp reads (OBJ+MTL, STL, PLY, glTF/GLB, FBX, 3MF, OFF, DAE...)")
      ->required();
  app.add_option("-o,--output", output, "the LDraw file to write (.ldr or .mpd)")->required();
  app.add_flag("--voxels-only", voxels_only,
               "write the voxel grid as 1x1 bricks, one per kept voxel");
  app.add_option("--height", height, "model height in bricks (default 20)")
      ->check(CLI::Range(1, 10000));
  std::string size;
  double scale = 0;
  app.add_option("--size", size,
                 "fit within W studs x H bricks x D studs, as WxHxD (overrides --height)");
  app.add_option("--scale", scale, "millimetres per mesh unit (overrides --height and --size)")
      ->check(CLI::PositiveNumber);
  app.add_option("--up", up, "the mesh's up axis")->check(CLI::IsMember({"x", "y", "z"}));
  app.add_option("--shell", shell, "keep voxels within N voxels of the surface (default 3)")
      ->check(CLI::Range(1, 1000));
  app.add_flag("--solid", solid, "do not hollow");
  app.add_option("--palette", palette_spec,
                 "paper (the paper's eight colours), all, or LDraw codes: 15,4,1");
  app.add_option("--max-voxels", max_voxels, "refuse grids larger than this (default 8,000,000)");
  int default_color = -1;
  app.add_option("--default-color", default_color,
                 "LDraw colour for surfaces the mesh gives no colour (default: grey)");
  app.footer("Exit codes: 0 written; 2 usage error or bad input (the output is then not written).");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  if (!voxels_only) {
    std::cerr
        << "legolize: the brick layout and its refinement (paper sections 4-7) are not built yet; "
           "--voxels-only writes the voxel grid\n";
    return 2;
  }
  try {
    const voxel::Palette palette = parse_palette(palette_spec);
    mesh::MeshOptions mesh_options;
    if (default_color >= 0) {
      auto rgb = ldraw::ColorTable::standard().rgb(default_color);
      if (!rgb)
        throw InputError(
            "", 0,
            "--default-color: " + std::to_string(default_color) + " is not in the colour table");
      mesh_options.default_color = voxel::from_hex(*rgb);
    }
    mesh_options.up = up == "x" ? mesh::UpAxis::X : up == "z" ? mesh::UpAxis::Z : mesh::UpAxis::Y;
    const mesh::Mesh m = mesh::load_mesh(input, mesh_options);
    voxel::VoxelizeOptions vo{
        .height_bricks = height, .fit = {0, 0, 0}, .mm_per_unit = scale, .max_voxels = max_voxels};
    if (!size.empty()) {
      char x1 = 0, x2 = 0, extra = 0;
      std::istringstream in(size);
      if (!(in >> vo.fit[0] >> x1 >> vo.fit[1] >> x2 >> vo.fit[2]) || (x1 != 'x' && x1 != 'X') ||
          (x2 != 'x' && x2 != 'X') || (in >> extra) || vo.fit[0] < 1 || vo.fit[1] < 1 ||
          vo.fit[2] < 1)
        throw InputError("", 0,
                         "--size '" + size + "': expected WxHxD, three positive whole numbers");
    }
    voxel::VoxelGrid grid = voxel::voxelize(m, vo);
    if (!solid) voxel::hollow(grid, shell);
    Assembly a = voxel_assembly(grid, palette);
    ldraw::WriteOptions w;
    w.title = "Voxels of " + std::filesystem::path(input).filename().string();
    w.author = "legolize";
    ldraw::write_model(output, a, w);
    std::cout << output << ": " << grid.width << " x " << grid.height << " x " << grid.depth
              << " voxels, " << a.bricks.size() << " kept (" << grid.count(voxel::Cell::Surface)
              << " on the surface)\n";
  } catch (const InputError& e) {
    std::cerr << "legolize: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
