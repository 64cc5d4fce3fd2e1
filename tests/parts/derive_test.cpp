// What the analysis derives from LDraw part files: the official library's parts (../shared, skipped
// without it) and small files written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "parts/derive.h"
#include "parts/part_library.h"
#include "test_paths.h"

namespace lego::parts {
namespace {

namespace fs = std::filesystem;

// The knowledge of a part derived from its file in `library`, the catalog's shapes left aside.
PartKnowledge derived(const fs::path& library, const std::string& part) {
  LibraryFiles files({library});
  GeometryCache cache;
  std::string why;
  auto file = files.find(part + ".dat", why);
  if (!file) throw std::runtime_error(why);
  const FileFinder find = [&](std::string_view reference, std::string& w) {
    return files.find(reference, w);
  };
  auto geometry = cache.flatten(*file, find, why);
  if (!geometry) throw std::runtime_error(why);
  return derive_part(part, *geometry, BrickCatalog::standard());
}

fs::path shared_library() {
  return test::ldraw_library();
}

std::vector<std::array<double, 4>> sorted(const std::vector<Connector>& connectors) {
  std::vector<std::array<double, 4>> out;
  for (const Connector& c : connectors)
    out.push_back({c.at[0], c.at[1], c.at[2], double(c.direction)});
  std::sort(out.begin(), out.end());
  return out;
}

// The library's own files for the catalog's bricks and plates derive to the shapes the catalog
// gives them: the derivation reads cavities, tubes and pins as the physics expects.
TEST(DerivePart, TheBrickFamilyDerivesToTheCatalogShapes) {
  SKIP_WITHOUT_LIBRARY();
  for (const BrickType& t : BrickCatalog::standard().types()) {
    if (!fs::exists(shared_library() / "parts" / (t.part + ".dat"))) continue;
    SCOPED_TRACE(t.part);
    const PartKnowledge k = derived(shared_library(), t.part);
    const PartShape expected = box_brick_shape(t.length, t.width, t.height, t.has_knobs);
    EXPECT_EQ(sorted(k.type.shape.studs), sorted(expected.studs));
    EXPECT_EQ(sorted(k.type.shape.receptacles), sorted(expected.receptacles));
    EXPECT_EQ(sorted(k.type.shape.bores), sorted(expected.bores));
    ASSERT_EQ(k.type.shape.body.size(), 1u);
    EXPECT_EQ(k.type.shape.body[0].min, expected.body[0].min);
    EXPECT_EQ(k.type.shape.body[0].max, expected.body[0].max);
    EXPECT_FALSE(k.carried);
  }
}

// The parts the issue names, as a builder knows them.
TEST(DerivePart, SlopesRoundPlatesSnotAndBaseplates) {
  SKIP_WITHOUT_LIBRARY();
  // A 45° slope 2 x 1: one stud on its top row, two cells underneath.
  PartKnowledge slope = derived(shared_library(), "3040b");
  EXPECT_EQ(slope.type.shape.studs.size(), 1u);
  EXPECT_EQ(slope.type.shape.receptacles.size(), 2u);
  // The round plate 1 x 1 draws its body with stud4.dat: a body and a cell, not a tube.
  PartKnowledge round = derived(shared_library(), "6141");
  EXPECT_EQ(round.type.shape.studs.size(), 1u);
  ASSERT_EQ(round.type.shape.receptacles.size(), 1u);
  EXPECT_EQ(round.type.shape.receptacles[0].at, (Vec3{0, 8, 0}));
  EXPECT_EQ(round.type.shape.bounds().max[1], 8);
  // SNOT: the headlight brick's recessed stud and 87087's side stud point to -z; the studs on
  // top point up (-y in LDraw's frame).
  for (const char* part : {"4070", "87087"}) {
    PartKnowledge k = derived(shared_library(), part);
    int up = 0, side = 0;
    for (const Connector& s : k.type.shape.studs) {
      up += s.direction == kMinusY;
      side += s.direction == kMinusZ;
    }
    EXPECT_EQ(up, 1) << part;
    EXPECT_EQ(side, 1) << part;
  }
  // The inverted slope's front studs are drawn long, from inside the body: they stand on top.
  for (const Connector& s : derived(shared_library(), "3660").type.shape.studs)
    EXPECT_EQ(s.at[1], 0);
  // A jumper plate's stud is half a stud off its cells; the tubes of 2-wide parts take such a
  // stud (a bore), the pins of 1-wide parts do not.
  PartKnowledge jumper = derived(shared_library(), "3794a");
  ASSERT_EQ(jumper.type.shape.studs.size(), 1u);
  EXPECT_EQ(jumper.type.shape.studs[0].at, (Vec3{0, 0, 0}));
  EXPECT_TRUE(jumper.type.shape.bores.empty());
  EXPECT_EQ(sorted(derived(shared_library(), "3031").type.shape.bores).size(), 9u);
  EXPECT_TRUE(derived(shared_library(), "3710").type.shape.bores.empty());
  // The corner brick has three cells, not the open fourth.
  EXPECT_EQ(derived(shared_library(), "2357").type.shape.receptacles.size(), 3u);
  // A baseplate says so, and has no cells under it.
  PartKnowledge base = derived(shared_library(), "3811");
  EXPECT_TRUE(base.type.baseplate);
  EXPECT_EQ(base.type.shape.studs.size(), 1024u);
  EXPECT_TRUE(base.type.shape.receptacles.empty());
  EXPECT_NE(base.type.mass_source.find("estimated from its body"), std::string::npos);
}

TEST(DerivePart, PartsWhoseConnectionsAreNotModelledAreCarried) {
  SKIP_WITHOUT_LIBRARY();
  // A hinge half with cells is held by its studs; the half without turns on its knuckles; one
  // with neither (a control stick's base: its ball is no cylinder) is carried.
  EXPECT_FALSE(derived(shared_library(), "3937").carried);
  EXPECT_FALSE(derived(shared_library(), "3938").carried);
  EXPECT_EQ(derived(shared_library(), "4592").carried, PartRole::HingeWithoutCells);
  EXPECT_EQ(derived(shared_library(), "3626b").carried, PartRole::MinifigurePart);
  EXPECT_FALSE(derived(shared_library(), "3641").carried);  // a tyre: its rim holds it
  EXPECT_EQ(derived(shared_library(), "3855").carried, PartRole::NoConnections);
  // A plate that holds wheels is a plate.
  EXPECT_FALSE(derived(shared_library(), "2926").carried);
}

// Technic holes, pins and axles from their primitives: a pin's two halves (connect.dat) one pin,
// a hole's two end rings (peghole.dat) one hole through the brick, an axle (axle.dat) as long as
// it is scaled. Parts held by nothing else are analysed through them.
TEST(DerivePart, TechnicHolesPinsAndAxles) {
  SKIP_WITHOUT_LIBRARY();
  auto shafts = [](const char* part) { return derived(shared_library(), part).type.shape.shafts; };
  const auto pin = shafts("3673");
  ASSERT_EQ(pin.size(), 1u);
  EXPECT_EQ(pin[0].kind, Shaft::Kind::Pin);
  EXPECT_EQ(pin[0].a, (Vec3{-20, 0, 0}));
  EXPECT_EQ(pin[0].b, (Vec3{20, 0, 0}));
  EXPECT_EQ(shafts("4459").at(0).kind, Shaft::Kind::FrictionPin);
  const auto brick = shafts("3700");
  ASSERT_EQ(brick.size(), 1u);
  EXPECT_EQ(brick[0].kind, Shaft::Kind::PinHole);
  EXPECT_EQ(brick[0].a, (Vec3{0, 10, -10}));
  EXPECT_EQ(brick[0].b, (Vec3{0, 10, 10}));
  const auto axle = shafts("3705");
  ASSERT_EQ(axle.size(), 1u);
  EXPECT_EQ(axle[0].kind, Shaft::Kind::Axle);
  EXPECT_EQ(axle[0].a, (Vec3{-40, 0, 0}));
  EXPECT_EQ(axle[0].b, (Vec3{40, 0, 0}));
  const auto liftarm = shafts("6632");  // 3 x 0.5: axle holes at its ends, pin holes between
  ASSERT_EQ(liftarm.size(), 5u);
  int axle_holes = 0;
  for (const Shaft& s : liftarm) axle_holes += s.kind == Shaft::Kind::AxleHole;
  EXPECT_EQ(axle_holes, 2);
  EXPECT_FALSE(derived(shared_library(), "3673").carried);
  EXPECT_FALSE(derived(shared_library(), "6632").carried);
}

// A hinge or turntable half's knuckles: its cylinder primitives on the line they cover longest,
// a finger at a time. Other parts' cylinders are none.
TEST(DerivePart, HingeAndTurntableKnuckles) {
  SKIP_WITHOUT_LIBRARY();
  auto shafts = [](const char* part) { return derived(shared_library(), part).type.shape.shafts; };
  const auto top = shafts("3938");  // two fingers on the line along x, 10 LDU below its top
  ASSERT_EQ(top.size(), 2u);
  for (const Shaft& s : top) {
    EXPECT_EQ(s.kind, Shaft::Kind::Knuckle);
    EXPECT_EQ(s.axis(), 0);
    EXPECT_EQ(s.a[1], 10);
    EXPECT_EQ(s.a[2], 0);
  }
  EXPECT_EQ(top[0].a[0], -20);
  EXPECT_EQ(top[1].b[0], 20);
  const auto base = shafts("3937");
  EXPECT_EQ(base.size(), 3u);
  const auto turntable = shafts("3404");  // about its vertical centre line
  ASSERT_EQ(turntable.size(), 1u);
  EXPECT_EQ(turntable[0].axis(), 1);
  EXPECT_EQ(turntable[0].a[0], 0);
  EXPECT_EQ(turntable[0].a[2], 0);
  for (const char* round : {"3062b", "3941"})  // round bricks are no hinges
    for (const Shaft& s : shafts(round)) EXPECT_FALSE(s.knuckle()) << round;
}

// Bars are round surfaces 4 LDU in radius all the way round their line; clips are what clip
// primitives draw at that radius. A hinge's round surfaces are its knuckles only.
TEST(DerivePart, BarsAndClips) {
  SKIP_WITHOUT_LIBRARY();
  auto shafts = [](const char* part) { return derived(shared_library(), part).type.shape.shafts; };
  const auto blade = shafts("30374");  // Bar 4L: along its y, 80 LDU
  ASSERT_EQ(blade.size(), 1u);
  EXPECT_EQ(blade[0].kind, Shaft::Kind::Bar);
  EXPECT_EQ(blade[0].axis(), 1);
  EXPECT_NEAR(std::abs(blade[0].b[1] - blade[0].a[1]), 80, 1e-9);
  const auto vertical = shafts("4085b");  // its clip stands up beside the plate
  ASSERT_EQ(vertical.size(), 1u);
  EXPECT_EQ(vertical[0].kind, Shaft::Kind::Clip);
  EXPECT_EQ(vertical[0].axis(), 1);
  EXPECT_NEAR(vertical[0].a[2], -20, 1e-9);
  const auto horizontal = shafts("6019");  // its clip lies along x
  ASSERT_FALSE(horizontal.empty());
  for (const Shaft& s : horizontal) {
    EXPECT_EQ(s.kind, Shaft::Kind::Clip);
    EXPECT_EQ(s.axis(), 0);
  }
  const auto handle = shafts("2540");  // the handle's bar, between and beside its two posts
  ASSERT_FALSE(handle.empty());
  for (const Shaft& s : handle) {
    EXPECT_EQ(s.kind, Shaft::Kind::Bar);
    EXPECT_EQ(s.axis(), 0);
    EXPECT_NEAR(s.a[1], 2, 1e-9);
    EXPECT_NEAR(s.a[2], -20, 1e-9);
  }
  EXPECT_TRUE(shafts("3001").empty());
  for (const Shaft& s : shafts("3938")) EXPECT_TRUE(s.knuckle());
}

// A wheel turns about the line its round surfaces are drawn on: its hub and its rim lie there,
// across its width; a tyre's bore too, found from its outline where its file draws no cylinder
// (6015's tread is segments turned about the axle). A wheel's hub is no bar. A plate's cells
// beside its wheel pins have the plate's bottom, not the pin's.
TEST(DerivePart, WheelsAndTyres) {
  SKIP_WITHOUT_LIBRARY();
  auto kinds_on_z_axle = [](const char* part) {
    const PartKnowledge k = derived(shared_library(), part);
    EXPECT_FALSE(k.carried) << part << ": " << carried_because(*k.carried);
    EXPECT_TRUE(k.type.rolls) << part;
    std::vector<Shaft::Kind> kinds;
    for (const Shaft& s : k.type.shape.shafts) {
      EXPECT_EQ(s.axis(), 2) << part;
      EXPECT_NEAR(s.a[0], 0, 1e-9) << part;
      EXPECT_NEAR(s.a[1], 0, 1e-9) << part;
      kinds.push_back(s.kind);
    }
    return kinds;
  };
  EXPECT_EQ(kinds_on_z_axle("4624"), (std::vector{Shaft::Kind::Rim, Shaft::Kind::Hub}));
  const auto rim = derived(shared_library(), "4624").type.shape.shafts[0];
  EXPECT_NEAR(std::min(rim.a[2], rim.b[2]), -8, 1e-9);
  EXPECT_NEAR(std::max(rim.a[2], rim.b[2]), 8, 1e-9);
  EXPECT_EQ(kinds_on_z_axle("6014"), (std::vector{Shaft::Kind::Rim, Shaft::Kind::Hub}));
  EXPECT_EQ(kinds_on_z_axle("3641"), (std::vector{Shaft::Kind::Tyre}));
  EXPECT_EQ(kinds_on_z_axle("6015"), (std::vector{Shaft::Kind::Tyre}));
  const PartKnowledge holder = derived(shared_library(), "4600");
  EXPECT_FALSE(holder.type.rolls);
  ASSERT_EQ(holder.type.shape.receptacles.size(), 4u);
  for (const Connector& r : holder.type.shape.receptacles) EXPECT_EQ(r.at[1], 8);
  int pins = 0;
  for (const Shaft& s : holder.type.shape.shafts) pins += s.kind == Shaft::Kind::Pin;
  EXPECT_EQ(pins, 2);
  // Fits: a wheel pin turns in a hub, a rim goes only into a tyre, a hub takes no rim.
  const Shaft pin{Shaft::Kind::Pin}, hub{Shaft::Kind::Hub}, tyre{Shaft::Kind::Tyre};
  EXPECT_TRUE(Shaft::fits(pin, hub));
  EXPECT_TRUE(Shaft::fits(rim, tyre));
  EXPECT_FALSE(Shaft::fits(rim, hub));
  EXPECT_FALSE(Shaft::fits(pin, tyre));
}

// Written here, without ../shared: the test library of tests/data (tests/data/make_library.py).
TEST(DerivePart, TheTestLibrary) {
  const fs::path library = test::data_dir() / "library";
  PartKnowledge corner = derived(library, "2357");
  EXPECT_EQ(corner.type.shape.studs.size(), 3u);
  EXPECT_EQ(corner.type.shape.receptacles.size(), 3u);
  PartKnowledge jumper = derived(library, "3794b");
  ASSERT_EQ(jumper.type.shape.studs.size(), 1u);
  EXPECT_EQ(jumper.type.shape.studs[0].at, (Vec3{0, 0, 0}));
  EXPECT_EQ(jumper.type.shape.receptacles.size(), 2u);  // either side of its pin
  PartKnowledge side = derived(library, "87087");
  EXPECT_EQ(side.type.shape.studs.size(), 2u);
}

// A part file that fans out (a part placing 20 copies of a subpart that places 20 copies of ...)
// is bounded, and references that leave the library are refused.
TEST(DerivePart, FanOutIsBoundedAndReferencesStayInTheLibrary) {
  const fs::path library = test::scratch("lego_parts_", "fanout");
  fs::create_directories(library / "parts");
  fs::create_directories(library / "p");
  std::ofstream(library / "p" / "leaf.dat") << "0 Leaf\n3 16 0 0 0 1 0 0 0 0 1\n";
  std::string previous = "leaf.dat";
  for (int level = 0; level < 6; ++level) {
    const std::string name = "fan" + std::to_string(level) + ".dat";
    std::ofstream out(library / "p" / name);
    out << "0 Fan " << level << "\n";
    for (int k = 0; k < 20; ++k)
      out << "1 16 " << k << " 0 0 1 0 0 0 1 0 0 0 1 " << previous << "\n";
    previous = name;
  }
  std::ofstream(library / "parts" / "fan.dat")
      << "0 Fan\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 " << previous << "\n";
  std::ofstream(library / "parts" / "escape.dat")
      << "0 Escape\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 /dev/zero\n"
      << "1 16 0 0 0 1 0 0 0 1 0 0 0 1 ../../../etc/passwd\n4 16 0 0 0 1 0 0 1 0 1 0 0 1\n";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(derived(library, "fan"), std::runtime_error);  // 20^6 faces: refused
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10);
  LibraryFiles files({library});
  std::string why;
  EXPECT_FALSE(files.find("/dev/zero", why));
  EXPECT_NE(why.find("outside the library"), std::string::npos);
  EXPECT_FALSE(files.find("..\\..\\x.dat", why));
  PartKnowledge escape = derived(library, "escape");  // the face it draws, nothing else
  EXPECT_EQ(escape.type.shape.body.size(), 1u);
}

// The fan-out again, through a subfile that is missing and through studs: neither faces nor a
// missing name may multiply (each level placed 20 copies of the list of missing names below it,
// 20^7 strings), and a part larger than any made is left out by the library (issue 19).
TEST(DerivePart, FanOutThroughMissingFilesAndStudsAndGiantPartsAreBounded) {
  const fs::path library = test::scratch("lego_parts_", "fanout_missing");
  fs::create_directories(library / "parts");
  fs::create_directories(library / "p");
  std::ofstream(library / "p" / "studs0.dat") << "0 Studs\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 stud.dat\n";
  std::string missing = "nowhere.dat", studs = "studs0.dat";
  for (int level = 0; level < 7; ++level) {
    const std::string m = "m" + std::to_string(level) + ".dat";
    const std::string st = "s" + std::to_string(level) + ".dat";
    std::ofstream out_m(library / "p" / m), out_s(library / "p" / st);
    out_m << "0 Missing fan " << level << "\n";
    out_s << "0 Stud fan " << level << "\n";
    for (int k = 0; k < 20; ++k) {
      out_m << "1 16 " << k << " 0 0 1 0 0 0 1 0 0 0 1 " << missing << "\n";
      out_s << "1 16 " << 20 * k << " 0 0 1 0 0 0 1 0 0 0 1 " << studs << "\n";
    }
    missing = m;
    studs = st;
  }
  std::ofstream(library / "parts" / "fanm.dat")
      << "0 Fan of missing files\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 " << missing
      << "\n4 16 0 0 0 20 0 0 20 0 20 0 0 20\n";
  std::ofstream(library / "parts" / "fans.dat")
      << "0 Fan of studs\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 " << studs << "\n";
  LibraryFiles files({library});
  GeometryCache cache;
  const FileFinder find = [&](std::string_view reference, std::string& w) {
    return files.find(reference, w);
  };
  std::string why;
  auto fanm = cache.flatten(*files.find("fanm.dat", why), find, why);
  ASSERT_TRUE(fanm) << why;
  EXPECT_EQ(fanm->missing, std::vector<std::string>{"nowhere.dat"});  // one name, once
  EXPECT_EQ(fanm->faces.size(), 2u);
  why.clear();
  EXPECT_FALSE(cache.flatten(*files.find("fans.dat", why), find, why));  // 20^7 studs
  EXPECT_NE(why.find("100,000 studs"), std::string::npos) << why;

  // A quad 2,000,000 LDU across (100,000 studs), then one of 1,000 studs: the library leaves out
  // the first with its size, and derives the second.
  std::ofstream(library / "parts" / "giant.dat")
      << "0 Giant\n4 16 -1e6 0 -1e6 1e6 0 -1e6 1e6 0 1e6 -1e6 0 1e6\n";
  std::ofstream(library / "parts" / "large.dat")
      << "0 Large\n4 16 -1e4 0 -1e4 1e4 0 -1e4 1e4 0 1e4 -1e4 0 1e4\n";
  PartLibrary parts({library}, BrickCatalog::standard());
  EmbeddedParts none{ldraw::Model{}};
  ldraw::PlacedPart giant;
  giant.part = "giant";
  giant.definition = library / "parts" / "giant.dat";
  EXPECT_EQ(parts.knowledge(giant, none, why), nullptr);
  EXPECT_NE(why.find("studs across, more than the 1000 a part may be"), std::string::npos) << why;
  ldraw::PlacedPart large = giant;
  large.part = "large";
  large.definition = library / "parts" / "large.dat";
  EXPECT_NE(parts.knowledge(large, none, why), nullptr) << why;
}

}  // namespace
}  // namespace lego::parts
