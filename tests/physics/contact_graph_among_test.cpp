// A build step's contacts taken from the whole model's (ContactGraph::among) are what a search
// of the step's own model finds, contact for contact and in the same order: on the official sets
// and the 120 Datsville models (plates, tiles, slopes, SNOT, hinges, Technic, baseplates), for
// their first parts as drawn and for parts taken at random.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/random.h"
#include "ldraw/reader.h"
#include "parts/assembly_builder.h"
#include "physics/contact_graph.h"
#include "test_paths.h"

namespace lego::physics {
namespace {

void expect_same(const ContactGraph& taken, const ContactGraph& found, const std::string& what) {
  ASSERT_EQ(taken.contacts.size(), found.contacts.size()) << what;
  EXPECT_EQ(taken.ground_height, found.ground_height) << what;
  EXPECT_EQ(taken.tips_over, found.tips_over) << what;
  EXPECT_EQ(taken.fixed, found.fixed) << what;
  EXPECT_EQ(taken.overlaps, found.overlaps) << what;
  EXPECT_EQ(taken.contacts_of, found.contacts_of) << what;
  EXPECT_EQ(taken.lattice_joints, found.lattice_joints) << what;
  EXPECT_EQ(taken.pivot_joints, found.pivot_joints) << what;
  EXPECT_EQ(taken.shaft_joints, found.shaft_joints) << what;
  for (size_t k = 0; k < taken.contacts.size(); ++k) {
    const Contact &x = taken.contacts[k], &y = found.contacts[k];
    const std::string at = what + ", contact " + std::to_string(k);
    EXPECT_EQ(x.lower, y.lower) << at;
    EXPECT_EQ(x.upper, y.upper) << at;
    EXPECT_EQ(x.direction, y.direction) << at;
    EXPECT_EQ(x.plane, y.plane) << at;
    EXPECT_EQ(x.patch.u0, y.patch.u0) << at;
    EXPECT_EQ(x.patch.v0, y.patch.v0) << at;
    EXPECT_EQ(x.patch.u1, y.patch.u1) << at;
    EXPECT_EQ(x.patch.v1, y.patch.v1) << at;
    EXPECT_EQ(x.studs, y.studs) << at;
    EXPECT_EQ(x.support, y.support) << at;
    EXPECT_EQ(x.misaligned, y.misaligned) << at;
    EXPECT_EQ(x.turned, y.turned) << at;
    EXPECT_EQ(x.joint, y.joint) << at;
    EXPECT_EQ(x.joint_kind, y.joint_kind) << at;
    EXPECT_EQ(x.joint_point, y.joint_point) << at;
    EXPECT_EQ(x.joint_axis, y.joint_axis) << at;
    EXPECT_EQ(x.joint_friction, y.joint_friction) << at;
    ASSERT_EQ(x.point_count, y.point_count) << at;
    for (uint32_t p = 0; p < x.point_count; ++p) {
      const FrictionPoint &a = taken.friction_points[x.first_point + p],
                          &b = found.friction_points[y.first_point + p];
      EXPECT_EQ(a.x, b.x) << at;
      EXPECT_EQ(a.y, b.y) << at;
      EXPECT_EQ(a.z, b.z) << at;
      EXPECT_EQ(a.share, b.share) << at;
    }
  }
}

ldraw::Model read(const std::filesystem::path& file) {
  ldraw::ReadOptions options;
  options.library_dirs = {test::shared_dir() / "ldraw-library"};
  return ldraw::read_file(file, options);
}

// The model's parts as a build step has them: the ground given, no carried parts. (The
// conversion keeps the parts' types.)
parts::AssemblyConversion steps_model(const std::filesystem::path& file,
                                      parts::PartLibrary& library) {
  parts::AssemblyConversion c = parts::to_assembly(read(file), library);
  c.assembly.carried.clear();
  c.assembly.ground_height = ContactGraph::build(c.assembly, GroundMode::Baseplate).ground_height;
  return c;
}

Assembly with(const Assembly& model, const std::vector<int>& parts) {
  Assembly out;
  out.ground_height = model.ground_height;
  for (int i : parts) out.bricks.push_back(model.bricks[size_t(i)]);
  return out;
}

TEST(ContactGraph, AmongSomePartsIsWhatTheirOwnModelFinds) {
  SKIP_WITHOUT_SHARED();
  const std::filesystem::path models = test::shared_dir() / "ldraw-models",
                              town = test::shared_dir() / "ldraw-corpus";
  parts::PartLibrary library({test::shared_dir() / "ldraw-library"}, BrickCatalog::standard());
  int compared = 0;
  std::vector<std::filesystem::path> files = {models / "car.ldr", models / "889-1-RadarTruck.mpd",
                                              models / "Bulldog.mpd"};
  std::ifstream list(town / "models.txt");
  for (std::string line; std::getline(list, line);)
    if (const auto name = line.substr(0, line.find_first_of("# \t")); !name.empty())
      files.push_back(town / name);
  for (const auto& file : files) {
    if (!std::filesystem::exists(file)) continue;
    const parts::AssemblyConversion conversion = steps_model(file, library);
    const Assembly& model = conversion.assembly;
    ContactGraph whole = ContactGraph::build(model, GroundMode::Baseplate);
    // Whether the whole model tips on a table is its own, not its parts'.
    whole.tips_over = true;
    if (!whole.pairwise()) continue;
    ++compared;
    const int n = int(model.bricks.size());
    Random rng(7);
    for (int round = 0; round < 6; ++round) {
      std::vector<int> parts;
      for (int i = 0; i < n; ++i)  // the first parts as drawn (a step), or parts at random
        if (round < 3 ? i < n * (round + 1) / 4 : rng.unit() < 0.5) parts.push_back(i);
      expect_same(whole.among(parts),
                  ContactGraph::build(with(model, parts), GroundMode::Baseplate),
                  file.filename().string() + " round " + std::to_string(round));
    }
  }
  EXPECT_GE(compared, 100) << "too few models read whose contacts are each between two parts";
}

// Carried parts tie what they touch together: a step's contacts then owe something to parts
// beyond the two, and are searched for.
TEST(ContactGraph, WithCarriedPartsIsNotPairwise) {
  SKIP_WITHOUT_SHARED();
  parts::PartLibrary library({test::shared_dir() / "ldraw-library"}, BrickCatalog::standard());
  const std::filesystem::path file = test::shared_dir() / "ldraw-models" / "car.ldr";
  const parts::AssemblyConversion conversion = parts::to_assembly(read(file), library);
  const Assembly& a = conversion.assembly;
  ASSERT_FALSE(a.carried.empty()) << "the car has wheels, carried";
  EXPECT_FALSE(ContactGraph::build(a, GroundMode::Baseplate).pairwise());
}

}  // namespace
}  // namespace lego::physics
