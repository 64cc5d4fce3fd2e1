// The fuzz step of CI (issue 19, tools/fuzz.sh). Mutated LDraw files go through the reader, the
// part knowledge, the physics and the reports in this process, and through the brickcheck
// program as a user runs it; mutated OBJ, PLY and STL meshes go through the legolize program.
// A crash, a hang over --timeout seconds, a sanitizer report, an uncaught exception, an exit code
// outside the documented ones or JSON that does not parse is a failure: its input is saved under
// --out and shown in the log, and the run exits 1. Built with the sanitizers (build-asan), a
// report inside this process stops it: tools/fuzz.sh then shows the input it was working on,
// which is always saved first as --out/current.mpd.
#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/stopwatch.h"
#include "ldraw_mutator.h"
#include "mesh_mutator.h"
#include "report/audit.h"
#include "report/render.h"

using namespace lego;
using namespace lego::fuzz;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// The input as C-escaped text, cut to `limit` bytes, for the log.
std::string escaped(const std::string& text, size_t limit = 1500) {
  std::string out;
  for (size_t i = 0; i < text.size() && i < limit; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n')
      out += "\\n\n";
    else if (c == '\\')
      out += "\\\\";
    else if (c < 32 || c >= 127)
      out += fmt::format("\\x{:02x}", c);
    else
      out += char(c);
  }
  if (text.size() > limit) out += fmt::format("... ({} bytes in all)", text.size());
  return out;
}

// "brickcheck/steps" → "brickcheck-steps"
std::string file_name(std::string category) {
  std::replace(category.begin(), category.end(), '/', '-');
  return category;
}

struct Tally {
  int inputs = 0, crashes = 0, hangs = 0, sanitizer = 0, other = 0;
  double slowest = 0;
  std::string slowest_input;  // saved where
};

class Report {
 public:
  explicit Report(fs::path out) : out_(std::move(out)) { fs::create_directories(out_ / "failed"); }

  // A failure: the input saved and shown.
  void fail(const std::string& category, const std::string& kind, const std::string& what,
            const std::string& input, const std::string& extension, const std::string& extra = {}) {
    Tally& t = tallies_[category];
    if (kind == "crash")
      ++t.crashes;
    else if (kind == "hang")
      ++t.hangs;
    else if (kind == "sanitizer")
      ++t.sanitizer;
    else
      ++t.other;
    const fs::path saved =
        out_ / "failed" / fmt::format("{}-{}{}", file_name(category), ++failures_, extension);
    write_file(saved, input);
    if (!extra.empty()) write_file(saved.string() + ".mtl", extra);
    std::cout << fmt::format(
                     "FAIL {} [{}]: {}\n  input saved as {}\n--- input ---\n{}\n-------------\n",
                     kind, category, what, saved.string(), escaped(input))
              << std::flush;
  }
  void ran(const std::string& category, double seconds, const std::string& input,
           const std::string& extension) {
    Tally& t = tallies_[category];
    ++t.inputs;
    if (seconds > t.slowest) {
      t.slowest = seconds;
      t.slowest_input =
          (out_ / fmt::format("slowest-{}{}", file_name(category), extension)).string();
      write_file(t.slowest_input, input);
    }
  }
  int failures() const { return failures_; }

  void print(double seconds) const {
    std::cout << fmt::format("\n{:<24} {:>8} {:>8} {:>6} {:>10} {:>6} {:>10}  {}\n", "category",
                             "inputs", "crashes", "hangs", "sanitizer", "other", "slowest_s",
                             "slowest input");
    Tally all;
    for (const auto& [name, t] : tallies_) {
      std::cout << fmt::format("{:<24} {:>8} {:>8} {:>6} {:>10} {:>6} {:>10.3f}  {}\n", name,
                               t.inputs, t.crashes, t.hangs, t.sanitizer, t.other, t.slowest,
                               t.slowest_input);
      all.inputs += t.inputs, all.crashes += t.crashes, all.hangs += t.hangs;
      all.sanitizer += t.sanitizer, all.other += t.other;
      if (t.slowest > all.slowest) all.slowest = t.slowest, all.slowest_input = t.slowest_input;
    }
    std::cout << fmt::format("{:<24} {:>8} {:>8} {:>6} {:>10} {:>6} {:>10.3f}  {}\n", "all",
                             all.inputs, all.crashes, all.hangs, all.sanitizer, all.other,
                             all.slowest, all.slowest_input);
    std::cout << fmt::format("{} failures in {:.0f} s\n", failures_, seconds);
  }

