// brickcheck: audits LDraw models for connectivity and stability (paper section 6).
#include <fmt/format.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <variant>

#include "app/number_checks.h"
#include "app/output_paths.h"
#include "core/brick_catalog.h"
#include "core/error.h"
#include "core/in_order.h"
#include "core/stop.h"
#include "core/text.h"
#include "ldraw/reader.h"
#include "ldraw/writer.h"
#include "parts/part_library.h"
#include "report/audit.h"
#include "report/instructions.h"
#include "report/render.h"

namespace fs = std::filesystem;
using namespace lego;

namespace {

enum Exit {
  kStable = 0,
  kUnstable = 1,
  kBadInput = 2,
  kNotJudged = 3,
  kUndecided = 4,
  kByAssumption = 5
};

constexpr const char* kExitCodes = R"(Exit codes:
  0  every file is stable and connected
  1  a file is unstable, has floating parts, has no equilibrium, or a build step falls (--steps)
  2  usage error, or a file cannot be read (missing, a directory, not text, no parts, a malformed
     type-1 line)
  3  a file cannot be judged: nothing in it can be analysed as structure, or most of its mass is
     carried (its connections assumed)
  4  the solver could not decide (iteration limit or numerical trouble)
  5  with --strict: a file is stable only by an assumption that can change the verdict (a part
     held by a connection that is not modelled, a part left out, or assumed rigid joints the
     model does not stand without)
When files differ, the highest of 2, 1, 4, 5, 3 in that order wins.)";

// Whether `dir` looks like an LDraw library: it has a parts/ or p/ folder (any case).
bool is_ldraw_library(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  for (fs::directory_iterator d(dir, ec), end; !ec && d != end; d.increment(ec)) {
    const std::string name = ascii_lower(d->path().filename().string());
    if ((name == "parts" || name == "p") && d->is_directory(ec)) return true;
  }
  return false;
}

fs::path heatmap_path(const fs::path& out, const fs::path& input, bool several) {
  if (!several) return out;
  return out.parent_path() /
         (out.stem().string() + "-" + input.stem().string() + out.extension().string());
}

// The booklet of one audited model: its parts step by step, with each step's analysis.
void write_instructions(const report::Audit& audit, const fs::path& dir,
                        const std::string& ldraw_dir, bool quiet) {
  // What each part's body is, as the audit derived it: the pictures frame the steps on it.
  std::vector<std::optional<Box>> bodies(audit.model.parts.size());
  const Assembly& a = audit.conversion.assembly;
  for (size_t i = 0; i < a.bricks.size() && i < audit.conversion.brick_part.size(); ++i)
    if (!a.bricks[i].type->shape.body.empty())
      bodies[audit.conversion.brick_part[i]] = a.bricks[i].type->shape.bounds();
  for (size_t c = 0; c < a.carried.size() && c < audit.conversion.carried_part.size(); ++c) {
    PartShape carried;
    carried.body = a.carried[c].body;
    if (!carried.body.empty()) bodies[audit.conversion.carried_part[c]] = carried.bounds();
  }
  report::Booklet booklet = report::booklet_of(audit.model, bodies);
  for (report::BookletStep& bs : booklet.steps)
    for (const report::StepAudit& s : audit.steps)
      if (s.step == bs.number) {
        if (s.status == physics::StabilityStatus::Solved) bs.cm_gf = s.cm_gf;
        bs.stands = s.stable;
        bs.certified = s.certified;
        bs.floats = s.floating > 0;
        bs.sub_assembly_judged = s.apart || s.built_aside;
        bs.why = s.why;
        if (s.built_aside)
          continue;  // its culprits are parts built aside, drawn in no falls picture
        for (int b : s.culprits)
          if (size_t(b) < audit.conversion.brick_part.size())
            bs.falling.push_back(audit.conversion.brick_part[size_t(b)]);
        for (int c : s.carried_culprits)
          if (size_t(c) < audit.conversion.carried_part.size())
            bs.falling.push_back(audit.conversion.carried_part[size_t(c)]);
      }
  report::draw_what_falls(booklet, audit.model, bodies);
  if (audit.stability.status == physics::StabilityStatus::Solved)
    booklet.cm_gf = audit.stability.cm_gf();
  booklet.verdict = "The finished model: " + report::render_text(audit, true);
  while (!booklet.verdict.empty() && booklet.verdict.back() == '\n') booklet.verdict.pop_back();
  fs::path library = ldraw_dir;
  if (library.empty()) {
    const auto from_env = ldraw::library_dirs_from_env();
    library = from_env.empty() ? default_parts_dir() : from_env.front();
  }
  auto progress = [&](const std::string& words) {
    if (!quiet) std::cerr << "brickcheck: " << words << "\n";
  };
  const std::string note = report::write_booklet(dir, booklet, library, progress);
  if (!note.empty()) std::cerr << "brickcheck: " << note << "\n";
}

