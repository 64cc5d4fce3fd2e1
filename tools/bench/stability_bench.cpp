// Times the stability analysis on generated hollow boxes under the LP configurations of
// docs/stability-lp.md. Output is one line per run, stable for comparing runs:
//   bricks rows cols nonzeros form method presolve scaling graph_s build_s solve_s status cm_gf
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <map>

#include "ldraw/writer.h"
#include "physics/stability.h"
#include "shapes.h"

using namespace lego;
using namespace lego::physics;

int main(int argc, char** argv) {
  CLI::App app{"Stability LP benchmark"};
  std::vector<int> sizes{500, 2000};
  std::string form = "scaled", method = "ipm";
  bool no_presolve = false, no_scaling = false;
  int repeat = 3;
  double max_seconds = 900;
  app.add_option("--bricks", sizes, "approximate brick counts");
  app.add_option("--form", form)->check(CLI::IsMember({"scaled", "maxmin"}));
  app.add_option("--method", method)
      ->check(CLI::IsMember({"ipm", "dual", "primal", "barrier", "barrier-nocross"}));
  app.add_flag("--no-presolve", no_presolve);
  app.add_flag("--no-scaling", no_scaling);
  app.add_option("--repeat", repeat, "runs per size; the median is printed");
  app.add_option("--max-seconds", max_seconds);
  double support_bound = 1e3;
  app.add_option("--support-bound", support_bound,
                 "bound on support forces while solving (inf: free)");
  std::string write;
  app.add_option("--write", write, "also write each generated model to WRITE-<bricks>.ldr");
  CLI11_PARSE(app, argc, argv);

  static const std::map<std::string, LpMethod> methods = {
      {"ipm", LpMethod::InteriorPoint},
      {"dual", LpMethod::DualSimplex},
      {"primal", LpMethod::PrimalSimplex},
      {"barrier", LpMethod::Barrier},
      {"barrier-nocross", LpMethod::BarrierNoCrossover}};
  StabilityOptions options;
  options.form = form == "scaled" ? LpForm::Scaled : LpForm::MaxMin;
  options.method = methods.at(method);
  options.presolve = !no_presolve;
  options.scaling = !no_scaling;
  options.max_seconds = max_seconds;
  options.support_bound = support_bound;
  for (int target : sizes) {
    Assembly a = bench::hollow_box_of(target);
    if (!write.empty())
      ldraw::write_model(fmt::format("{}-{}.ldr", write, target), a,
                         {.title = "Hollow box", .name = {}});
    std::vector<double> solve, build, graph;
    StabilityResult r;
    for (int k = 0; k < repeat; ++k) {
      r = analyze_stability(a, options);
      solve.push_back(r.stats.solve_seconds);
      build.push_back(r.stats.build_seconds);
      graph.push_back(r.stats.graph_seconds);
    }
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    std::string top;
    if (!r.weakest.empty()) top = fmt::format("{}-{}", r.weakest[0].lower, r.weakest[0].upper);
    fmt::print(
        "{:6} {:7} {:7} {:8} {:6} {:15} {:3} {:3} {:8.4f} {:8.4f} {:9.3f} {:16} {:10.4f} {}\n",
        a.bricks.size(), r.stats.rows, r.stats.columns, r.stats.nonzeros, form, method,
        no_presolve ? "-" : "pre", no_scaling ? "-" : "sc", median(graph), median(build),
        median(solve), to_string(r.status), r.cm_gf(), top);
    std::fflush(stdout);
  }
}
