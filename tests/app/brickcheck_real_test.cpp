// brickcheck on what people build: small models written here with the official parts (from
// $LDRAWDIR or ../shared/ldraw-library; skipped without either), each pinning what a builder
// would say, and the properties every verdict must have.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <array>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "app/run_tool.h"
#include "test_paths.h"

namespace lego {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::run_tool;

std::string library() {
  return test::ldraw_library().string();
}

// The weakest contact is between parts `a` and `b`.
void expect_weakest_between(const json& j, const char* a, const char* b) {
  ASSERT_FALSE(j["weakest"].empty()) << j;
  EXPECT_EQ(j["weakest"][0]["a"]["part"], a);
  EXPECT_EQ(j["weakest"][0]["b"]["part"], b);
}

fs::path model(const std::string& name, const std::string& lines) {
  auto path = test::scratch("lego_real_", name);
  std::ofstream(path) << "0 " << name << "\n0 Name: " << name << "\n" << lines;
  return path;
}

json check(const fs::path& path, int expected_exit, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"--json", "--ldraw-dir", library()};
  args.insert(args.end(), extra.begin(), extra.end());
  args.push_back(path.string());
  auto run = run_tool("brickcheck", args);
  EXPECT_EQ(run.exit_code, expected_exit) << run.out << run.err;
  return json::parse(run.out);
}

// A 45° slope on a brick: its cells take the brick's studs; the brick's weight and its own stand
// on the ground.
TEST(BrickcheckReal, SlopeOnABrick) {
  SKIP_WITHOUT_LIBRARY();
  json j = check(model("slope.ldr",
                       "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3004.dat\n"
                       "1 4 10 -48 0 0 0 1 0 1 0 -1 0 0 3040b.dat\n"),
                 0);
  EXPECT_EQ(j["bricks"], 2);
  EXPECT_EQ(j["carried"].size(), 0u);
  EXPECT_EQ(j["components"], 1);
  EXPECT_NEAR(j["cm_gf"].get<double>(), 71.658, 1e-6);
}

// A jumper plate's stud sits half a stud off the lattice: a 2x2 plate takes it in its tube, a
// 1x2 plate cannot (its pin is in the way) and only lies on the jumper.
TEST(BrickcheckReal, AJumperStudInATube) {
  SKIP_WITHOUT_LIBRARY();
  const std::string base =
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3004.dat\n"
      "1 1 0 -32 0 1 0 0 0 1 0 0 0 1 3794a.dat\n";
  json j = check(model("jumper.ldr", base + "1 2 0 -40 0 1 0 0 0 1 0 0 0 1 3022.dat\n"), 0);
  EXPECT_EQ(j["bricks"], 3);
  EXPECT_EQ(j["carried"].size(), 0u) << j["carried"];
  EXPECT_EQ(j["components"], 1);
  json pin = check(model("jumper-pin.ldr", base + "1 2 0 -40 0 1 0 0 0 1 0 0 0 1 3023.dat\n"), 0);
  EXPECT_EQ(pin["bricks"], 2);
  ASSERT_EQ(pin["carried"].size(), 1u);
  EXPECT_EQ(pin["carried"][0]["part"], "3023");
  // A 1x8 plate reaching out from the 2x2 plate pulls on the jumper's stud in the tube: that is
  // the weakest contact, and the model turned 90° about the vertical says the same.
  json arm = check(model("jumper-arm.ldr", base + "1 2 0 -40 0 1 0 0 0 1 0 0 0 1 3022.dat\n"
                                                  "1 14 60 -48 10 1 0 0 0 1 0 0 0 1 3460.dat\n"),
                   0);
  // 71.243 gf; with the plate and its arm carried, their weight on the jumper, it was 71.477.
  const double cm = arm["cm_gf"].get<double>();
  EXPECT_LT(cm, 71.3);
  expect_weakest_between(arm, "3794a", "3022");
  json turned = check(model("jumper-arm-turned.ldr",
                            "1 4 0 -24 0 0 0 1 0 1 0 -1 0 0 3004.dat\n"
                            "1 1 0 -32 0 0 0 1 0 1 0 -1 0 0 3794a.dat\n"
                            "1 2 0 -40 0 0 0 1 0 1 0 -1 0 0 3022.dat\n"
                            "1 14 10 -48 -60 0 0 1 0 1 0 -1 0 0 3460.dat\n"),
                      0);
  EXPECT_NEAR(turned["cm_gf"].get<double>(), cm, 1e-6);
}