 private:
  fs::path out_;
  std::map<std::string, Tally> tallies_;
  int failures_ = 0;
};

std::vector<std::string> load_seeds(const std::vector<std::string>& dirs) {
  size_t builtin_count = 0;
  const std::string* builtin = builtin_ldraw_seeds(builtin_count);
  std::vector<std::string> seeds(builtin, builtin + builtin_count);
  for (const auto& dir : dirs) {
    if (!fs::is_directory(dir)) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const auto ext = entry.path().extension();
      if ((ext == ".ldr" || ext == ".mpd" || ext == ".dat") && entry.file_size() <= 64 * 1024)
        files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());  // the same seeds in the same order on every machine
    for (const auto& f : files) seeds.push_back(read_file(f));
  }
  return seeds;
}

// A hang inside this process cannot be interrupted: the watchdog reports it and ends the run.
class Watchdog {
 public:
  Watchdog(double limit, fs::path current) : limit_(limit), current_(std::move(current)) {
    thread_ = std::thread([this] {
      while (!stop_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        const long started = started_ns_;
        if (started == 0) continue;
        const double elapsed = double(Clock::now().time_since_epoch().count() - started) * 1e-9;
        if (elapsed > limit_) {
          std::cout << fmt::format(
                           "FAIL hang [in-process]: over {:.0f} s on the input saved as {}\n"
                           "--- input ---\n{}\n-------------\n",
                           limit_, current_.string(), escaped(read_file(current_)))
                    << std::flush;
          std::_Exit(1);
        }
      }
    });
  }
  ~Watchdog() {
    stop_ = true;
    thread_.join();
  }
  void start() { started_ns_ = long(Clock::now().time_since_epoch().count()); }
  void stop() { started_ns_ = 0; }

