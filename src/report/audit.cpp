#include "report/audit.h"

#include <fmt/format.h>
#include <chrono>
#include <regex>

#include "core/error.h"

namespace lego::report {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

physics::StabilityOptions with_capacity(physics::StabilityOptions o, bool capacity) {
  o.brick_capacity = capacity;
  return o;
}

// Places each load on the bricks it names; returns a note per load, or throws InputError.
std::vector<std::string> apply_loads(Audit& audit, const std::vector<LoadSpec>& loads) {
  std::vector<std::string> notes;
  auto& assembly = audit.conversion.assembly;
  for (const LoadSpec& spec : loads) {
    std::vector<int> targets;
    for (int i = 0; i < int(assembly.bricks.size()); ++i) {
      const auto& part = audit.model.parts[audit.conversion.brick_part[i]];
      bool hit = false;
      switch (spec.target) {
        case LoadSpec::Target::Line:
          hit = part.line == spec.number &&
                (spec.file.empty() || std::filesystem::path(part.file).filename() == spec.file ||
                 part.file == spec.file);
          break;
        case LoadSpec::Target::Step:
          hit = part.step == spec.number;
          break;
        case LoadSpec::Target::Submodel: {
          hit = normalize_part_name(part.submodel) == normalize_part_name(spec.name);
          break;
        }
      }
      if (hit) targets.push_back(i);
    }
    if (targets.empty())
      throw InputError(audit.file, 0, fmt::format("--load {}: names no analysed brick", spec.text));
    // The weight is shared by knob count, so a step's load sits evenly on all its top knobs.
    int knobs = 0;
    for (int i : targets) knobs += assembly.bricks[i].size_x() * assembly.bricks[i].size_z();
    for (int i : targets) {
      const Brick& b = assembly.bricks[i];
      double share = double(b.size_x() * b.size_z()) / knobs;
      assembly.loads.push_back({i, {0, -weight_newton(spec.grams) * share, 0}, true, {}});
    }
    notes.push_back(fmt::format("{} g on the top knobs of {} brick{}", spec.grams, targets.size(),
                                targets.size() == 1 ? "" : "s"));
  }
  return notes;
}

Verdict verdict_of(const physics::StabilityResult& r, double min_cm_gf) {
  using physics::StabilityStatus;
  switch (r.status) {
    case StabilityStatus::Solved:
      return r.cm_gf() > min_cm_gf ? Verdict::Stable : Verdict::Unstable;
    case StabilityStatus::Floating:
    case StabilityStatus::NoEquilibrium:
      return Verdict::Unstable;
    case StabilityStatus::IterationLimit:
    case StabilityStatus::NumericalTrouble:
      return Verdict::Undecided;
    case StabilityStatus::Empty:
      return Verdict::NothingToAnalyse;
  }
  return Verdict::Undecided;
}

}  // namespace

LoadSpec parse_load_spec(const std::string& text) {
  static const std::regex pattern(
      R"(^(?:(step|submodel):(.+)|(?:(.+):)?(\d+))=([0-9]*\.?[0-9]+(?:[eE][-+]?\d+)?)$)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern))
    throw InputError(
        "", 0,
        fmt::format("--load '{}': expected LINE=GRAMS, FILE:LINE=GRAMS, step:K=GRAMS or "
                    "submodel:NAME=GRAMS",
                    text));
  LoadSpec spec;
  spec.text = text;
  spec.grams = std::stod(m[5]);
  if (m[1] == "step") {
    spec.target = LoadSpec::Target::Step;
    try {
      spec.number = std::stoi(m[2]);
    } catch (const std::exception&) {
      throw InputError("", 0, fmt::format("--load '{}': the step must be a number", text));
    }
  } else if (m[1] == "submodel") {
    spec.target = LoadSpec::Target::Submodel;
    spec.name = m[2];
  } else {
    spec.file = m[3];
    spec.number = std::stoi(m[4]);
  }
  return spec;
}

std::string describe_brick(const Audit& audit, int brick) {
  if (brick == physics::kGround) return "the ground";
  const Brick& b = audit.conversion.assembly.bricks[brick];
  auto t = ldraw::brick_transform(b, audit.conversion.assembly.origin_ldu);
  return fmt::format("{}:{} {} {} at ({:g}, {:g}, {:g})",
                     std::filesystem::path(b.source.file).filename().string(), b.source.line,
                     b.type->part, ldraw::ColorTable::standard().name(b.color), t.pos[0], t.pos[1],
                     t.pos[2]);
}

Audit audit_file(const std::filesystem::path& path, const AuditOptions& options) {
  Audit audit;
  audit.file = path.string();
  auto start = std::chrono::steady_clock::now();
  audit.model = ldraw::read_file(path, options.read);
  audit.parse_seconds = seconds_since(start);
  for (const auto& d : audit.model.diagnostics)
    if (d.severity == ldraw::Severity::Error) {
      audit.fatal = d.text();
      return audit;
    }
  if (audit.model.parts.empty()) {
    audit.fatal = fmt::format("{}: error: no part in the model", audit.file);
    return audit;
  }
  audit.conversion =
      ldraw::to_assembly(audit.model, BrickCatalog::standard(), options.read.library_dirs);
  if (audit.conversion.assembly.bricks.empty()) {
    audit.verdict = Verdict::NothingToAnalyse;
    return audit;
  }
  audit.load_notes = apply_loads(audit, options.loads);
  audit.stability = physics::analyze_stability(
      audit.conversion.assembly, with_capacity(options.stability, options.brick_capacity));
  audit.verdict = verdict_of(audit.stability, options.min_cm_gf);

  if (options.steps) {
    const Assembly& whole = audit.conversion.assembly;
    int last = 0;
    for (const Brick& b : whole.bricks) last = std::max(last, b.source.step);
    for (int step = 1; step <= last; ++step) {
      Assembly partial;
      partial.origin_ldu = whole.origin_ldu;
      partial.ground_y =
          whole.ground_level();  // the finished model's ground, not the partial one's
      std::vector<int> index(whole.bricks.size(), -1);
      for (int i = 0; i < int(whole.bricks.size()); ++i)
        if (whole.bricks[i].source.step <= step) {
          index[i] = int(partial.bricks.size());
          partial.bricks.push_back(whole.bricks[i]);
        }
      for (const auto& load : whole.loads)
        if (index[load.brick] >= 0)
          partial.loads.push_back(
              {index[load.brick], load.force_n, load.spread_over_top_knobs, load.point});
      if (partial.bricks.empty()) continue;
      auto r = physics::analyze_stability(partial, options.stability);
      StepAudit s{step, int(partial.bricks.size()), r.status, r.cm_gf(),
                  verdict_of(r, options.min_cm_gf) == Verdict::Stable};
      if (!s.stable && !audit.first_failing_step) audit.first_failing_step = step;
      audit.steps.push_back(s);
    }
    if (audit.first_failing_step && audit.verdict == Verdict::Stable)
      audit.verdict = Verdict::Unstable;
  }
  return audit;
}

}  // namespace lego::report