// Round plates stacked on a brick: each round plate's cell takes the stud under it.
TEST(BrickcheckReal, A6141Stack) {
  SKIP_WITHOUT_LIBRARY();
  std::string lines = "1 15 0 -24 0 1 0 0 0 1 0 0 0 1 3005.dat\n";
  for (int k = 0; k < 4; ++k)
    lines += "1 4 0 " + std::to_string(-32 - 8 * k) + " 0 1 0 0 0 1 0 0 0 1 6141.dat\n";
  json j = check(model("round.ldr", lines), 0);
  EXPECT_EQ(j["bricks"], 5);
  EXPECT_EQ(j["components"], 1);
  EXPECT_EQ(j["carried"].size(), 0u);
}

// SNOT: a plate on the headlight brick's side stud is held by that stud, sideways. Its weight
// pulls on the stud's friction, so C_M is below T, and the bottleneck is that connection.
TEST(BrickcheckReal, APlateOnA4070SideStud) {
  SKIP_WITHOUT_LIBRARY();
  auto path = model("snot.ldr",
                    "1 15 0 -24 0 1 0 0 0 1 0 0 0 1 4070.dat\n"
                    "1 4 0 -14 -14 1 0 0 0 0 -1 0 1 0 3024.dat\n");
  json j = check(path, 0);
  EXPECT_EQ(j["bricks"], 2);
  EXPECT_EQ(j["components"], 1) << "the side stud snaps";
  const double cm = j["cm_gf"].get<double>();
  EXPECT_LT(cm, 71.658);
  EXPECT_GT(cm, 60);
  expect_weakest_between(j, "4070", "3024");
  // The same model turned 90° about the vertical, and mirrored, has the same C_M.
  auto turned = model("snot-turned.ldr",
                      "1 15 0 -24 0 0 0 1 0 1 0 -1 0 0 4070.dat\n"
                      "1 4 -14 -14 0 0 1 0 0 0 -1 -1 0 0 3024.dat\n");
  EXPECT_NEAR(check(turned, 0)["cm_gf"].get<double>(), cm, 1e-6);
  auto mirrored = model("snot-mirrored.ldr",
                        "1 15 0 -24 0 1 0 0 0 1 0 0 0 -1 4070.dat\n"
                        "1 4 0 -14 14 1 0 0 0 0 -1 0 -1 0 3024.dat\n");
  EXPECT_NEAR(check(mirrored, 0)["cm_gf"].get<double>(), cm, 1e-6);
}

// A brick resting on a tile is held by its weight alone: it reaches the ground through the tile
// (a face contact from below) without a snap, and pulls nothing.
TEST(BrickcheckReal, ABrickRestingOnATile) {
  SKIP_WITHOUT_LIBRARY();
  json j = check(model("tile.ldr",
                       "1 7 0 -8 0 1 0 0 0 1 0 0 0 1 3068b.dat\n"
                       "1 4 0 -32 0 1 0 0 0 1 0 0 0 1 3003.dat\n"),
                 0);
  EXPECT_EQ(j["bricks"], 2);
  EXPECT_EQ(j["components"], 2) << "resting is not a snap";
  EXPECT_TRUE(j["floating"].empty());
  EXPECT_NEAR(j["cm_gf"].get<double>(), 71.658, 1e-6);
  // Lift the tile away: the brick floats, and the model says so (exit 1) with the part named.
  json lifted = check(model("no-tile.ldr",
                            "1 7 100 -8 0 1 0 0 0 1 0 0 0 1 3068b.dat\n"
                            "1 4 0 -32 0 1 0 0 0 1 0 0 0 1 3003.dat\n"),
                      1);
  ASSERT_EQ(lifted["floating_carried"].size(), 1u);
  EXPECT_EQ(lifted["floating_carried"][0]["line"], 4);
}