// How the exit codes of several files combine: the highest rank wins.
int rank(int code) {
  return code == kBadInput       ? 5
         : code == kUnstable     ? 4
         : code == kUndecided    ? 3
         : code == kByAssumption ? 2
         : code == kNotJudged    ? 1
                                 : 0;
}

int exit_code(report::Verdict verdict) {
  switch (verdict) {
    case report::Verdict::Stable:
      return kStable;
    case report::Verdict::Unstable:
      return kUnstable;
    case report::Verdict::Undecided:
      return kUndecided;
    case report::Verdict::Unreadable:
      return kBadInput;
    case report::Verdict::NothingToAnalyse:
    case report::Verdict::NotJudged:
      return kNotJudged;
    case report::Verdict::StableByAssumption:
      return kByAssumption;
  }
  return kBadInput;
}

// What the command line asks of every file.
// The files' results as they are reported, in order (JSON is printed at the end, as one array).
// A file's hard deadline, in the stop's thread, ends the run with them.
struct Reported {
  std::mutex mutex;
  int worst = kStable;
  nlohmann::json all = nlohmann::json::array();
  size_t files = 0;
};

// Titles and names are the user's bytes: text that is not UTF-8 is shown with U+FFFD.
void print_json(const nlohmann::json& j) {
  std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n"
            << std::flush;
}

struct Settings {
  report::AuditOptions options;
  bool json = false, quiet = false;
  bool progress = false;  // a progress line on stderr for long stages
  // What has been reported of the files so far: a file's hard deadline (below) reads it.
  Reported* reported = nullptr;
  std::string heatmap, instructions, ldraw_dir, main_model;
};

// --max-seconds also ends the process a little after the budget, for a stage that cannot check it
// (one factorization of a Datsville streets file took 172 s past a 10 s budget; a pipe nobody
// writes never ends): a quarter past the budget (and its build steps' as much again), and two
// seconds (a stage that checks the budget stops well within that, under the sanitizers too). The
// files not reported by then are not checked.
double hard_deadline(const report::AuditOptions& o) {
  return o.stability.max_seconds * (o.steps ? 2 : 1) * 1.25 + 2;
}

// One file's part of the output, made apart from the others' so that files checked at once
// print in the order given.
struct FileReport {
  int code = kStable;
  std::string text;     // stdout without --json
  nlohmann::json json;  // with --json
  std::string errors;   // stderr
};

// A line on a terminal that says how far a long stage of a file is; cleared when the file is done.
class ProgressLine {
 public:
  ProgressLine(bool shown, std::string file) : shown_(shown), file_(std::move(file)) {}
  ~ProgressLine() {
    if (drawn_) std::cerr << "\r\033[K" << std::flush;
  }
  Budget::Progress sink() {
    if (!shown_) return {};
    return [this](Stage stage, size_t done, size_t total) {
      const std::lock_guard lock(mutex_);
      std::cerr << "\r\033[K"
                << fmt::format("brickcheck: {}: {} {}{} {}s", file_, stage.name, done,
                               total ? fmt::format("/{}", total) : "", stage.unit)
                << std::flush;
      drawn_ = true;
    };
  }

