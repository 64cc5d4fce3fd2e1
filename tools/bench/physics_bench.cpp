#include "physics_bench.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "report/audit.h"

namespace lego::bench {
namespace {

namespace fs = std::filesystem;

// A formulation: the force model's choices and its T (grams-force per contact point). A T other
// than the paper's moves C_M by the difference: the largest friction a model needs does not
// depend on T.
struct Candidate {
  const char* name;
  physics::Formulation formulation;
  double t_gf;
};

// The paper's support force is one per contact (its analysis is in 2D): no twist about the knobs.
// StableLego's knob presses and BrickSim's in-plane fields are per knob or point: they hold one.
const Candidate kCandidates[] = {
    {"this model", {.knob_balance = true, .push_at_knobs = false}, 71.658},
    {"paper", {.knob_balance = false, .push_at_knobs = false, .knobs_hold_twist = false}, 71.658},
    {"StableLego", {.knob_balance = false, .push_at_knobs = true}, 100},
    {"BrickSim", {.knob_balance = false, .push_at_knobs = true}, 71.43},
    {"balance+knobs", {.knob_balance = true, .push_at_knobs = true}, 71.658},
};

struct Evidence {
  std::string name;
  fs::path file;
  bool stood;
  std::string load;  // brickcheck's --load
};

std::vector<Evidence> evidence(const fs::path& source, const fs::path& shared) {
  std::vector<Evidence> out;
  const fs::path built = shared / "physical-tests" / "stablelego";
  if (fs::is_directory(built)) {
    for (const auto& [file, stood, load] : std::vector<std::tuple<std::string, bool, std::string>>{
             {"stair_19", true, ""},
             {"stair_20", false, ""},
             {"stair_20_good", true, ""},
             {"stick_light", true, ""},
             {"stick_heavy", false, ""},
             {"stick_heavy_good", true, ""},
             {"stick_heavy_good_test_horizontal_force", true, ""},
             {"external_weight_good", true, "9=198.85"},
             {"external_weight_fail", false, "11=198.85"},
         })
      out.push_back({file, built / (file + ".ldr"), stood, load});
  }
  // The paper built both bridges until they fell: (a) at five 1 x 8 bricks, (b) at eleven.
  for (char variant : {'a', 'b'})
    for (int n = 1; n <= (variant == 'a' ? 5 : 11); ++n)
      out.push_back(
          {fmt::format("figure 7 ({}) {}", variant, n),
           source / "tests" / "data" / "bridges" / fmt::format("bridge-{}-{:02}.ldr", variant, n),
           n < (variant == 'a' ? 5 : 11), ""});
  return out;
}

}  // namespace

void physics_section(const fs::path& source, const fs::path& shared) {
  const auto items = evidence(source, shared);
  fmt::print("\nphysics: C_M (gf) of what people built, by formulation; * a wrong verdict\n");
  fmt::print("{:<40} {:>6}", "structure", "real");
  for (const Candidate& c : kCandidates) fmt::print(" {:>13}", c.name);
  fmt::print("\n");
  std::vector<int> dangerous(std::size(kCandidates), 0), cautious(std::size(kCandidates), 0);
  for (const Evidence& e : items) {
    fmt::print("{:<40} {:>6}", e.name, e.stood ? "stands" : "falls");
    for (size_t k = 0; k < std::size(kCandidates); ++k) {
      const Candidate& c = kCandidates[k];
      report::AuditOptions options;
      options.stability.formulation = c.formulation;
      if (!e.load.empty()) options.loads.push_back(report::parse_load_spec(e.load));
      parts::PartLibrary library({}, BrickCatalog::standard());
      const report::Audit a = report::audit_file(e.file, options, library);
      double cm = -std::numeric_limits<double>::infinity();
      if (a.stability.status == physics::StabilityStatus::Solved)
        cm = a.stability.cm_gf() + (c.t_gf - physics::kMaxFrictionLoad / physics::kGravity);
      const bool stands = cm > 0 && a.stability.connectivity.all_grounded();
      if (stands && !e.stood) ++dangerous[k];
      if (!stands && e.stood) ++cautious[k];
      fmt::print(" {:>12}{}", std::isfinite(cm) ? fmt::format("{:.2f}", cm) : "no eq.",
                 stands == e.stood ? " " : "*");
    }
    fmt::print("\n");
  }
  fmt::print("{:<47}", "wrong: says it stands, it fell");
  for (int n : dangerous) fmt::print(" {:>13}", n);
  fmt::print("\n{:<47}", "wrong: says it falls, it stood");
  for (int n : cautious) fmt::print(" {:>13}", n);
  fmt::print("\n");
}

}  // namespace lego::bench