// Technic joints (issue 35): a 1 x 2 brick with a hole on a stack, another beside it held only
// by a pin through both holes, a 1 x 4 brick on the second reaching out. A pin turns: nothing
// holds the arm, and the report names the joints that would have to hold a moment about the pin
// (3.48 gf·stud: the 1 x 4's 1.74 g two studs out). Two pins hold it; an axle through axle holes
// holds it alone; a friction pin holds a little (kFrictionPinMoment, 5 gf·stud), so the arm
// stands on one, its grip in C_M.
TEST(BrickcheckReal, TechnicPinsTurnAxlesHold) {
  SKIP_WITHOUT_LIBRARY();
  const std::string stack =
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3004.dat\n"
      "1 4 0 -48 0 1 0 0 0 1 0 0 0 1 3700.dat\n"
      "1 1 0 -48 20 1 0 0 0 1 0 0 0 1 3700.dat\n";
  const std::string pin = "1 7 0 -38 10 0 0 1 0 1 0 -1 0 0 3673.dat\n";
  const std::string arm = "1 14 40 -72 20 1 0 0 0 1 0 0 0 1 3010.dat\n";
  const auto one_pin = model("one-pin.ldr", stack + arm + pin);
  json one = check(one_pin, 1);
  EXPECT_EQ(one["status"], "no equilibrium");
  EXPECT_EQ(one["components"], 1);
  ASSERT_EQ(one["technic_joints"].size(), 2u);
  EXPECT_EQ(one["technic_joints"][0]["kind"], "turns");
  ASSERT_EQ(one["turning"].size(), 2u) << one["turning"];
  EXPECT_NEAR(one["turning"][0]["moment_gf_stud"].get<double>(), 1.74 * 2, 1e-3);
  EXPECT_EQ(one["turning"][0]["b"]["part"], "3673");
  const auto text = run_tool("brickcheck", {"--ldraw-dir", library(), one_pin.string()});
  EXPECT_NE(text.out.find("no equilibrium: 2 joints turn and must not"), std::string::npos)
      << text.out;
  // The pair doubled, a pin through each level: the arm's pair cannot turn.
  json two = check(model("two-pins.ldr", stack + pin +
                                             "1 4 0 -72 0 1 0 0 0 1 0 0 0 1 3700.dat\n"
                                             "1 1 0 -72 20 1 0 0 0 1 0 0 0 1 3700.dat\n"
                                             "1 7 0 -62 10 0 0 1 0 1 0 -1 0 0 3673.dat\n"
                                             "1 14 40 -96 20 1 0 0 0 1 0 0 0 1 3010.dat\n"),
                   0);
  EXPECT_EQ(two["technic_joints"].size(), 4u);
  EXPECT_TRUE(two["turning"].empty());
  // One friction pin: it holds 5 gf·stud, the arm needs 3.48; its grip is a friction in C_M.
  json friction = check(
      model("friction-pin.ldr", stack + arm + "1 7 0 -38 10 0 0 1 0 1 0 -1 0 0 4459.dat\n"), 0);
  EXPECT_NEAR(friction["cm_gf"].get<double>(), 71.658 * (1 - 1.74 * 2 / 5), 1e-3);
  EXPECT_EQ(friction["weakest"][0]["b"]["part"], "4459");
}

