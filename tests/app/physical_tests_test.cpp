// The structures of ../shared/physical-tests: people built them from real bricks and watched
// them stand or fall (see its README). Each verdict is pinned to that outcome, and each C_M to
// the force model's value (docs/physics.md gives the table and the hand computations).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/run_tool.h"
#include "test_paths.h"

namespace lego {
namespace {

namespace fs = std::filesystem;

struct Built {
  const char* file;
  bool stands;
  double cm_gf;
  const char* load;  // brickcheck's --load, where the test hung a payload
};

// The payload is StableLego's 200 g block: a 2 x 2 brick (1.18 g) with 198.85 g on its knobs.
const Built kBuilt[] = {
    {"stair_19.ldr", true, 1.946, nullptr},
    {"stair_20.ldr", false, -6.256, nullptr},
    {"stair_20_good.ldr", true, 1.946, nullptr},
    {"stick_light.ldr", true, 2.605, nullptr},
    {"stick_heavy.ldr", false, -5.660, nullptr},
    {"stick_heavy_good.ldr", true, 0.965, nullptr},
    {"stick_heavy_good_test_horizontal_force.ldr", true, 18.580, nullptr},
    {"external_weight_good.ldr", true, 29.775, "9=198.85"},
    {"external_weight_fail.ldr", false, -12.564, "11=198.85"},
};

TEST(PhysicalTests, EveryBuiltStructureGetsItsRealOutcome) {
  const fs::path dir = test::shared_dir() / "physical-tests" / "stablelego";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "../shared/physical-tests is absent";
  for (const Built& b : kBuilt) {
    SCOPED_TRACE(b.file);
    std::vector<std::string> args = {"--json"};
    if (b.load) args.insert(args.end(), {"--load", b.load});
    args.push_back((dir / b.file).string());
    const auto run = test::run_tool("brickcheck", args);
    EXPECT_EQ(run.exit_code, b.stands ? 0 : 1) << run.out << run.err;
    const auto j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["stable"].get<bool>(), b.stands);
    EXPECT_NEAR(j["cm_gf"].get<double>(), b.cm_gf, 2e-3);
  }
}

}  // namespace
}  // namespace lego
