// legolize on meshes as people have them (issue 18): textures named the Windows way, declared
// and signed up axes, colours a builder can buy, scenes of several objects, thin parts, and
// outputs checked before any work. Each test writes its own small mesh; Debian's test models are
// used where installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <nlohmann/json.hpp>
#include "app/run_tool.h"

#include "ldraw/reader.h"
#include "test_paths.h"

namespace lego {
namespace {

namespace fs = std::filesystem;
using test::run_tool;

fs::path scratch(const std::string& name) {
  return test::scratch("lego_meshes_", name);
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// Colour code -> bricks of it in an LDraw file.
std::map<int, int> colours_of(const fs::path& model) {
  std::map<int, int> out;
  for (const auto& p : ldraw::read_file(model).parts) ++out[p.color];
  return out;
}

// An axis-aligned box as OBJ faces on vertices from `first` (1-based), with material `mtl`.
std::string obj_box(double x0, double y0, double z0, double x1, double y1, double z1, int first,
                    const std::string& mtl = "") {
  std::string s;
  for (int i = 0; i < 8; ++i)
    s += "v " + std::to_string(i & 1 ? x1 : x0) + " " + std::to_string(i & 2 ? y1 : y0) + " " +
         std::to_string(i & 4 ? z1 : z0) + "\n";
  if (!mtl.empty()) s += "usemtl " + mtl + "\n";
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces)
    s += "f " + std::to_string(first + f[0]) + " " + std::to_string(first + f[1]) + " " +
         std::to_string(first + f[2]) + " " + std::to_string(first + f[3]) + "\n";
  return s;
}

// A 2 x 2 red image as binary PPM (stb_image reads PNM).
void write_red_ppm(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary);
  out << "P6\n2 2\n255\n";
  for (int i = 0; i < 4; ++i) out << char(220) << char(10) << char(10);
}

// A textured quad standing in the xy plane, 8 x 8, whose material names `map`.
fs::path textured_quad(const fs::path& dir, const std::string& map) {
  fs::create_directories(dir);
  std::ofstream(dir / "quad.mtl") << "newmtl painted\nKd 1 1 1\nmap_Kd " << map << "\n";
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv 0 0 0\nv 8 0 0\nv 8 8 0\nv 0 8 0\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl painted\n"
                                     "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  return dir / "quad.obj";
}

TEST(LegolizeMeshes, TexturesAreFoundTheWayWindowsToolsNameThem) {
  // The mesh in model/, its texture in Textures/Red.ppm, named root-relative with backslashes
  // and in another case, as Collada and OBJ files exported on Windows do.
  write_red_ppm(scratch("Textures/Red.ppm"));
  const fs::path quad = textured_quad(scratch("model"), "\\..\\TEXTURES\\red.PPM");
  const fs::path out = scratch("quad.ldr"), report = scratch("quad.json");
  auto run = run_tool("legolize", {quad.string(), "--voxels-only", "--height", "8", "--palette",
                                   "4,1,15", "-o", out.string(), "--report", report.string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto colours = colours_of(out);
  EXPECT_GT(colours.count(4) ? colours.at(4) : 0, 0) << "the texture's red";
  EXPECT_EQ(colours.count(15), 0u) << "white would be the material colour: texture dropped";
  EXPECT_TRUE(read_json(report)["warnings"].empty());
}

// An FBX exported on another machine names its texture by that machine's absolute path; the
// file sits in a sibling folder of the mesh's (Assimp's own FBX/spider.fbx and OBJ/SpiderTex.jpg).
TEST(LegolizeMeshes, ATextureNamedByAnotherMachinesPathIsFoundInASiblingFolder) {
  write_red_ppm(scratch("set/OBJ/Red.ppm"));
  const fs::path quad = textured_quad(scratch("set/FBX"), "D:\\projects\\set\\OBJ\\red.ppm");
  const fs::path out = scratch("quad.ldr"), report = scratch("quad.json");
  const std::vector<std::string> args = {quad.string(), "--voxels-only", "--height", "8",
                                         "--palette",   "4,1,15",        "-o",       out.string(),
                                         "--report",    report.string()};
  auto run = run_tool("legolize", args);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_GT(colours_of(out)[4], 0) << "the texture's red";
  EXPECT_TRUE(read_json(report)["warnings"].empty()) << run.err;
  // Not there: the warning says where it looked, the parents' folders included.
  fs::remove(scratch("set/OBJ/Red.ppm"));
  run = run_tool("legolize", args);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find(scratch("set").string() + "/…/OBJ/red.ppm"), std::string::npos) << run.err;
}

TEST(LegolizeMeshes, ATextureThatCannotBeReadIsAWarningOrWithStrictAnError) {
  const fs::path quad = textured_quad(scratch("model"), "maps\\missing.png");
  const fs::path out = scratch("quad.ldr"), report = scratch("quad.json");
  auto run = run_tool("legolize", {quad.string(), "--voxels-only", "--height", "8", "--palette",
                                   "4,1,15", "-o", out.string(), "--report", report.string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("warning"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("maps\\missing.png"), std::string::npos) << run.err;
  const auto warnings = read_json(report)["warnings"];
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].get<std::string>().find("not found"), std::string::npos);
  EXPECT_GT(colours_of(out)[15], 0) << "the material's white stands in";
  // --strict: an error, and nothing written.
  const fs::path strict = scratch("strict.ldr");
  run = run_tool("legolize", {quad.string(), "--voxels-only", "--strict", "-o", strict.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("missing.png"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(strict));
}

// A 2 x 2 x 8 box standing along z, in a Collada file that declares Z_UP.
fs::path z_up_collada() {
  const fs::path p = scratch("tall.dae");
  std::string positions, indices;
  for (int i = 0; i < 8; ++i)
    positions += std::to_string(i & 1 ? 2 : 0) + " " + std::to_string(i & 2 ? 2 : 0) + " " +
                 std::to_string(i & 4 ? 8 : 0) + " ";
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces)
    for (int k : {0, 1, 2, 0, 2, 3}) indices += std::to_string(f[k]) + " ";
  std::ofstream(p)
      << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
         "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
         "<asset><unit name=\"meter\" meter=\"1\"/><up_axis>Z_UP</up_axis></asset>\n"
         "<library_geometries><geometry id=\"box\"><mesh>\n"
         "<source id=\"p\"><float_array id=\"pa\" count=\"24\">"
      << positions
      << "</float_array><technique_common><accessor source=\"#pa\" count=\"8\" stride=\"3\">"
         "<param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/>"
         "<param name=\"Z\" type=\"float\"/></accessor></technique_common></source>\n"
         "<vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/></vertices>\n"
         "<triangles count=\"12\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>"
      << indices
      << "</p></triangles></mesh></geometry></library_geometries>\n"
         "<library_visual_scenes><visual_scene id=\"s\"><node id=\"n\">"
         "<instance_geometry url=\"#box\"/></node></visual_scene></library_visual_scenes>\n"
         "<scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>\n";
  return p;
}

TEST(LegolizeMeshes, UpIsWhatTheFileDeclaresOrWhatTheUserNamesInItsCoordinates) {
  const fs::path dae = z_up_collada();
  auto voxels = [&](const std::vector<std::string>& up) {
    const fs::path out = scratch("tall.ldr"), report = scratch("tall.json");
    std::vector<std::string> args{dae.string(), "--voxels-only", "--height", "8",
                                  "-o",         out.string(),    "--report", report.string()};
    args.insert(args.end(), up.begin(), up.end());
    auto run = run_tool("legolize", args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return read_json(report);
  };
  // Upright: 8 layers over a 2-unit square (3 studs at 1.2 studs a layer).
  const auto automatic = voxels({});
  EXPECT_EQ(automatic["voxels"], nlohmann::json::array({3, 8, 3}));
  EXPECT_NE(automatic["up"].get<std::string>().find("up_axis"), std::string::npos);
  // --up z names the file's own z: upright too (Assimp's own turn is off then).
  const auto z = voxels({"--up", "z"});
  EXPECT_EQ(z["voxels"], nlohmann::json::array({3, 8, 3}));
  EXPECT_NE(z["up"].get<std::string>().find("--up"), std::string::npos);
  // --up y: the file's y is up, so the box lies on its side; -z stands it on its head.
  EXPECT_EQ(voxels({"--up", "y"})["voxels"][1].get<int>(), 8);
  EXPECT_GT(voxels({"--up", "y"})["voxels"][2].get<int>(), 8);
  EXPECT_EQ(voxels({"--up", "-z"})["voxels"], nlohmann::json::array({3, 8, 3}));
  auto bad = run_tool("legolize", {dae.string(), "--up", "w", "-o", scratch("x.ldr").string()});
  EXPECT_EQ(bad.exit_code, 2);
}

TEST(LegolizeMeshes, MinusYTurnsAnLDrawExportRightSideUp) {
  // A pyramid as LDraw tools export it (y down): its base at y = 0, its apex at y = -10.
  const fs::path stl = scratch("pyramid.stl");
  {
    std::ofstream out(stl);
    out << "solid pyramid\n";
    const double base[4][3] = {{0, 0, 0}, {10, 0, 0}, {10, 0, 10}, {0, 0, 10}};
    const double apex[3] = {5, -10, 5};
    auto facet = [&](const double* a, const double* b, const double* c) {
      out << "facet normal 0 0 0\nouter loop\n";
      for (const double* v : {a, b, c})
        out << "vertex " << v[0] << " " << v[1] << " " << v[2] << "\n";
      out << "endloop\nendfacet\n";
    };
    for (int k = 0; k < 4; ++k) facet(base[k], base[(k + 1) % 4], apex);
    facet(base[0], base[2], base[1]);
    facet(base[0], base[3], base[2]);
    out << "endsolid pyramid\n";
  }
  // Bricks per layer, from the bottom (LDraw y grows downwards).
  auto layers = [&](const std::vector<std::string>& up) {
    const fs::path out = scratch("pyramid.ldr");
    std::vector<std::string> args{stl.string(), "--voxels-only", "--solid", "--height", "6",
                                  "-o",         out.string()};
    args.insert(args.end(), up.begin(), up.end());
    EXPECT_EQ(run_tool("legolize", args).exit_code, 0);
    std::map<double, int, std::greater<>> per_y;
    for (const auto& p : ldraw::read_file(out).parts) ++per_y[p.transform.pos[1]];
    std::vector<int> out_layers;
    for (const auto& [y, n] : per_y) out_layers.push_back(n);
    return out_layers;
  };
  const auto upright = layers({"--up", "-y"});
  ASSERT_GE(upright.size(), 3u);
  EXPECT_GT(upright.front(), upright.back()) << "the wide base is at the bottom";
  const auto upside_down = layers({});
  EXPECT_LT(upside_down.front(), upside_down.back()) << "the file's y taken as up: apex down";
}

TEST(LegolizeMeshes, NavyStaysBlueSkinStaysSkinAndUncolouredIsGrey) {
  const fs::path obj = scratch("cube.obj");
  std::ofstream(scratch("cube.mtl")) << "newmtl navy\nKd 0 0 0.5\nnewmtl skin\nKd 1 0.8 0.65\n";
  std::ofstream(obj) << "mtllib cube.mtl\n"
                     << obj_box(0, 0, 0, 12, 12, 12, 1, "navy")
                     << obj_box(0, 12, 0, 12, 24, 12, 9, "skin");
  const fs::path out = scratch("cube.ldr");
  ASSERT_EQ(
      run_tool("legolize", {obj.string(), "--voxels-only", "--height", "8", "-o", out.string()})
          .exit_code,
      0);
  const auto colours = colours_of(out);
  EXPECT_GT(colours.count(272) + colours.count(1), 0u) << "navy is a blue";
  EXPECT_EQ(colours.count(0), 0u) << "never black";
  EXPECT_GT(colours.count(78), 0u) << "skin is Light Nougat";
  EXPECT_EQ(colours.count(25), 0u) << "never orange";
  // A mesh without colours comes out in the documented default, Light Bluish Grey.
  const fs::path plain = scratch("plain.obj");
  std::ofstream(plain) << obj_box(0, 0, 0, 8, 8, 8, 1);
  ASSERT_EQ(
      run_tool("legolize", {plain.string(), "--voxels-only", "--height", "4", "-o", out.string()})
          .exit_code,
      0);
  const auto grey = colours_of(out);
  EXPECT_GT(grey.count(71), 0u);
  EXPECT_EQ(grey.count(15), 0u);
}

TEST(LegolizeMeshes, AnObjectInTheAirStandsOnColumnsAndBrickcheckAgrees) {
  // One cube on the ground, another beside it and well above: two objects of one scene.
  const fs::path obj = scratch("two.obj");
  std::ofstream(obj) << obj_box(0, 0, 0, 12, 12, 12, 1) << obj_box(24, 24, 0, 36, 36, 12, 9);
  const fs::path mpd = scratch("two.mpd"), report = scratch("two.json");
  auto run = run_tool("legolize", {obj.string(), "--height", "12", "-o", mpd.string(), "--report",
                                   report.string(), "--quiet"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("under 1 object the mesh leaves in the air"), std::string::npos)
      << run.out;
  auto r = read_json(report);
  EXPECT_EQ(r["floating_objects"]["objects"], 1);
  EXPECT_GE(r["floating_objects"]["columns"].get<int>(), 1);
  EXPECT_EQ(r["floating_objects"]["still_floating"], 0);
  ASSERT_EQ(r["pieces"].size(), 1u);
  EXPECT_GT(r["supports"]["bricks"].get<int>(), 0);
  EXPECT_TRUE(r["steps"][0]["supports"].get<bool>()) << "columns from the ground, built first";
  // The file as delivered stands, as brickcheck reads it, step by step too.
  auto check = run_tool("brickcheck", {"--steps", mpd.string()});
  EXPECT_EQ(check.exit_code, 0) << check.out;
  // The columns are built from the ground up, a few bricks a step when steps are small.
  run = run_tool("legolize", {obj.string(), "--height", "12", "-o", mpd.string(), "--report",
                              report.string(), "--quiet", "--max-step-parts", "3"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  r = read_json(report);
  int in_support_steps = 0, support_steps = 0;
  bool supports_over = false;
  for (const auto& st : r["steps"]) {
    EXPECT_TRUE(st["stands"].get<bool>());
    if (!st["supports"].get<bool>()) {
      supports_over = true;
      continue;
    }
    EXPECT_FALSE(supports_over) << "the supports' steps come first";
    EXPECT_LE(st["new_bricks"].get<int>(), 3);
    ++support_steps;
    in_support_steps += st["new_bricks"].get<int>();
  }
  EXPECT_GT(support_steps, 1);
  EXPECT_EQ(in_support_steps, r["supports"]["bricks"].get<int>());
  // Every supports' step tells the builder the same: its own step says when to build it.
  std::ifstream written(mpd);
  std::set<std::string> said;
  for (std::string line; std::getline(written, line);)
    if (line.rfind("0 // Supports:", 0) == 0) said.insert(line);
  EXPECT_EQ(said.size(), 1u);
  // A block above the cube: its columns rest on the cube, so they come with the layers they
  // stand on, not first.
  const fs::path over = scratch("over.obj"), over_mpd = scratch("over.mpd");
  std::ofstream(over) << obj_box(0, 0, 0, 24, 12, 24, 1) << obj_box(0, 24, 0, 24, 36, 24, 9);
  run = run_tool("legolize", {over.string(), "--height", "12", "-o", over_mpd.string(), "--report",
                              report.string(), "--quiet"});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("each built with the layer it stands on"), std::string::npos) << run.out;
  r = read_json(report);
  EXPECT_EQ(r["floating_objects"]["objects"], 1);
  for (const auto& st : r["steps"]) EXPECT_FALSE(st["supports"].get<bool>());
  EXPECT_TRUE(r["steps_stand"].get<bool>());
  check = run_tool("brickcheck", {"--steps", over_mpd.string()});
  EXPECT_EQ(check.exit_code, 0) << check.out;
}

TEST(LegolizeMeshes, WithoutSupportsAnObjectInTheAirIsAPieceBuiltApartThatFloats) {
  const fs::path obj = scratch("two.obj");
  std::ofstream(obj) << obj_box(0, 0, 0, 12, 12, 12, 1) << obj_box(24, 24, 0, 36, 36, 12, 9);
  const fs::path mpd = scratch("two.mpd"), report = scratch("two.json");
  auto run = run_tool("legolize", {obj.string(), "--height", "12", "-o", mpd.string(), "--report",
                                   report.string(), "--quiet", "--no-supports"});
  // Built apart it stands, but where the mesh puts it nothing holds it: brickcheck says so of
  // the file, and so does legolize.
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  EXPECT_NE(run.out.find("piece 2 floats 8 layers up"), std::string::npos) << run.out;
  const auto check = run_tool("brickcheck", {mpd.string()});
  EXPECT_EQ(check.exit_code, 1) << check.out;
  EXPECT_NE(check.out.find("floating"), std::string::npos) << check.out;
  const auto r = read_json(report);
  EXPECT_FALSE(r["stable"].get<bool>());
  EXPECT_EQ(r["floating_objects"]["objects"], 0);
  ASSERT_EQ(r["pieces"].size(), 2u);
  EXPECT_TRUE(r["pieces"][0]["grounded"].get<bool>());
  EXPECT_FALSE(r["pieces"][1]["grounded"].get<bool>());
  EXPECT_EQ(r["pieces"][1]["lift_layers"].get<int>(), 8);
  EXPECT_EQ(r["pieces"][1]["submodel"], "two-piece-2.ldr");
  EXPECT_TRUE(r["pieces"][1]["stable"].get<bool>());
  EXPECT_EQ(r["bricks"].get<int>(),
            r["pieces"][0]["bricks"].get<int>() + r["pieces"][1]["bricks"].get<int>());
  // The submodel is in the file, placed where the object was: its lowest bricks 8 layers up
  // (a brick's LDraw position is the top of its body, one brick height above its bottom).
  std::ifstream in(mpd);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("0 FILE two-piece-2.ldr"), std::string::npos);
  const ldraw::Model model = ldraw::read_file(mpd);
  EXPECT_EQ(int(model.parts.size()), r["bricks"].get<int>());
  double lowest_of_piece = -1e9;  // LDraw y grows downwards: the largest y is the lowest
  for (const auto& p : model.parts)
    if (p.submodel.rfind("two-piece-2", 0) == 0)
      lowest_of_piece = std::max(lowest_of_piece, p.transform.pos[1]);
  EXPECT_DOUBLE_EQ(lowest_of_piece, -(8 + 1) * 24.0);
  // In an .ldr the piece follows as further steps, said in a comment.
  const fs::path ldr = scratch("two.ldr");
  ASSERT_EQ(run_tool("legolize", {obj.string(), "--height", "12", "-o", ldr.string(), "--quiet",
                                  "--no-step-analysis", "--no-supports"})
                .exit_code,
            1);
  std::ifstream lin(ldr);
  const std::string ltext((std::istreambuf_iterator<char>(lin)), {});
  EXPECT_NE(ltext.find("0 // Piece 2 of 2"), std::string::npos);
  // Two objects side by side on the ground are one piece, standing together.
  const fs::path pair = scratch("pair.obj");
  std::ofstream(pair) << obj_box(0, 0, 0, 12, 12, 12, 1) << obj_box(24, 0, 0, 36, 12, 12, 9);
  ASSERT_EQ(run_tool("legolize", {pair.string(), "--height", "6", "-o", scratch("pair.ldr"),
                                  "--report", report.string(), "--quiet", "--no-step-analysis"})
                .exit_code,
            0);
  const auto p = read_json(report);
  ASSERT_EQ(p["pieces"].size(), 1u);
  EXPECT_EQ(p["pieces"][0]["objects"].get<int>(), 2);
}

TEST(LegolizeMeshes, APieceBuiltApartHasItsOwnHeatMapCheckedWithTheOtherOutputs) {
  const fs::path obj = scratch("two.obj");
  std::ofstream(obj) << obj_box(0, 0, 0, 12, 12, 12, 1) << obj_box(24, 24, 0, 36, 36, 12, 9);
  const fs::path mpd = scratch("two.mpd"), heat = scratch("heat.ldr");
  auto run =
      run_tool("legolize", {obj.string(), "--height", "12", "-o", mpd.string(), "--heatmap",
                            heat.string(), "--quiet", "--no-step-analysis", "--no-supports"});
  ASSERT_EQ(run.exit_code, 1) << run.err;
  EXPECT_TRUE(fs::exists(heat));
  EXPECT_TRUE(fs::exists(scratch("heat-piece-2.ldr")));
  // The second piece's heat map is the file --report names: refused, nothing written.
  fs::remove(mpd);
  run = run_tool("legolize",
                 {obj.string(), "--height", "12", "-o", mpd.string(), "--heatmap", heat.string(),
                  "--report", scratch("heat-piece-2.ldr").string(), "--quiet", "--no-supports"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("name the same file"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(mpd));
}

TEST(LegolizeMeshes, AThinSpanIsJoinedWithAddedVoxelsAndTheReportSaysHowMany) {
  // Two towers joined at their top by a one-stud beam one layer thick and 18 studs long: no
  // brick is that long, so the layout cuts the beam into pieces that only added voxels join.
  // Mesh units are studs (--scale 8: 8 mm a unit), a layer 1.2 units.
  const fs::path obj = scratch("span.obj");
  std::ofstream(obj) << obj_box(0, 0, 0, 4, 7.2, 4, 1) << obj_box(22, 0, 0, 26, 7.2, 4, 9)
                     << obj_box(4, 6.05, 1.05, 22, 7.15, 1.95, 17);
  const fs::path out = scratch("span.ldr"), report = scratch("span.json");
  auto run = run_tool("legolize", {obj.string(), "--scale", "8", "--solid", "-o", out.string(),
                                   "--report", report.string(), "--quiet", "--no-step-analysis"});
  ASSERT_NE(run.exit_code, 2) << run.err;
  const auto r = read_json(report);
  EXPECT_TRUE(r["single_connected"].get<bool>()) << run.out;
  EXPECT_EQ(r["components"].get<int>(), 1);
  EXPECT_GT(r["voxels_added_to_join"].get<int>(), 0);
  EXPECT_GT(r["pieces_before_joining"].get<int>(), 1);
  EXPECT_EQ(r["pieces"][0]["voxels_added"], r["voxels_added_to_join"]);
  EXPECT_NE(run.out.find("voxels added to join thin parts"), std::string::npos) << run.out;
}

// A heavy slab on one thin post at its corner: no layout of it stands. legolize adds a column
// under what hangs, in the support colour, as a submodel built first; brickcheck agrees that the
// file and each of its steps stand. Without supports it says the model falls (exit 1).
TEST(LegolizeMeshes, WhatCannotStandGetsSupportsInASubmodelOfTheirOwn) {
  const fs::path obj = scratch("table.obj");
  std::ofstream(obj) << obj_box(0, 0, 0, 16, 57.6, 16, 1) << obj_box(0, 57.6, 0, 96, 86.4, 96, 9);
  const fs::path out = scratch("table.mpd"), report = scratch("table.json");
  // The refinement ends on --fail-max, not on a time limit that a slow machine could reach.
  const std::vector<std::string> args = {
      obj.string(), "--scale", "1",          "--fail-max", "10",           "--refine-seconds",
      "1e6",        "-o",      out.string(), "--report",   report.string()};
  auto run = run_tool("legolize", args);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("supports: 1 column of 5 bricks in Medium_Azure (322)"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("as the submodel table-supports.ldr"), std::string::npos) << run.out;
  const auto json = read_json(report);
  EXPECT_GE(json["supports"]["columns"].get<int>(), 1);
  EXPECT_EQ(json["supports"]["color"], 322);
  EXPECT_EQ(json["pieces"][0]["supports"]["bricks"], json["supports"]["bricks"]);
  EXPECT_GT(json["cm_gf_final"].get<double>(), 0);
  ASSERT_GE(json["steps"].size(), 2u);
  EXPECT_TRUE(json["steps"][0]["supports"].get<bool>());
  EXPECT_FALSE(json["steps"][1]["supports"].get<bool>());
  // The supports are the first step's submodel, every brick of it in the support colour.
  const ldraw::Model model = ldraw::read_file(out);
  ASSERT_FALSE(model.steps.empty());
  int supports = 0;
  for (const auto& p : model.parts)
    if (p.submodel == "table-supports.ldr") {
      ++supports;
      EXPECT_EQ(p.color, 322);
      EXPECT_EQ(p.step, 1);
    }
  EXPECT_EQ(supports, json["supports"]["bricks"].get<int>());
  auto check = run_tool("brickcheck", {out.string(), "--steps"});
  EXPECT_EQ(check.exit_code, 0) << check.out;
  // Another colour on request; none at all: the model falls.
  run = run_tool("legolize", {obj.string(), "--scale", "1", "--fail-max", "10", "-o", out.string(),
                              "--support-color", "14", "--quiet"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_GT(colours_of(out)[14], 0);
  run = run_tool("legolize", {obj.string(), "--scale", "1", "--fail-max", "10", "-o", out.string(),
                              "--no-supports", "--no-step-analysis", "--quiet"});
  EXPECT_EQ(run.exit_code, 1) << run.out;
  EXPECT_EQ(run.out.find("supports:"), std::string::npos) << run.out;
  EXPECT_EQ(colours_of(out).count(322), 0u);
  // Supports keep to the limits: with no brick of the support colour allowed, there are none.
  run = run_tool("legolize", {obj.string(), "--scale", "1", "--fail-max", "10", "-o", out.string(),
                              "--limit", "3003@322:0", "--limit", "3004@322:0", "--limit",
                              "3005@322:0", "--no-step-analysis", "--quiet"});
  EXPECT_EQ(run.exit_code, 1) << run.out;
  EXPECT_EQ(colours_of(out).count(322), 0u);
  // A refinement stopped by its time limit says so; supports take over from there.
  run = run_tool("legolize",
                 {obj.string(), "--scale", "1", "--refine-seconds", "0.001", "-o", out.string(),
                  "--report", report.string(), "--no-step-analysis", "--quiet"});
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find("(the refinement stopped at its time limit, --refine-seconds 0.001)"),
            std::string::npos)
      << run.out;
  EXPECT_TRUE(read_json(report)["refine_out_of_time"].get<bool>());
  EXPECT_GT(read_json(report)["supports"]["columns"].get<int>(), 0);
  run = run_tool("legolize", {obj.string(), "-o", out.string(), "--support-color", "9999"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--support-color: 9999 is not in the colour table"), std::string::npos)
      << run.err;
}

TEST(LegolizeMeshes, OutputsAreCheckedBeforeAnyWork) {
  const fs::path obj = scratch("cube.obj");
  std::ofstream(obj) << obj_box(0, 0, 0, 8, 8, 8, 1);
  const fs::path out = scratch("out.mpd");
  // Two options naming one file: a usage error, and the file is not made.
  auto run = run_tool("legolize", {obj.string(), "-o", out.string(), "--parts-list",
                                   (out.parent_path() / "." / "out.mpd").string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("name the same file"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));
  // A folder where no file can be made (/proc refuses new files, even to root).
  if (fs::is_directory("/proc/self")) {
    run = run_tool("legolize", {obj.string(), "-o", "/proc/legolize-test.mpd"});
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_NE(run.err.find("no file can be written"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("reading"), std::string::npos) << "refused before reading the mesh";
  }
  // A read-only output is one its owner meant to keep: refused, untouched. A writable one is
  // replaced and keeps its mode.
  const fs::path kept = scratch("kept.ldr");
  std::ofstream(kept) << "0 mine\n";
  fs::permissions(kept, fs::perms::owner_read | fs::perms::group_read);
  run = run_tool("legolize", {obj.string(), "--voxels-only", "-o", kept.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("read-only"), std::string::npos) << run.err;
  std::ifstream in(kept);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "0 mine\n");
  fs::permissions(kept, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  run = run_tool("legolize", {obj.string(), "--voxels-only", "-o", kept.string()});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(fs::status(kept).permissions(),
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_GT(fs::file_size(kept), 10u);
}

TEST(LegolizeMeshes, TheSameSeedGivesTheSameModelWhateverTheJobs) {
  // The table sample under a weight, whose refinement accepts candidates: the file written with
  // one thread and with two is the same.
  const fs::path table = test::data_dir() / ".." / ".." / "samples" / "table.obj";
  std::string texts[2];
  for (int jobs : {1, 2}) {
    const fs::path out = scratch("table.ldr");
    // No time limit on the refinement: where it would end depends on the machine's speed.
    auto run = run_tool(
        "legolize", {table.string(), "--scale", "1", "--load-top", "300", "--refine-seconds", "1e6",
                     "-o", out.string(), "--jobs", std::to_string(jobs), "--quiet"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find("accepted"), std::string::npos);
    std::ifstream in(out);
    texts[jobs - 1].assign(std::istreambuf_iterator<char>(in), {});
  }
  EXPECT_EQ(texts[0], texts[1]);
}

// Debian's assimp-testmodels, where installed: the cases the issue names.
TEST(LegolizeMeshes, DebianTestModels) {
  const fs::path models = "/usr/share/assimp/models";
  if (!fs::is_directory(models)) GTEST_SKIP() << "assimp-testmodels is not installed";
  // The earth's texture is named "\..\LWO\LWO2\MappingModes\EarthCylindric.jpg".
  const fs::path report = scratch("earth.json"), out = scratch("earth.ldr");
  auto run =
      run_tool("legolize", {(models / "Collada" / "earthCylindrical.DAE").string(), "--voxels-only",
                            "--height", "12", "-o", out.string(), "--report", report.string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(read_json(report)["warnings"].empty()) << run.err;
  const auto colours = colours_of(out);
  EXPECT_GT(colours.count(272) + colours.count(1), 0u) << "oceans";
  EXPECT_GT(colours.count(288) + colours.count(2) + colours.count(330) + colours.count(28), 0u)
      << "land";
  // The teapots scene: one piece, in one part, what is in the air on columns.
  const fs::path teapots = scratch("teapots.json");
  run = run_tool("legolize", {(models / "Collada" / "teapots.DAE").string(), "--height", "12", "-o",
                              scratch("teapots.mpd").string(), "--report", teapots.string(),
                              "--quiet", "--no-refine", "--no-step-analysis"});
  ASSERT_NE(run.exit_code, 2) << run.err;
  const auto t = read_json(teapots);
  EXPECT_TRUE(t["single_connected"].get<bool>()) << run.out;
  EXPECT_EQ(t["components"].get<int>(), 1);
  EXPECT_EQ(t["pieces"].size(), 1u);
  EXPECT_EQ(t["floating_objects"]["still_floating"], 0);
}

}  // namespace
}  // namespace lego