// The turning-joint diagnosis takes each structure with no equilibrium alone (a town holds the same
// building many times): two copies of the one-pin arm, 200 LDU apart, each have their two joints
// named, with the moment the one alone needs.
TEST(BrickcheckReal, EachStructureThatTurnsIsDiagnosedAlone) {
  SKIP_WITHOUT_LIBRARY();
  std::string arms;
  for (int x : {0, 200})
    arms += fmt::format(
        "1 4 {0} -24 0 1 0 0 0 1 0 0 0 1 3004.dat\n"
        "1 4 {0} -48 0 1 0 0 0 1 0 0 0 1 3700.dat\n"
        "1 1 {0} -48 20 1 0 0 0 1 0 0 0 1 3700.dat\n"
        "1 14 {1} -72 20 1 0 0 0 1 0 0 0 1 3010.dat\n"
        "1 7 {0} -38 10 0 0 1 0 1 0 -1 0 0 3673.dat\n",
        x, x + 40);
  json j = check(model("two-arms.ldr", arms), 1);
  EXPECT_EQ(j["status"], "no equilibrium");
  EXPECT_EQ(j["components"], 2);
  ASSERT_EQ(j["turning"].size(), 4u) << j["turning"];
  std::set<double> xs;
  for (const auto& t : j["turning"]) {
    EXPECT_NEAR(t["moment_gf_stud"].get<double>(), 1.74 * 2, 1e-3) << t;
    EXPECT_EQ(t["b"]["part"], "3673") << t;
    xs.insert(t["b"]["position"][0].get<double>());
  }
  EXPECT_EQ(xs, (std::set<double>{0, 200}));
}

// `parts` parts, all analysed, with no assumed joint: two joined by one joint that turns.
void expect_analysed_on_one_turning_joint(const json& j, int parts, const char* a, const char* b) {
  EXPECT_EQ(j["bricks"], parts);
  EXPECT_TRUE(j["carried"].empty());
  EXPECT_TRUE(j["joints"].empty());
  ASSERT_EQ(j["technic_joints"].size(), 1u);
  EXPECT_EQ(j["technic_joints"][0]["kind"], "turns");
  EXPECT_EQ(j["technic_joints"][0]["a"]["part"], a);
  EXPECT_EQ(j["technic_joints"][0]["b"]["part"], b);
}