 private:
  bool shown_, drawn_ = false;
  std::string file_;
  std::mutex mutex_;
};

FileReport check_file(const std::string& file, size_t files, const Settings& s,
                      parts::PartLibrary& library) {
  FileReport r;
  report::Audit audit;
  try {
    ProgressLine progress(s.progress, file);
    report::AuditOptions options = s.options;
    options.progress = progress.sink();
    const stop::Deadline deadline(hard_deadline(options), [&s, file] {
      report::Audit ended;
      ended.file = file;
      ended.verdict = report::Verdict::Undecided;
      ended.out_of_time = fmt::format(
          "out of time ({:g} s): a stage that cannot stop itself (reading a pipe, one "
          "factorization) ran on past it, and the run was ended",
          s.options.stability.max_seconds);
      Reported& reported = *s.reported;
      const std::lock_guard lock(reported.mutex);
      if (!s.json) {
        std::cout << report::render_text(ended, true) << std::flush;
      } else if (reported.files == 1) {
        print_json(report::render_json(ended, s.options));
      } else {
        nlohmann::json all = reported.all;
        all.push_back(report::render_json(ended, s.options));
        print_json(all);
      }
      std::string words = file + ": " + ended.out_of_time;
      if (reported.files > 1) words += "; the files not reported were not checked";
      return stop::Ending{words,
                          rank(kUndecided) > rank(reported.worst) ? kUndecided : reported.worst};
    });
    audit = report::audit_file(file, options, library);
  } catch (const InputError& e) {
    audit.file = file;
    audit.verdict = report::Verdict::Unreadable;
    audit.fatal = e.what();
  }
  r.code = exit_code(audit.verdict);
  auto fail = [&](const std::string& why) {
    r.errors += "brickcheck: " + why + "\n";
    if (rank(kBadInput) > rank(r.code)) r.code = kBadInput;
  };
  if (s.json)
    r.json = report::render_json(audit, s.options);
  else
    r.text = report::render_text(audit, s.quiet);
  if (audit.verdict == report::Verdict::Unreadable && s.json) r.errors += audit.fatal + "\n";

  // A file read and analysed to the end: one --max-seconds stopped has no forces to show.
  const bool analysed = audit.verdict != report::Verdict::Unreadable && audit.out_of_time.empty() &&
                        audit.out_of_memory.empty();
  if (!s.instructions.empty() && analysed) {
    try {
      write_instructions(audit, s.instructions, s.ldraw_dir, s.quiet || s.json);
    } catch (const InputError& e) {
      fail(e.what());
    }
  }
  if (!s.heatmap.empty() && analysed && audit.verdict != report::Verdict::NothingToAnalyse) {
    const fs::path out = heatmap_path(s.heatmap, file, files > 1);
    try {
      // A file the model reads that the command line does not name (a submodel in its own
      // file, a part file beside the model) is no more replaced than the file named.
      std::set<fs::path> read(audit.model.files.begin(), audit.model.files.end());
      for (const auto& p : audit.model.parts)
        if (!p.definition.empty()) read.insert(p.definition);
      for (const fs::path& f : read)
        if (app::same_file(out, f))
          throw InputError(
              out.string(), 0,
              "--heatmap: would overwrite " + f.string() + ", which " + file + " reads");
      ldraw::write_file_atomically(out, report::render_heatmap(audit));
      if (!s.quiet && !s.json) r.text += "  heat map: " + out.string() + "\n";
    } catch (const InputError& e) {
      fail(e.what());
    }
  }
  return r;
}

// What the command line gives.
struct Arguments {
  std::vector<std::string> files;
  std::string ldraw_dir, ground = "baseplate", heatmap, main_model, instructions;
  std::vector<std::string> load_texts, ground_part_texts;
  double min_cm = 0, max_seconds = 60;
  bool json = false, steps = false, quiet = false, strict = false;
  int jobs = 1;
};

