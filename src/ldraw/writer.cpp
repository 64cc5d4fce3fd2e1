#include "ldraw/writer.h"

#include <fmt/format.h>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <system_error>

#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <csignal>

#include "core/error.h"
#include "core/text.h"

namespace lego::ldraw {
namespace {

std::string number(double v) {
  std::string s = fmt::format("{:.4f}", v);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

std::string color_field(int code) {
  return code >= kDirectColorBase ? fmt::format("0x2{:06X}", code - kDirectColorBase)
                                  : std::to_string(code);
}

std::string brick_line(const Brick& b, const std::array<int, 3>& origin) {
  return part_line(b.color, brick_transform(b, origin), b.type->part + ".dat");
}

// A header field is one line: control characters (a newline in a mesh's file name) would start
// new LDraw lines of their own.
std::string one_line(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return text;
}

std::string header(const std::string& title, const std::string& name, const std::string& author) {
  return fmt::format("0 {}\n0 Name: {}\n0 Author: {}\n0 !LDRAW_ORG Unofficial_Model\n\n",
                     one_line(title), one_line(name), one_line(author));
}

// Brick indices ordered by step, stable within a step.
std::vector<size_t> by_step(const Assembly& a) {
  std::vector<size_t> order(a.bricks.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
    return a.bricks[x].source.step < a.bricks[y].source.step;
  });
  return order;
}

}  // namespace

std::string part_line(int color, const Transform& t, const std::string& reference) {
  std::string line = fmt::format("1 {} {} {} {}", color_field(color), number(t.pos[0]),
                                 number(t.pos[1]), number(t.pos[2]));
  for (double m : t.rot) {
    line += ' ';
    line += number(m);
  }
  line += fmt::format(" {}\n", reference);
  return line;
}

Transform brick_transform(const Brick& brick, const std::array<int, 3>& origin_ldu) {
  const Pose pose = model_pose(brick);
  Transform t;
  for (int a = 0; a < 3; ++a) t.pos[size_t(a)] = origin_ldu[size_t(a)] + pose.origin[size_t(a)];
  t.rot = pose.rotation;
  return t;
}

namespace {

// What a builder reads where the supports begin (Brick::support).
constexpr const char* kSupportsWords =
    "Supports: columns that are not the model's, which it stands on. Build them first; the model "
    "needs them to stand";

// The bricks of one assembly by build step, `0 STEP` after each step. Supports are a group of
// their own (LeoCAD's, which other editors keep as comments), so that they can be seen and
// selected together.
std::string bricks_by_step(const Assembly& assembly, bool steps) {
  std::string out;
  auto order = steps ? by_step(assembly) : std::vector<size_t>{};
  if (!steps)
    for (size_t i = 0; i < assembly.bricks.size(); ++i) order.push_back(i);
  bool in_supports = false;
  for (size_t k = 0; k < order.size(); ++k) {
    const Brick& b = assembly.bricks[order[k]];
    if (in_supports && !b.support) {
      out += "0 !LEOCAD GROUP END\n";
      in_supports = false;
    }
    if (steps && k > 0 && assembly.bricks[order[k - 1]].source.step != b.source.step)
      out += "0 STEP\n";
    if (b.support && !in_supports) {
      out += fmt::format("0 // {}.\n0 !LEOCAD GROUP BEGIN Supports\n", kSupportsWords);
      in_supports = true;
    }
    out += brick_line(b, assembly.origin_ldu);
  }
  if (in_supports) out += "0 !LEOCAD GROUP END\n";
  if (steps && !order.empty()) out += "0 STEP\n";
  return out;
}

std::string piece_comment(size_t k, size_t n) {
  return fmt::format(
      "0 // Piece {} of {}: it does not reach the ground. Build it apart, then set it in "
      "place.\n",
      k, n);
}

// One model of an .mpd: its file, placing a submodel per build step (and `extra` lines after
// them), then the step submodels.
std::string mpd_model(const Assembly& assembly, const std::string& name, const std::string& title,
                      const std::string& author, const std::string& extra) {
  const std::string stem = std::filesystem::path(name).stem().string();
  std::map<int, std::vector<size_t>> steps;
  for (size_t i : by_step(assembly)) steps[assembly.bricks[i].source.step].push_back(i);
  std::string out = "0 FILE " + name + "\n" + header(title, name, author);
  // A step of supports only is the submodel "<stem>-supports.ldr".
  auto supports_only = [&](const std::vector<size_t>& bricks) {
    return std::all_of(bricks.begin(), bricks.end(),
                       [&](size_t i) { return assembly.bricks[i].support; });
  };
  std::vector<std::string> names;
  int k = 0;
  for (const auto& [step, bricks] : steps) {
    ++k;
    names.push_back(supports_only(bricks) ? fmt::format("{}-supports.ldr", stem)
                                          : fmt::format("{}-step-{:03}.ldr", stem, k));
    if (supports_only(bricks)) out += fmt::format("0 // {}.\n", kSupportsWords);
    out += "1 16 0 0 0 1 0 0 0 1 0 0 0 1 " + names.back() + "\n0 STEP\n";
  }
  out += extra + "0 NOFILE\n";
  k = 0;
  for (const auto& [step, bricks] : steps) {
    const std::string& file = names[k++];
    const std::string step_title = supports_only(bricks)
                                       ? fmt::format("{} - step {}: supports", title, k)
                                       : fmt::format("{} - step {}", title, k);
    out += "0 FILE " + file + "\n" + header(step_title, file, author);
    for (size_t i : bricks) out += brick_line(assembly.bricks[i], assembly.origin_ldu);
    out += "0 NOFILE\n";
  }
  return out;
}

}  // namespace

std::string to_ldr(const Assembly& assembly, const WriteOptions& options) {
  return to_ldr(std::vector<const Assembly*>{&assembly}, options);
}

std::string to_ldr(const std::vector<const Assembly*>& pieces, const WriteOptions& options) {
  std::string out =
      header(options.title, options.name.empty() ? "model.ldr" : options.name, options.author);
  for (size_t k = 0; k < pieces.size(); ++k) {
    if (k > 0) out += piece_comment(k + 1, pieces.size());
    out += bricks_by_step(*pieces[k], options.steps);
  }
  return out;
}

std::string piece_submodel_name(const std::string& model_name, int piece) {
  return fmt::format("{}-piece-{}.ldr", std::filesystem::path(model_name).stem().string(), piece);
}

std::string to_mpd(const Assembly& assembly, const WriteOptions& options) {
  return to_mpd(std::vector<const Assembly*>{&assembly}, options);
}

std::string to_mpd(const std::vector<const Assembly*>& pieces, const WriteOptions& options) {
  const std::string main_name = options.name.empty() ? "model.ldr" : options.name;
  std::string extra, rest;
  for (size_t k = 1; k < pieces.size(); ++k) {
    const std::string name = piece_submodel_name(main_name, int(k) + 1);
    extra +=
        piece_comment(k + 1, pieces.size()) + "1 16 0 0 0 1 0 0 0 1 0 0 0 1 " + name + "\n0 STEP\n";
    rest += mpd_model(*pieces[k], name, fmt::format("{} - piece {}", options.title, k + 1),
                      options.author, "");
  }
  return mpd_model(*pieces.front(), main_name, options.title, options.author, extra) + rest;
}

namespace {

// The process's umask, read once before any thread starts (reading it means setting it): the
// mode a new output gets, as if the program had created it with open().
const mode_t kUmask = [] {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return mask;
}();

// A file being written beside its destination, to be renamed over it.
struct Temporary {
  std::filesystem::path path;
  int fd = -1;
};

// A new temporary beside `path`, made by mkstemp: a name no other run shares, created with
// O_EXCL, so that a link planted under a predictable name is never written through.
Temporary create_temporary(const std::filesystem::path& path) {
  std::string name = path.string() + ".tmp-legolization-XXXXXX";
  const int fd = ::mkstemp(name.data());
  if (fd < 0) throw InputError(path.string(), 0, "cannot write here");
  return {name, fd};
}

// Writes `text` into the temporary for `path` and closes it, with the mode of the file it
// replaces (a 640 model stays 640), else the one a new file gets.
void write_temporary(Temporary& t, const std::filesystem::path& path, const std::string& text) {
  std::error_code ec;
  const auto old = std::filesystem::status(path, ec);
  const mode_t mode = !ec && std::filesystem::is_regular_file(old)
                          ? mode_t(old.permissions()) & 07777
                          : 0666 & ~kUmask;
  bool ok = ::fchmod(t.fd, mode) == 0;
  for (size_t done = 0; ok && done < text.size();) {
    const ssize_t n = ::write(t.fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    ok = n > 0;
    if (ok) done += size_t(n);
  }
  ok = ::close(t.fd) == 0 && ok;
  t.fd = -1;
  if (!ok) throw InputError(path.string(), 0, "writing failed");
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  write_files_atomically({{path, text}});
}

// Where a file named by the user is written: through a symbolic link to the file it names (the
// link stays), and straight into what is not a regular file (a device, a FIFO), which cannot be
// replaced by a rename. A folder is refused.
struct Destination {
  std::filesystem::path path;
  bool direct = false;
};

Destination destination_of(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  Destination d{path, false};
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    d.path = fs::canonical(path, ec);
    // A link to nothing that has a name (a dangling link, /dev/stdout to a pipe): through it.
    if (ec) return {path, true};
  }
  const auto status = fs::status(d.path, ec);
  if (fs::is_directory(status)) throw InputError(path.string(), 0, "is a folder");
  d.direct = fs::exists(status) && !fs::is_regular_file(status);
  return d;
}

namespace {

// The temporaries of the outputs being written, for a signal handler to remove: a run stopped by
// SIGINT, SIGTERM or SIGHUP before its outputs are in place leaves the old files whole and no
// temporary behind. Threads writing at once (brickcheck -j) each hold slots; the handler is
// installed while any slot is. (Plain arrays: the handler may only call async-signal-safe
// functions. A slot's path is written before it is marked used, and it is marked free before it
// is written again.)
constexpr int kMaxPending = 64;
char g_pending[kMaxPending][4096];
volatile std::sig_atomic_t g_pending_used[kMaxPending] = {};

extern "C" void remove_pending_and_stop(int signal_number) {
  for (int i = 0; i < kMaxPending; ++i)
    if (g_pending_used[i]) ::unlink(g_pending[i]);
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};

// While alive: the temporaries are removed if the process is stopped.
class PendingTemporaries {
 public:
  explicit PendingTemporaries(const std::vector<std::filesystem::path>& temporaries) {
    const std::lock_guard lock(mutex_);
    for (const auto& t : temporaries) {
      const std::string text = t.string();
      if (text.size() >= sizeof g_pending[0]) continue;
      int slot = 0;
      while (slot < kMaxPending && g_pending_used[slot]) ++slot;
      if (slot == kMaxPending) break;
      std::copy(text.begin(), text.end(), g_pending[slot]);
      g_pending[slot][text.size()] = '\0';
      g_pending_used[slot] = 1;
      slots_.push_back(slot);
    }
    if (holders_++ > 0) return;
    struct sigaction action {};
    action.sa_handler = remove_pending_and_stop;
    sigemptyset(&action.sa_mask);
    for (size_t i = 0; i < std::size(kStopSignals); ++i)
      ::sigaction(kStopSignals[i], &action, &previous_[i]);
  }
  ~PendingTemporaries() {
    const std::lock_guard lock(mutex_);
    for (int slot : slots_) g_pending_used[slot] = 0;
    if (--holders_ > 0) return;
    for (size_t i = 0; i < std::size(kStopSignals); ++i)
      ::sigaction(kStopSignals[i], &previous_[i], nullptr);
  }
  PendingTemporaries(const PendingTemporaries&) = delete;
  PendingTemporaries& operator=(const PendingTemporaries&) = delete;