// A hinge between two walls: both halves are analysed, joined where their knuckles share the
// hinge's line by a joint that passes force but no moment about that line. Centred, the wall
// above stands on the hinge (with nothing assumed: --strict passes); a 1 x 6 brick across it,
// off its line by half a stud, turns it, and the report names the joint and the moment it
// would have to hold.
TEST(BrickcheckReal, AHingeTurnsUnderASideLoad) {
  SKIP_WITHOUT_LIBRARY();
  const std::string hinge =
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3004.dat\n"
      "1 15 0 -48 0 -1 0 0 0 1 0 0 0 -1 3937.dat\n"
      "1 15 0 -48 0 1 0 0 0 1 0 0 0 1 3938.dat\n";
  auto path = model("hinge.ldr", hinge + "1 4 0 -72 0 1 0 0 0 1 0 0 0 1 3004.dat\n");
  json j = check(path, 0, {"--strict"});
  expect_analysed_on_one_turning_joint(j, 4, "3937", "3938");
  EXPECT_TRUE(j["strict"]["passes"]);
  // A 1 x 3 across the hinge, centred on its line: it balances.
  json across = check(model("across.ldr", hinge + "1 2 10 -72 0 0 0 1 0 1 0 -1 0 0 3622.dat\n"), 0);
  EXPECT_TRUE(across["turning"].empty());
  // A 1 x 6 across it, its centre 10 LDU off the line: the hinge turns.
  auto side = model("side.ldr", hinge + "1 2 10 -72 -10 0 0 1 0 1 0 -1 0 0 3009.dat\n");
  json turned = check(side, 1);
  EXPECT_EQ(turned["status"], "no equilibrium");
  ASSERT_EQ(turned["turning"].size(), 1u) << turned["turning"];
  EXPECT_EQ(turned["turning"][0]["a"]["part"], "3937");
  EXPECT_EQ(turned["turning"][0]["b"]["part"], "3938");
  EXPECT_GT(turned["turning"][0]["moment_gf_stud"].get<double>(), 0);
  auto text = run_tool("brickcheck", {"--ldraw-dir", library(), side.string()});
  EXPECT_NE(text.out.find("1 joint turns and must not"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("side.ldr:4 3937 White at (0, -48, 0) and side.ldr:5 3938"),
            std::string::npos)
      << text.out;
}

// A plate hanging by its handle (2540) in a horizontal clip (6019) beside a brick: the handle is
// a bar, the clip grips it on its line, and the joint turns about that line, holding what a
// friction pin holds (docs/physics.md, "Joints"). The plate's own weight, a stud out, it holds;
// 20 g on its studs it does not, and the clip is the weakest contact. A bar that no clip holds
// (a lightsaber blade standing on a brick) is carried, saying so.
TEST(BrickcheckReal, APlateHangsByItsHandleInAClip) {
  SKIP_WITHOUT_LIBRARY();
  const auto hang = model("hang.ldr",
                          "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
                          "1 15 10 -8 -10 1 0 0 0 1 0 0 0 1 6019.dat\n"
                          "1 2 10 -8 -50 -1 0 0 0 1 0 0 0 -1 2540.dat\n");
  json j = check(hang, 0, {"--strict"});
  expect_analysed_on_one_turning_joint(j, 3, "6019", "2540");
  EXPECT_TRUE(j["strict"]["passes"]);
  const double held = j["cm_gf"].get<double>();
  EXPECT_GT(held, 60);
  EXPECT_LT(held, 71.658 - 1);  // the clip's grip holds the plate's moment, and is what binds
  json loaded = check(hang, 1, {"--load", "5=20"});
  EXPECT_LT(loaded["cm_gf"].get<double>(), 0);
  expect_weakest_between(loaded, "6019", "2540");
  // The same plate 10 LDU off the clip's line: no joint, and nothing holds it.
  json off = check(model("off.ldr",
                         "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
                         "1 15 10 -8 -10 1 0 0 0 1 0 0 0 1 6019.dat\n"
                         "1 2 10 -8 -60 -1 0 0 0 1 0 0 0 -1 2540.dat\n"),
                   1);
  EXPECT_TRUE(off["technic_joints"].empty());
  EXPECT_EQ(off["floating_carried"].size() + off["floating"].size(), 1u);
  json blade = check(model("blade.ldr",
                           "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
                           "1 0 10 -80 -10 1 0 0 0 1 0 0 0 1 30374.dat\n"),
                     0);
  ASSERT_EQ(blade["carried"].size(), 1u);
  EXPECT_EQ(blade["carried"][0]["reason"], "a bar no clip holds (what holds it is not modelled)");
}

// A lightsaber blade (30374, a bar) in a vertical clip (4085b): analysed, joined to the clip.
TEST(BrickcheckReal, ABarStandsInAVerticalClip) {
  SKIP_WITHOUT_LIBRARY();
  json j = check(model("clip.ldr",
                       "1 4 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
                       "1 15 10 -8 -10 1 0 0 0 1 0 0 0 1 4085b.dat\n"
                       "1 0 10 -60 -30 1 0 0 0 1 0 0 0 1 30374.dat\n"),
                 0);
  EXPECT_EQ(j["bricks"], 3);
  ASSERT_EQ(j["technic_joints"].size(), 1u);
  EXPECT_EQ(j["technic_joints"][0]["b"]["part"], "30374");
}

// An arm on a turntable: the top turns on the base about their shared vertical line, a joint
// that passes force and no moment about that line; gravity has none about it, so the arm is held
// as PHYSICS.md's check of a 1 x 8 brick on three knobs of the plate on the top. (The corpus's
// tower crane: its 96-part arm.)
TEST(BrickcheckReal, AnArmOnATurntable) {
  SKIP_WITHOUT_LIBRARY();
  // The top, a 4x4 plate on it and a 1 x 8 brick on the plate, over `under`.
  auto arm_over = [](const std::string& name, const std::string& under, int exit) {
    return check(model(name, under + "1 7 0 -24 0 1 0 0 0 1 0 0 0 1 3404.dat\n"
                                     "1 4 0 -32 0 1 0 0 0 1 0 0 0 1 3031.dat\n"
                                     "1 4 60 -56 10 1 0 0 0 1 0 0 0 1 3008.dat\n"),
                 exit);
  };
  json j = arm_over("turntable.ldr", "1 7 0 -24 0 1 0 0 0 1 0 0 0 1 3403.dat\n", 0);
  expect_analysed_on_one_turning_joint(j, 4, "3403", "3404");
  EXPECT_NEAR(j["cm_gf"].get<double>(), 71.658 - 3.08 / (4 * (2.5 + 1.5 + 0.5)), 1e-3);
  ASSERT_FALSE(j["weakest"].empty());
  EXPECT_EQ(j["weakest"][0]["b"]["part"], "3008");
  // Over a 2x4 brick instead of its base, the top turns on nothing: it and the arm are carried,
  // and float.
  json alone = arm_over("top-alone.ldr", "1 7 0 0 0 1 0 0 0 1 0 0 0 1 3001.dat\n", 1);
  EXPECT_EQ(alone["bricks"], 1);
  EXPECT_EQ(alone["floating_carried"].size(), 3u);
  for (const auto& c : alone["carried"])
    EXPECT_EQ(c["reason"], "its studs and receptacles meet nothing that stands") << c;
}

// A car on its tyres, on a table: its wheels turn on their pins, its tyres held by their rims,
// and the tyres reach the lowest plane and hold it up.
TEST(BrickcheckReal, ACarOnTyresOnATable) {
  SKIP_WITHOUT_SHARED();
  json j = check(test::shared_dir() / "ldraw-models" / "car.ldr", 0, {"--ground", "table"});
  EXPECT_EQ(j["skipped"].size(), 0u);
  EXPECT_TRUE(j["floating"].empty());
  EXPECT_TRUE(j["floating_carried"].empty());
  EXPECT_FALSE(j["cm_gf"].is_null());
  for (const auto& c : j["carried"]) EXPECT_NE(c["part"], "3641") << c;
  int turns = 0, holds = 0;
  for (const auto& t : j["technic_joints"]) {
    if (t["a"]["part"] == "4624" && t["b"]["part"] == "4600") turns += t["kind"] == "turns";
    if (t["a"]["part"] == "3641" && t["b"]["part"] == "4624") holds += t["kind"] == "holds";
  }
  EXPECT_EQ(turns, 4);
  EXPECT_EQ(holds, 4);
}

// `lines` turned about the vertical by a quarter turn, or mirrored across x = 0: each part's
// place and matrix premultiplied.
std::string transformed(const std::string& lines, const std::array<double, 9>& m) {
  std::istringstream in(lines);
  std::string out, line;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string type, colour, part;
    double p[3], r[9];
    f >> type >> colour >> p[0] >> p[1] >> p[2];
    for (double& x : r) f >> x;
    f >> part;
    double q[3] = {0, 0, 0}, s[9] = {0};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        q[i] += m[size_t(3 * i + k)] * p[k];
        for (int c = 0; c < 3; ++c) s[3 * i + c] += m[size_t(3 * i + k)] * r[3 * k + c];
      }
    out +=
        fmt::format("1 {} {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g} {}\n", colour,
                    q[0], q[1], q[2], s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], part);
  }
  return out;
}