void add_options(CLI::App& app, Arguments& a) {
  app.add_option("files", a.files, "LDraw models to check")->required();
  app.add_option("-j,--jobs", a.jobs,
                 "check this many files at once; the reports still come in the order given "
                 "(default 1)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--ldraw-dir", a.ldraw_dir,
                 "LDraw library for parts we do not ship (default: $LDRAWDIR)");
  app.add_option("--ground", a.ground, "baseplate: the ground holds knobs; table: it only pushes")
      ->check(CLI::IsMember({"baseplate", "table"}));
  // One value per use, so an option never swallows the files that follow it.
  app.add_option(
         "--load", a.load_texts,
         "external weight: LINE=GRAMS or FILE:LINE=GRAMS (a brick's top knobs), step:K=GRAMS, "
         "submodel:NAME=GRAMS, top=GRAMS (the highest parts; spread over their top knobs); "
         "repeatable")
      ->allow_extra_args(false);
  app.add_option("--ground-part", a.ground_part_texts,
                 "the part this line places is fixed, part of the ground: LINE or FILE:LINE; "
                 "repeatable")
      ->allow_extra_args(false);
  app.add_option("--min-cm", a.min_cm, "stability threshold for C_M in grams-force (default 0)")
      ->check(app::cm_threshold(physics::kMaxFrictionLoad / physics::kGravity));
  app.add_option("--main", a.main_model, "the MPD model to check instead of the first FILE");
  app.add_option("--max-seconds", a.max_seconds,
                 "give up on a model's stability after this long, and on its build steps after as "
                 "long again: exit 4, undecided (default 60)")
      ->check(app::finite_number(app::Sign::Positive));
  app.add_flag("--json", a.json, "print JSON on stdout (docs/brickcheck-json.md)");
  app.add_option("--heatmap", a.heatmap,
                 "write the model coloured by per-brick capacity to this .ldr");
  app.add_flag("--steps", a.steps, "check the model after every build step");
  app.add_option("--instructions", a.instructions,
                 "write an HTML booklet into this folder (one FILE): a page per build step with a "
                 "picture (LeoCAD), its parts and its C_M; implies --steps");
  app.add_flag("--quiet", a.quiet, "print only the verdict line of each file");
  app.add_flag("--strict", a.strict,
               "exit 5 when a stable verdict rests on an assumption that can change it (a part "
               "held by a connection not modelled, a part left out, assumed rigid joints the "
               "model does not stand without), naming each");
}

// The audit's options from the arguments, or what is wrong with them.
std::variant<report::AuditOptions, std::string> audit_options(const Arguments& a) {
  report::AuditOptions options;
  if (!a.ldraw_dir.empty()) {
    if (!is_ldraw_library(a.ldraw_dir))
      return "--ldraw-dir " + a.ldraw_dir +
             " is not an LDraw library (no parts/ or p/ folder in it)";
    options.read.library_dirs = {a.ldraw_dir};
  } else {
    options.read.library_dirs = ldraw::library_dirs_from_env();
  }
  if (!a.main_model.empty()) options.read.main_model = a.main_model;
  options.stability.ground =
      a.ground == "table" ? physics::GroundMode::Table : physics::GroundMode::Baseplate;
  options.min_cm_gf = a.min_cm;
  options.strict = a.strict;
  options.stability.max_seconds = a.max_seconds;
  options.steps = a.steps || !a.instructions.empty();
  options.brick_capacity = !a.heatmap.empty();
  try {
    if (!a.instructions.empty()) {
      if (a.files.size() != 1) return std::string("--instructions takes one FILE");
      report::check_booklet_folder(a.instructions);
    }
    for (const auto& t : a.load_texts) options.loads.push_back(report::parse_load_spec(t));
    for (const auto& t : a.ground_part_texts)
      options.ground_parts.push_back(report::parse_line_spec(t, "--ground-part"));
  } catch (const InputError& e) {
    return std::string(e.what());
  }
  return options;
}

