#include "ldraw/writer.h"

#include <fmt/format.h>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/stop.h"
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

// What a builder reads where the supports begin (Brick::support). Their steps say when: those on
// the ground come first, those on the model (under what the mesh leaves in the air) with the layer
// they stand on.
constexpr const char* kSupportsWords =
    "Supports: columns that are not the model's, which it stands on; the model needs them to "
    "stand";

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
  auto supports_only = [&](const std::vector<size_t>& bricks) {
    return std::all_of(bricks.begin(), bricks.end(),
                       [&](size_t i) { return assembly.bricks[i].support; });
  };
  // A first step of supports only is the submodel "<stem>-supports.ldr".
  std::vector<std::string> names;
  int k = 0;
  for (const auto& [step, bricks] : steps) {
    ++k;
    names.push_back(k == 1 && supports_only(bricks) ? fmt::format("{}-supports.ldr", stem)
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

// The private folders a set of outputs is written in, one beside each destination folder (a
// rename does not cross file systems): made by mkdtemp (a name no other run shares, mode 0700, so
// that nothing planted in it is written through), listed for a stop, and removed when done.
class PrivateFolders {
 public:
  PrivateFolders() = default;
  PrivateFolders(const PrivateFolders&) = delete;
  PrivateFolders& operator=(const PrivateFolders&) = delete;
  ~PrivateFolders() {
    std::error_code ec;
    for (const auto& [dir, folder] : folders_) std::filesystem::remove_all(folder, ec);
  }

  // Where the output `path` is written before it is moved into place.
  std::filesystem::path file_for(const std::filesystem::path& path) {
    const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
    auto it = folders_.find(dir);
    if (it == folders_.end()) {
      std::string name = (dir / ".tmp-legolization-XXXXXX").string();
      if (!::mkdtemp(name.data()))
        throw InputError(path.string(), 0,
                         std::string("cannot write here: ") + std::strerror(errno));
      it = folders_.emplace(dir, name).first;
      on_stop_.push_back(std::make_unique<stop::RemovedOnStop>(name));
    }
    return it->second / path.filename();
  }

 private:
  std::map<std::filesystem::path, std::filesystem::path> folders_;
  std::vector<std::unique_ptr<stop::RemovedOnStop>> on_stop_;
};

// Writes `text` as the new file `written` (O_EXCL, O_NOFOLLOW), with the mode of the file at
// `path` it will replace (a 640 model stays 640), else the one a new file gets.
void write_new_file(const std::filesystem::path& written, const std::filesystem::path& path,
                    const std::string& text) {
  std::error_code ec;
  const auto old = std::filesystem::status(path, ec);
  const mode_t mode = !ec && std::filesystem::is_regular_file(old)
                          ? mode_t(old.permissions()) & 07777
                          : new_file_mode(false);
  const int fd =
      ::open(written.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) throw InputError(path.string(), 0, "cannot write here");
  bool ok = ::fchmod(fd, mode) == 0;
  for (size_t done = 0; ok && done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    ok = n > 0;
    if (ok) done += size_t(n);
  }
  ok = ::close(fd) == 0 && ok;
  if (!ok) throw InputError(path.string(), 0, "writing failed");
}

}  // namespace

mode_t new_file_mode(bool folder) {
  return (folder ? 0777 : 0666) & ~kUmask;
}

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
  PrivateFolders folders;
  std::vector<std::filesystem::path> written;
  {
    const stop::Publishing made_and_listed;  // a stop waits: it finds every folder made
    for (const auto& f : files) written.push_back(folders.file_for(f.first));
  }
  for (size_t i = 0; i < files.size(); ++i)
    write_new_file(written[i], files[i].first, files[i].second);
  // What cannot be renamed into place (a device, a FIFO) is written before anything moves, so
  // that a failure or a stop there still leaves every old output whole.
  for (const auto& [path, text] : direct) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw InputError(path.string(), 0, "writing failed");
  }
  // Every rename, or none: each file replaced is kept (a second name in the private folder) until
  // all are in place, and put back if one cannot move.
  const stop::Publishing publishing;
  std::vector<std::filesystem::path> kept(files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    const std::filesystem::path old = written[i].parent_path() / (".old-" + std::to_string(i));
    if (::link(files[i].first.c_str(), old.c_str()) == 0) kept[i] = old;
  }
  for (size_t i = 0; i < files.size(); ++i) {
    std::filesystem::rename(written[i], files[i].first, ec);
    if (!ec) continue;
    const std::string why = ec.message();
    for (size_t k = 0; k < i; ++k) {
      if (!kept[k].empty())
        std::filesystem::rename(kept[k], files[k].first, ec);
      else
        std::filesystem::remove(files[k].first, ec);
    }
    throw InputError(
        files[i].first.string(), 0,
        "cannot move the written file into place (" + why + "); every output is as it was");
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