// A car on two axles of wheel pins (4600) stands on its tyres, every part analysed: its wheels
// turn on the pins, its tyres hold on the rims. On one axle with a brick at one end, it tips
// about the axle (the wheels carried as rigid ground, as before, held it up). Drawn by eye, a
// wheel 3 LDU below its pin is still on it. Turned or mirrored, the verdicts are the same.
TEST(BrickcheckReal, ACarStandsOnWheelsThatTurn) {
  SKIP_WITHOUT_LIBRARY();
  auto axle = [](int z, int wheel_y) {
    std::string lines = fmt::format("1 7 0 0 {} 1 0 0 0 1 0 0 0 1 4600.dat\n", z);
    for (const int side : {-1, 1})
      for (const char* part : {"4624", "3641"})
        lines += fmt::format("1 0 {} {} {} 0 0 {} 0 1 0 {} 0 0 {}.dat\n", 30 * side, wheel_y, z,
                             -side, side, part);
    return lines;
  };
  const std::string plate = "1 4 0 -8 0 0 0 1 0 1 0 -1 0 0 3034.dat\n";
  const std::string end_brick = "1 1 10 -32 70 1 0 0 0 1 0 0 0 1 3005.dat\n";
  const std::array<double, 9> quarter{0, 0, 1, 0, 1, 0, -1, 0, 0},
      mirror{-1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::string car = plate + axle(-60, 5) + axle(60, 8) + end_brick;
  for (const auto& [name, lines] :
       {std::pair("car.ldr", car), std::pair("car-turned.ldr", transformed(car, quarter)),
        std::pair("car-mirrored.ldr", transformed(car, mirror))}) {
    SCOPED_TRACE(name);
    json j = check(model(name, lines), 0);
    EXPECT_EQ(j["bricks"], 12);
    EXPECT_TRUE(j["carried"].empty());
    int turns = 0, holds = 0;
    for (const auto& t : j["technic_joints"]) {
      turns += t["kind"] == "turns";
      holds += t["kind"] == "holds";
    }
    EXPECT_EQ(turns, 4);
    EXPECT_EQ(holds, 4);
  }
  const std::string one_axle = plate + axle(0, 5) + end_brick;
  for (const auto& [name, lines] :
       {std::pair("one-axle.ldr", one_axle),
        std::pair("one-axle-turned.ldr", transformed(one_axle, quarter)),
        std::pair("one-axle-mirrored.ldr", transformed(one_axle, mirror))}) {
    SCOPED_TRACE(name);
    json j = check(model(name, lines), 1);
    EXPECT_EQ(j["status"], "no equilibrium");
    EXPECT_TRUE(j["carried"].empty());
  }
  // Without the brick at its end it balances on the one axle.
  check(model("balanced.ldr", plate + axle(0, 5)), 0);
}

// A wheel whose holder's grip is not derived (a wheel centre's stub axles in 2415's wheel clips)
// is carried with its tyre, as wheels were before they were analysed: on the ground they hold the
// holder as the ground does.
TEST(BrickcheckReal, AWheelOnAHolderNotDerivedIsCarried) {
  SKIP_WITHOUT_LIBRARY();
  json j = check(model("clips.ldr",
                       "1 7 0 -24 0 1 0 0 0 1 0 0 0 1 2415.dat\n"
                       "1 7 0 -3 20 1 0 0 0 1 0 0 0 1 3464.dat\n"
                       "1 0 0 -3 20 0 0 -1 0 1 0 1 0 0 59895.dat\n"),
                 0);
  ASSERT_EQ(j["carried"].size(), 2u);
  for (const auto& c : j["carried"])
    EXPECT_EQ(c["reason"],
              "a wheel or tyre on no pin or axle we find (what holds it is not modelled)");
  EXPECT_EQ(j["bricks"], 1);
  EXPECT_TRUE(j["floating"].empty());
}

// A building on a baseplate: the baseplate is the ground; a brick cantilevered from a column on
// it pulls on the column's studs, not on the baseplate's.
TEST(BrickcheckReal, ABuildingOnA3811) {
  SKIP_WITHOUT_LIBRARY();
  json j = check(model("base.ldr",
                       "1 2 0 0 0 1 0 0 0 1 0 0 0 1 3811.dat\n"
                       "1 4 10 -24 10 1 0 0 0 1 0 0 0 1 3005.dat\n"
                       "1 4 10 -48 10 1 0 0 0 1 0 0 0 1 3005.dat\n"
                       "1 14 80 -72 10 1 0 0 0 1 0 0 0 1 3008.dat\n"),
                 0);
  ASSERT_EQ(j["fixed"].size(), 1u);
  EXPECT_EQ(j["fixed"][0]["part"], "3811");
  EXPECT_EQ(j["components"], 1);
  // A 1x8 held by one knob at its end: as the paper's check, with a 1x1 column.
  EXPECT_LT(j["cm_gf"].get<double>(), 71.658);
  EXPECT_EQ(j["weakest"][0]["b"]["part"], "3008");
  // A part the user names is ground too.
  json named = check(model("named.ldr",
                           "1 4 10 -24 10 1 0 0 0 1 0 0 0 1 3005.dat\n"
                           "1 4 10 -48 10 1 0 0 0 1 0 0 0 1 3005.dat\n"),
                     0, {"--ground-part", "4"});
  ASSERT_EQ(named["fixed"].size(), 1u);
  EXPECT_EQ(named["fixed"][0]["line"], 4);
}

// Replacing a carried part by an analysed equivalent never lowers coverage.
TEST(BrickcheckRealProperty, AnalysingACarriedPartNeverLowersCoverage) {
  SKIP_WITHOUT_LIBRARY();
  const std::string base =
      "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
      "1 4 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n";
  // Turned 45 degrees about its middle, neither of its receptacles is on a stud (a 1 x 1 brick
  // turned so about its one receptacle would be: analysed since its stud is in it).
  const std::string angled = "1 4 -20 -72 -10 0.71 0 0.71 0 1 0 -0.71 0 0.71 3004.dat\n";
  const std::string upright = "1 4 -20 -72 -10 1 0 0 0 1 0 0 0 1 3004.dat\n";
  json a = check(model("angled.ldr", base + angled), 0);
  json b = check(model("upright.ldr", base + upright), 0);
  EXPECT_EQ(a["carried"].size(), 1u);
  EXPECT_EQ(b["carried"].size(), 0u);
  EXPECT_GT(b["bricks"].get<int>(), a["bricks"].get<int>());
}

// The command line as a pre-commit hook uses it.
TEST(BrickcheckRealCli, OptionsNeverSwallowFilesAndLibrariesAreChecked) {
  auto path = model("two.ldr",
                    "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n"
                    "1 4 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n");
  auto run = run_tool("brickcheck", {"--json", "--load", "4=50", path.string()});
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(json::parse(run.out)["file"], path.string());
  run = run_tool("brickcheck", {"--ground-part", "3", "--load", "4=5", path.string()});
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  auto not_a_library = test::scratch("lego_real_", "empty-dir");
  fs::create_directories(not_a_library);
  run = run_tool("brickcheck", {"--ldraw-dir", not_a_library.string(), path.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("is not an LDraw library"), std::string::npos) << run.err;
  run = run_tool("brickcheck", {"--ground-part", "99", path.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.out.find("no part is placed by that line"), std::string::npos) << run.out;
  for (const char* bad : {"99999999999=5", "5=1e999", "4=-1", "4=nan"})
    EXPECT_EQ(run_tool("brickcheck", {"--load", bad, path.string()}).exit_code, 2) << bad;
  EXPECT_EQ(
      run_tool("brickcheck", {"--load", std::string(60000, '1') + "=5", path.string()}).exit_code,
      2);
}

}  // namespace
}  // namespace lego