// Every heat map against every input, before anything is read or written: the heat map of one
// file must not replace another file still to be checked, nor the heat map of another. What is
// wrong, or nothing.
std::optional<std::string> heatmap_clash(const Arguments& a) {
  const auto& files = a.files;
  for (size_t i = 0; i < files.size(); ++i) {
    const fs::path out = heatmap_path(a.heatmap, files[i], files.size() > 1);
    try {
      app::check_outputs({{"--heatmap", out.string()}}, {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    for (size_t k = 0; k < files.size(); ++k) {
      if (app::same_file(out, files[k]))
        return "--heatmap: the heat map of " + files[i] + " (" + out.string() +
               ") would overwrite the input " + files[k];
      if (k < i && app::same_file(out, heatmap_path(a.heatmap, files[k], true)))
        return "--heatmap: " + files[k] + " and " + files[i] + " would write the same heat map " +
               out.string();
    }
  }
  return std::nullopt;
}

// Checks every file, `jobs` at once, and prints their reports in the order given; the worst
// exit code.
int check_files(const Arguments& a, report::AuditOptions options) {
  const int jobs_used = int(std::min(size_t(a.jobs), a.files.size()));
  // One file at a time: its independent structures' large blocks (a town's) two at a time.
  options.stability.block_jobs =
      jobs_used > 1 ? 1 : int(std::clamp(std::thread::hardware_concurrency(), 1u, 2u));
  // On a terminal only, and for one file at a time: lines of files checked at once would mix.
  const bool progress = !a.quiet && jobs_used == 1 && ::isatty(STDERR_FILENO);
  Reported reported;
  reported.files = a.files.size();
  Settings settings{options,   a.json,         a.quiet,     progress,    &reported,
                    a.heatmap, a.instructions, a.ldraw_dir, a.main_model};
  parts::PartLibrary library(options.read.library_dirs, BrickCatalog::standard());
  auto check = [&](size_t i) { return check_file(a.files[i], a.files.size(), settings, library); };
  run_in_order<FileReport>(a.files.size(), jobs_used, check, [&](size_t, FileReport&& r) {
    const std::lock_guard lock(reported.mutex);
    if (rank(r.code) > rank(reported.worst)) reported.worst = r.code;
    if (a.json)
      reported.all.push_back(std::move(r.json));
    else
      std::cout << r.text << std::flush;
    std::cerr << r.errors << std::flush;
  });
  const std::lock_guard lock(reported.mutex);
  if (a.json) print_json(a.files.size() == 1 ? reported.all[0] : reported.all);
  return reported.worst;
}

}  // namespace

int main(int argc, char** argv) {
  stop::install("brickcheck");  // before any thread starts: they inherit its signal mask
  CLI::App app{"brickcheck: check LDraw models (.ldr, .mpd) for connectivity and stability"};
  app.footer(kExitCodes);
  Arguments arguments;
  add_options(app, arguments);
  // A usage error on stderr, and with --json as a JSON object on stdout too, so that a script
  // reading stdout learns why there is no report. --json is looked for in the arguments as given:
  // a parse error leaves the flag unset.
  const bool wants_json = std::any_of(
      argv + 1, argv + argc, [](const char* arg) { return std::string_view(arg) == "--json"; });
  auto json_error = [&](const std::string& message) {
    if (wants_json)
      std::cout << nlohmann::json{{"error", message}, {"verdict", "usage"}, {"stable", false}}.dump(
                       2, ' ', false, nlohmann::json::error_handler_t::replace)
                << "\n";
  };
  auto usage_error = [&](const std::string& message) {
    std::cerr << "brickcheck: " << message << "\n";
    json_error(message);
    return kBadInput;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    app.exit(e);
    json_error(e.what());
    return kBadInput;
  }
  auto options = audit_options(arguments);
  if (const auto* error = std::get_if<std::string>(&options)) return usage_error(*error);
  if (!arguments.heatmap.empty())
    if (const auto clash = heatmap_clash(arguments)) return usage_error(*clash);
  return check_files(arguments, std::get<report::AuditOptions>(std::move(options)));
}