 private:
  double limit_;
  fs::path current_;
  std::atomic<long> started_ns_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

void fuzz_in_process(int count, const std::vector<std::string>& seeds,
                     const std::vector<fs::path>& library_dirs, double timeout, Rng& rng,
                     const fs::path& out, Report& report) {
  const fs::path current = out / "current.mpd";
  Watchdog watchdog(timeout, current);
  report::AuditOptions base;
  base.read.library_dirs = library_dirs;
  base.read.max_parts = 200000;  // brickcheck's 2,000,000 would make a copied line take minutes
  // The analysis, and the build steps after it, give up long before an input counts as a hang.
  base.stability.max_seconds = timeout / 4;
  parts::PartLibrary library(library_dirs, BrickCatalog::standard());
  for (int i = 0; i < count; ++i) {
    const auto mutation = LdrawMutation(i % kLdrawMutations);
    const std::string category = std::string("in-process/") + name(mutation);
    const std::string input = mutate_ldraw(seeds[rng() % seeds.size()], mutation, rng);
    write_file(current, input);
    report::AuditOptions options = base;
    options.steps = rng() % 10 == 0;
    options.brick_capacity = rng() % 10 == 0;
    if (rng() % 10 == 0) options.stability.ground = physics::GroundMode::Table;
    const auto start = Clock::now();
    watchdog.start();
    try {
      report::Audit audit;
      try {
        audit = report::audit_file(current, options, library);
      } catch (const InputError& e) {
        audit.file = current.string();
        audit.verdict = report::Verdict::Unreadable;
        audit.fatal = e.what();
      }
      // What brickcheck prints, in every form.
      (void)report::render_json(audit, options)
          .dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
      (void)report::render_text(audit, false);
      if (options.brick_capacity && audit.verdict != report::Verdict::Unreadable &&
          audit.verdict != report::Verdict::NothingToAnalyse)
        (void)report::render_heatmap(audit);
    } catch (const std::exception& e) {
      report.fail(category, "exception", e.what(), input, ".mpd");
    }
    watchdog.stop();
    report.ran(category, seconds_since(start), input, ".mpd");
    if ((i + 1) % 2000 == 0)
      std::cout << fmt::format("in-process: {} of {}\n", i + 1, count) << std::flush;
  }
}

struct ProcessRun {
  bool timed_out = false;
  bool signalled = false;
  int code = -1;  // exit code, or the signal
  std::string out, err;
  double seconds = 0;
};

// Runs `argv` with its output in files under `dir`, killing it (and whatever it started) after
// `timeout` seconds.
ProcessRun run_process(const std::vector<std::string>& argv, const fs::path& dir, double timeout) {
  const fs::path out_file = dir / "stdout", err_file = dir / "stderr";
  ProcessRun run;
  const auto start = Clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    const int o = ::open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, 1);
    ::dup2(e, 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (seconds_since(start) > timeout) {
      ::kill(-pid, SIGKILL);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      run.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ::kill(-pid, SIGKILL);  // a mesh reader child left behind
  run.seconds = seconds_since(start);
  if (WIFSIGNALED(status)) run.signalled = true, run.code = WTERMSIG(status);
  if (WIFEXITED(status)) run.code = WEXITSTATUS(status);
  run.out = read_file(out_file);
  run.err = read_file(err_file);
  return run;
}

bool sanitizer_report(const std::string& err) {
  return err.find("Sanitizer") != std::string::npos ||
         err.find("runtime error:") != std::string::npos;
}

// A report whose first frame is inside Assimp, in legolize's guarded reader: the README's "a mesh
// Assimp crashes on" (exit 2, the file named), which we cannot fix. One frame of ours first, and it
// is ours (the PLY whose face named vertex 139 of 3 crashed in our loop, in that same child).
bool assimp_report(const std::string& err) {
  const size_t frame = err.find("    #0 ");
  if (frame == std::string::npos || err.find("runtime error:") != std::string::npos) return false;
  const size_t end = err.find('\n', frame);
  return err.substr(frame, end - frame).find("libassimp") != std::string::npos &&
         err.find("the mesh cannot be read: the reader crashed") != std::string::npos;
}

// The verdict of one run of our programs: fine, or a failure with its kind.
void judge(const ProcessRun& run, const std::set<int>& documented, bool json_out,
           const std::string& category, const std::string& input, const std::string& extension,
           const std::string& extra, const std::string& command, Report& report) {
  auto tail = [&] { return run.err.substr(0, 1200); };
  if (run.timed_out)
    return report.fail(category, "hang", fmt::format("{} ran over its time", command), input,
                       extension, extra);
  if (sanitizer_report(run.err) && !(run.code == 2 && assimp_report(run.err)))
    return report.fail(category, "sanitizer", command + "\n" + tail(), input, extension, extra);
  if (run.signalled)
    return report.fail(category, "crash",
                       fmt::format("{} died of signal {}\n{}", command, run.code, tail()), input,
                       extension, extra);
  if (!documented.count(run.code))
    return report.fail(
        category, "exit",
        fmt::format("{} exited {}, not a documented code\n{}", command, run.code, tail()), input,
        extension, extra);
  if (json_out && !run.out.empty() && !nlohmann::json::accept(run.out))
    return report.fail(category, "json", command + " printed JSON that does not parse", input,
                       extension, extra);
}

void fuzz_brickcheck(int count, const std::vector<std::string>& seeds, const fs::path& bin,
                     const std::string& ldraw_dir, double timeout, Rng& rng, const fs::path& out,
                     Report& report) {
  const fs::path dir = out / "brickcheck";
  fs::create_directories(dir);
  const fs::path model = dir / "model.mpd";
  static const std::vector<std::vector<std::string>> kOptions = {
      {},
      {"--steps"},
      {"--ground", "table"},
      {"--strict"},
      {"--load", "top=50"},
      {"--load", "step:2=20"},
      {"--ground-part", "2"},
      {"--min-cm", "10"},
      {"--heatmap", (dir / "heat.ldr").string()},
      {"--load", "99999999999=5"},
      {"--load", "5=1e999"},
      {"--load", std::string(60000, '1') + "=5"},
      {"--max-seconds", "0.5"},
      {"--main", "sub.ldr"},
  };
  for (int i = 0; i < count; ++i) {
    const auto mutation = LdrawMutation(i % kLdrawMutations);
    const std::string category = std::string("brickcheck/") + name(mutation);
    const std::string input = mutate_ldraw(seeds[rng() % seeds.size()], mutation, rng);
    write_file(model, input);
    std::vector<std::string> argv = {(bin / "brickcheck").string(), "--json"};
    if (!ldraw_dir.empty()) argv.insert(argv.end(), {"--ldraw-dir", ldraw_dir});
    const auto& extra = kOptions[rng() % kOptions.size()];
    if (extra.empty() || extra[0] != "--max-seconds")  // giving up long before a hang
      argv.insert(argv.end(), {"--max-seconds", fmt::format("{}", timeout / 4)});
    argv.insert(argv.end(), extra.begin(), extra.end());
    argv.push_back(model.string());
    const ProcessRun run = run_process(argv, dir, timeout);
    std::string command;
    for (const auto& a : argv) {
      if (!command.empty()) command += ' ';
      command.append(a, 0, 80);
    }
    std::set<int> documented = {0, 1, 2, 3, 4};
    if (std::find(extra.begin(), extra.end(), "--strict") != extra.end())
      documented.insert(5);  // stable only by an assumption
    judge(run, documented, true, category, input, ".mpd", {}, command, report);
    report.ran(category, run.seconds, input, ".mpd");
  }
}

void fuzz_legolize(int count, const fs::path& bin, double timeout, Rng& rng, const fs::path& out,
                   Report& report) {
  const fs::path dir = out / "legolize";
  fs::create_directories(dir);
  for (int i = 0; i < count; ++i) {
    const auto format = MeshFormat(i % kMeshFormats);
    const std::string category = std::string("legolize/") + name(format);
    const MeshFile mesh = mutated_mesh(format, rng);
    const fs::path path = dir / ("mesh" + mesh.extension);
    write_file(path, mesh.text);
    fs::remove(dir / "mesh.mtl");
    if (!mesh.mtl.empty()) write_file(dir / "mesh.mtl", mesh.mtl);
    fs::remove(dir / "out.ldr");
    fs::remove(dir / "report.json");
    const std::vector<std::string> argv = {(bin / "legolize").string(),
                                           path.string(),
                                           "-o",
                                           (dir / "out.ldr").string(),
                                           "--report",
                                           (dir / "report.json").string(),
                                           "--height",
                                           std::to_string(2 + rng() % 4),
                                           "--read-seconds",
                                           fmt::format("{}", timeout / 2)};
    const ProcessRun run = run_process(argv, dir, timeout);
    judge(run, {0, 1, 2, 4}, false, category, mesh.text, mesh.extension, mesh.mtl,
          "legolize " + path.string(), report);
    if (!run.timed_out && !run.signalled && run.code != 2 && fs::exists(dir / "report.json") &&
        !nlohmann::json::accept(read_file(dir / "report.json")))
      report.fail(category, "json", "legolize wrote a report that does not parse", mesh.text,
                  mesh.extension, mesh.mtl);
    report.ran(category, run.seconds, mesh.text, mesh.extension);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "legolization-fuzz: mutated LDraw files and meshes through our readers and programs"};
  uint64_t seed = 1;
  int in_process = 20000, brickcheck = 1000, legolize = 60;
  double timeout = 10;
  std::string bin, ldraw_dir, out = "fuzz-out";
  std::vector<std::string> seed_dirs;
  app.add_option("--seed", seed, "the random seed (printed; the same seed, the same inputs)");
  app.add_option("--in-process", in_process,
                 "mutated LDraw files through reader, part knowledge, physics and reports here");
  app.add_option("--brickcheck", brickcheck, "mutated LDraw files through the brickcheck program");
  app.add_option("--legolize", legolize, "mutated meshes through the legolize program");
  app.add_option("--timeout", timeout, "seconds an input may take before it counts as a hang");
  app.add_option("--bin", bin, "the folder with brickcheck and legolize")->required();
  app.add_option("--ldraw-dir", ldraw_dir, "an LDraw library for the part files (optional)");
  app.add_option("--seeds", seed_dirs, "folders whose .ldr, .mpd and .dat files are seeds");
  app.add_option("--out", out, "where inputs that fail, and the slowest ones, are saved");
  CLI11_PARSE(app, argc, argv);

  const auto start = Clock::now();
  fs::create_directories(out);
  Report report(out);
  const auto seeds = load_seeds(seed_dirs);
  std::vector<fs::path> library_dirs;
  if (!ldraw_dir.empty()) library_dirs.push_back(ldraw_dir);
  std::cout << fmt::format(
                   "fuzz: seed {}, {} seed files, {} in-process, {} brickcheck, {} legolize\n",
                   seed, seeds.size(), in_process, brickcheck, legolize)
            << std::flush;
  Rng rng(seed);
  fuzz_in_process(in_process, seeds, library_dirs, timeout, rng, out, report);
  fuzz_brickcheck(brickcheck, seeds, bin, ldraw_dir, timeout, rng, out, report);
  fuzz_legolize(legolize, bin, timeout, rng, out, report);
  report.print(seconds_since(start));
  return report.failures() == 0 ? 0 : 1;
}
