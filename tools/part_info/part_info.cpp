// part-info: what the analysis derives from LDraw part files (studs, receptacles, body boxes,
// mass, whether it is carried and why). For looking at a part the way the physics sees it.
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <iostream>

#include "core/brick_catalog.h"
#include "parts/part_library.h"

using namespace lego;

int main(int argc, char** argv) {
  CLI::App app{"part-info: the studs, receptacles, body and mass derived from LDraw part files"};
  std::vector<std::string> names;
  std::string ldraw_dir;
  app.add_option("parts", names, "part numbers or file names (3001, 3040b.dat)")->required();
  app.add_option("--ldraw-dir", ldraw_dir, "the LDraw library")->required();
  CLI11_PARSE(app, argc, argv);
  parts::PartLibrary library({ldraw_dir}, BrickCatalog::standard());
  parts::EmbeddedParts none{ldraw::Model{}};
  for (const std::string& name : names) {
    ldraw::PlacedPart p;
    p.part = normalize_part_name(name);
    p.reference = name;
    for (const char* folder : {"parts", "p"}) {
      auto path = std::filesystem::path(ldraw_dir) / folder / (p.part + ".dat");
      if (std::filesystem::exists(path)) p.definition = path;
    }
    std::string why;
    const parts::PartKnowledge* k = library.knowledge(p, none, why);
    if (!k) {
      fmt::print("{}: {}\n", name, why);
      continue;
    }
    const BrickType& t = k->type;
    fmt::print("{}: {} [{}]{}{}\n", t.part, t.name, t.kind, t.baseplate ? " baseplate" : "",
               !k->carried ? "" : " CARRIED: " + std::string(carried_because(*k->carried)));
    fmt::print("  mass {:.3f} g ({})\n", t.mass_g, t.mass_source);
    static const char* kDir[6] = {"+x", "-x", "+y(down)", "-y(up)", "+z", "-z"};
    for (const Box& b : t.shape.body)
      fmt::print("  body  x {:g}..{:g}  y {:g}..{:g}  z {:g}..{:g}\n", b.min[0], b.max[0], b.min[1],
                 b.max[1], b.min[2], b.max[2]);
    for (const Connector& c : t.shape.studs)
      fmt::print("  stud        ({:g}, {:g}, {:g}) {}\n", c.at[0], c.at[1], c.at[2],
                 kDir[c.direction]);
    for (const Connector& c : t.shape.receptacles)
      fmt::print("  receptacle  ({:g}, {:g}, {:g}) {}\n", c.at[0], c.at[1], c.at[2],
                 kDir[c.direction]);
    constexpr const char* kShaft[] = {
        "pin hole",        "axle hole", "pin", "friction pin", "axle", "knuckle",
        "locking knuckle", "clip",      "bar", "hub",          "rim",  "tyre"};
    static_assert(std::size(kShaft) == size_t(Shaft::Kind::Tyre) + 1, "a name for every kind");
    for (const Shaft& s : t.shape.shafts)
      fmt::print("  {:<10}  ({:g}, {:g}, {:g}) to ({:g}, {:g}, {:g})\n", kShaft[int(s.kind)],
                 s.a[0], s.a[1], s.a[2], s.b[0], s.b[1], s.b[2]);
  }
  return 0;
}