 private:
  std::vector<int> slots_;
  // Shared by the threads writing: how many hold slots, and the handlers before the first.
  static inline std::mutex mutex_;
  static inline int holders_ = 0;
  static inline struct sigaction previous_[std::size(kStopSignals)]{};
};

// Stop signals wait while alive: the renames that put the outputs in place all happen, or none.
class SignalsWait {
 public:
  SignalsWait() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : kStopSignals) sigaddset(&set, s);
    ::pthread_sigmask(SIG_BLOCK, &set, &previous_);
  }
  ~SignalsWait() { ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  SignalsWait(const SignalsWait&) = delete;
  SignalsWait& operator=(const SignalsWait&) = delete;

 private:
  sigset_t previous_;
};

}  // namespace

void write_files_atomically(
    const std::vector<std::pair<std::filesystem::path, std::string>>& given) {
  std::error_code ec;
  std::vector<std::pair<std::filesystem::path, std::string>> files, direct;
  for (const auto& [path, text] : given) {
    const Destination d = destination_of(path);
    (d.direct ? direct : files).emplace_back(d.path, text);
  }
  // Two texts for one file: one would silently replace the other. Refused before anything is
  // written.
  for (size_t i = 0; i < given.size(); ++i)
    for (size_t k = 0; k < i; ++k) {
      auto resolved = [&](const std::filesystem::path& p) {
        return std::filesystem::weakly_canonical(std::filesystem::absolute(p, ec), ec);
      };
      if (resolved(given[i].first) == resolved(given[k].first))
        throw InputError(given[i].first.string(), 0, "two outputs name this one file");
    }
  // Created and listed for the stop handler with stop signals waiting: a stop removes every
  // temporary made.
  std::vector<Temporary> temporaries;
  std::optional<PendingTemporaries> pending;
  auto remove_temporaries = [&] {
    for (Temporary& t : temporaries) {
      if (t.fd >= 0) ::close(t.fd);
      std::filesystem::remove(t.path, ec);
    }
  };
  {
    const SignalsWait wait;
    try {
      for (const auto& f : files) temporaries.push_back(create_temporary(f.first));
    } catch (const InputError&) {
      remove_temporaries();
      throw;
    }
    std::vector<std::filesystem::path> names;
    for (const Temporary& t : temporaries) names.push_back(t.path);
    pending.emplace(names);
  }
  try {
    for (size_t i = 0; i < files.size(); ++i)
      write_temporary(temporaries[i], files[i].first, files[i].second);
    // What cannot be renamed into place (a device, a FIFO) is written before anything moves, so
    // that a failure or a stop there still leaves every old output whole.
    for (const auto& [path, text] : direct) {
      std::ofstream out(path, std::ios::binary);
      out << text;
      out.flush();
      if (!out) throw InputError(path.string(), 0, "writing failed");
    }
  } catch (const InputError&) {
    remove_temporaries();
    throw;
  }
  const SignalsWait wait;
  for (size_t i = 0; i < files.size(); ++i) {
    std::filesystem::rename(temporaries[i].path, files[i].first, ec);
    if (ec) {
      for (size_t k = i; k < files.size(); ++k) std::filesystem::remove(temporaries[k].path, ec);
      throw InputError(files[i].first.string(), 0, "cannot move the written file into place");
    }
  }
}

bool is_mpd(const std::filesystem::path& path) {
  return ascii_lower(path.extension().string()) == ".mpd";
}

std::string model_text(const std::filesystem::path& path, const Assembly& assembly,
                       WriteOptions options) {
  return model_text(path, std::vector<const Assembly*>{&assembly}, std::move(options));
}

std::string model_text(const std::filesystem::path& path,
                       const std::vector<const Assembly*>& pieces, WriteOptions options) {
  if (options.name.empty()) options.name = path.filename().string();
  return is_mpd(path) ? to_mpd(pieces, options) : to_ldr(pieces, options);
}

void write_model(const std::filesystem::path& path, const Assembly& assembly,
                 WriteOptions options) {
  write_file_atomically(path, model_text(path, assembly, std::move(options)));
}

}  // namespace lego::ldraw
