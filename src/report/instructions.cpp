#include "report/instructions.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <regex>
#include <set>

#include "core/brick_catalog.h"
#include "core/error.h"
#include "core/stop.h"
#include "core/text.h"
#include "ldraw/color_table.h"
#include "ldraw/writer.h"
#include "report/step_camera.h"

namespace lego::report {

namespace fs = std::filesystem;

namespace {

// Marks a folder as ours: a booklet written before may be replaced, nothing else.
constexpr const char* kGenerator = R"(<meta name="generator" content="legolization booklet">)";
constexpr int kWidth = 640, kHeight = 480;
// A picture's size on disk at most: LeoCAD's 640x480 PNGs of the Datsville buildings are 40 to
// 150 kB.
constexpr uintmax_t kPictureBytes = 512 << 10;
constexpr int kRenderSeconds = 900;  // per LeoCAD run; a large town building takes a minute

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  return out;
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool have(const char* program) {
  return stop::run_command(fmt::format("command -v {} >/dev/null 2>&1", program)) == 0;
}

// A part's name as a builder reads it: the catalog's, else the first line of its own file
// without the library's marks ("=Brick 1 x 1", "~Plate 1 x 2 (Obsolete)" are a brick and a
// plate to the builder).
std::string part_name(const ldraw::PlacedPart& p) {
  if (const BrickType* t = BrickCatalog::standard().find(p.part))
    return readable_part_name(t->name);
  if (!p.definition.empty()) {
    std::ifstream in(p.definition);
    std::string line;
    if (std::getline(in, line)) {
      while (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.starts_with("0 "))
        if (std::string name = readable_part_name(std::string_view(line).substr(2)); !name.empty())
          return name;
    }
  }
  return p.part;
}

std::vector<PartCount> sorted(std::map<std::pair<std::string, int>, PartCount> counts) {
  std::vector<PartCount> out;
  for (auto& [key, c] : counts) out.push_back(c);
  return out;
}

// Whether DIR holds a booklet of ours: its index.html, a regular file (not a link to a device or
// a FIFO, which would never end), begins with our generator line.
bool is_booklet(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(dir / "index.html", ec))) return false;
  std::ifstream index(dir / "index.html", std::ios::binary);
  std::string head(4096, '\0');
  index.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(index.gcount()));
  return head.find(kGenerator) != std::string::npos;
}

// The files of a booklet: what a new booklet replaces in DIR. Anything else there is the user's
// and moves into the new one.
bool booklet_file(const std::string& name) {
  static const std::regex ours(
      R"(step-\d{3,}\.png|part-\d{3,}\.png|cover\.png|index\.html|instructions\.pdf)");
  return std::regex_match(name, ours);
}

// The booklet is made in a new private folder beside DIR and swapped in when whole: a stop or a
// failure on the way leaves the old booklet as it was.
class NewFolder {
 public:
  explicit NewFolder(const fs::path& dir) {
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    std::error_code ec;
    fs::create_directories(parent, ec);
    std::string name = (parent / ".tmp-legolization-XXXXXX").string();
    if (!::mkdtemp(name.data()))
      throw InputError(
          dir.string(), 0,
          std::string("--instructions: cannot make a folder beside it: ") + std::strerror(errno));
    path_ = name;
    on_stop_.emplace(path_);
    ::chmod(path_.c_str(), ldraw::new_file_mode(true));
  }
  ~NewFolder() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  NewFolder(const NewFolder&) = delete;
  NewFolder& operator=(const NewFolder&) = delete;
  const fs::path& path() const { return path_; }

  // Puts the folder in DIR's place at once (the old booklet goes; the user's other files there
  // come into the new one) and returns a note when something could not move.
  std::string publish(const fs::path& dir) {
    const stop::Publishing publishing;
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(dir, ec))) {
      fs::rename(path_, dir, ec);
      if (ec)
        throw InputError(dir.string(), 0, "--instructions: cannot move the booklet into place");
      path_.clear();
      return {};
    }
    if (::renameat2(AT_FDCWD, path_.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) != 0)
      throw InputError(
          dir.string(), 0,
          std::string("--instructions: cannot put the booklet in place: ") + std::strerror(errno));
    // path_ now holds the old folder.
    std::string note;
    for (const auto& e : fs::directory_iterator(path_, ec)) {
      const std::string name = e.path().filename().string();
      if (booklet_file(name)) continue;
      fs::rename(e.path(), dir / name, ec);
      if (ec) note = "some of the files that were in " + dir.string() + " are in " + path_.string();
    }
    if (note.empty()) fs::remove_all(path_, ec);
    path_.clear();
    return note;
  }

 private:
  fs::path path_;
  std::optional<stop::RemovedOnStop> on_stop_;
};

// New parts' highlight: magenta, which few parts are (LeoCAD's yellow hid yellow parts' edges and
// tinted white and nougat parts yellow).
constexpr const char* kHighlight = "#FFFF00FF";

// LeoCAD renders the steps (new parts highlighted, earlier ones faded) and the finished model;
// returns which pictures exist, and a note when some do not.
struct Pictures {
  std::map<int, std::string> step;                          // step -> file name in the folder
  std::map<int, std::string> falls;                         // step -> its picture of what falls
  std::map<std::pair<std::string, int>, std::string> part;  // (part, colour) -> file name
  std::string cover;
  std::string note;
};

// LeoCAD's look for pictures that show one step's parts and nothing of the steps before.
constexpr const char* kNothingBefore = "--no-highlight --fade-steps --fade-steps-color '#00FFFFFF'";

// A part's picture beside a step's parts list.
constexpr int kPartWidth = 160, kPartHeight = 120;

// The kinds of part (part and colour) the steps place, in the order of the booklet's lists.
std::vector<std::pair<std::string, int>> part_kinds(const Booklet& booklet) {
  std::vector<std::pair<std::string, int>> kinds;
  for (const BookletStep& s : booklet.steps)
    for (const PartCount& p : s.parts) kinds.emplace_back(p.part, p.color);
  std::sort(kinds.begin(), kinds.end());
  kinds.erase(std::unique(kinds.begin(), kinds.end()), kinds.end());
  return kinds;
}

// An LDraw file for LeoCAD to draw: `model`, and the parts the model embeds after it, as an MPD
// (a renderer finds those parts nowhere else).
std::string with_embedded(const std::string& name, const std::string& model,
                          const std::string& embedded) {
  if (embedded.empty()) return model;
  return "0 FILE " + name + "\n" + model + "0 NOFILE\n" + embedded;
}

// Each kind of part alone, as printed instructions draw a step's parts: a file placing each at
// the origin in a step of its own, drawn by one LeoCAD run with the steps before faded to nothing
// and no edge lines (a faded part's edges would show across the part drawn). All are drawn at one
// scale, as printed instructions draw them: a 1 x 1 brick is smaller than a 2 x 4.
std::string parts_one_by_one(const std::vector<std::pair<std::string, int>>& kinds,
                             const std::string& embedded) {
  std::string out = "0 The booklet's parts\n0 Name: parts.ldr\n0 Author: legolization\n\n";
  for (const auto& [part, color] : kinds)
    out += ldraw::part_line(color, ldraw::Transform{}, part + ".dat") + "0 STEP\n";
  return with_embedded("parts.ldr", out, embedded);
}

// Why the booklet can have no pictures here (no LeoCAD, no display and no xvfb-run, too little
// room on the disk), or nothing.
std::optional<std::string> no_pictures(const fs::path& dir, const Booklet& booklet) {
  if (!have("leocad"))
    return "LeoCAD is not installed (Debian package leocad): the booklet has no pictures.";
  const bool display = std::getenv("DISPLAY") && *std::getenv("DISPLAY");
  if (!display && !have("xvfb-run"))
    return "LeoCAD needs a display and xvfb-run is not installed (Debian package xvfb): the "
           "booklet has no pictures.";
  // LeoCAD on a full disk waits for room until its time limit: no pictures are tried without room
  // for them.
  struct statvfs room {};
  const uintmax_t needed = (booklet.steps.size() + 1) * kPictureBytes;
  if (::statvfs(dir.c_str(), &room) == 0 && uintmax_t(room.f_bavail) * room.f_frsize < needed)
    return fmt::format(
        "The disk beside the booklet has {} MB free and its pictures need about {} MB: the booklet "
        "has no pictures.",
        uintmax_t(room.f_bavail) * room.f_frsize >> 20, (needed >> 20) + 1);
  return std::nullopt;
}

// LeoCAD's pictures in `scratch` moved into `dir` under the booklet's names (step-NNN.png by the
// booklet's step number, part-NNN.png, falls-NNN.png) and listed in `out`. `last`: LeoCAD's last
// step, which a run of one step renders without a number.
void collect_pictures(const fs::path& scratch, const fs::path& dir, const Booklet& booklet,
                      const std::vector<std::pair<std::string, int>>& kinds, int last,
                      Pictures& out) {
  auto number_of = [&](int leocad_step) {
    return leocad_step >= 1 && leocad_step <= int(booklet.steps.size())
               ? booklet.steps[size_t(leocad_step - 1)].number
               : 0;
  };
  std::error_code ec;
  // Which picture of a LeoCAD run `name` is: its number, or 0 for `single` (a run of one step
  // renders to the name given, of several to the name with the step's number).
  static const std::regex step_numbered(R"(step(\d+)\.png)"), part_numbered(R"(part(\d+)\.png)"),
      falls_numbered(R"(falls(\d+)\.png)");
  auto rendered = [](const std::string& name, const std::regex& numbered,
                     const char* single) -> std::optional<int> {
    std::smatch m;
    if (std::regex_match(name, m, numbered)) return std::stoi(m[1]);
    if (name == single) return 0;
    return std::nullopt;
  };
  for (const auto& e : fs::directory_iterator(scratch)) {
    const std::string name = e.path().filename().string();
    if (const auto k = rendered(name, part_numbered, "part.png")) {
      const size_t index = *k == 0 ? 0 : size_t(*k) - 1;
      if (index >= kinds.size()) continue;
      const std::string target = fmt::format("part-{:03}.png", index + 1);
      fs::rename(e.path(), dir / target, ec);
      if (!ec) out.part[kinds[index]] = target;
    } else if (const auto k = rendered(name, falls_numbered, "falls.png")) {
      const size_t index = *k == 0 ? 0 : size_t(*k) - 1;
      if (index >= booklet.falls_steps.size()) continue;
      const int step = booklet.falls_steps[index];
      const std::string target = fmt::format("falls-{:03}.png", step);
      fs::rename(e.path(), dir / target, ec);
      if (!ec) out.falls[step] = target;
    } else if (const auto n = rendered(name, step_numbered, "step.png")) {
      const int step = number_of(*n == 0 ? last : *n);
      if (step <= 0) continue;
      const std::string target = fmt::format("step-{:03}.png", step);
      fs::rename(e.path(), dir / target, ec);
      if (!ec) out.step[step] = target;
    }
  }
}

Pictures render(const fs::path& dir, const Booklet& booklet, const fs::path& library,
                const BookletProgress& progress) {
  Pictures out;
  if (auto why = no_pictures(dir, booklet)) {
    out.note = *why;
    return out;
  }
  const bool display = std::getenv("DISPLAY") && *std::getenv("DISPLAY");
  const fs::path scratch = dir / ".render";
  std::error_code ec;
  fs::remove_all(scratch, ec);
  fs::create_directories(scratch);
  // The booklet's own steps: LeoCAD's step k is the booklet's k-th.
  const fs::path shown = scratch / "steps.ldr";
  ldraw::write_file_atomically(shown, with_embedded("steps.ldr", booklet.drawn, booklet.embedded));
  const int last = std::max<int>(1, int(booklet.steps.size()));
  // Steps: the booklet's steps, new parts highlighted; Whole: the cover; Alone: each step's
  // parts without what came before; Falls: each picture of what falls, as drawn.
  enum class Look { Steps, Whole, Alone, Falls };
  auto leocad = [&](const fs::path& file, const std::string& image, int from, int to, Look look) {
    const bool alone = look == Look::Alone;
    // The steps and what falls are seen by the booklet's camera, each framed; the cover by its
    // own; the parts from the cover's direction, whole.
    const std::string camera = look == Look::Steps || look == Look::Falls
                                   ? fmt::format("-c {}", kStepCamera)
                               : look == Look::Whole ? fmt::format("-c {}", kCoverCamera)
                                                     : std::string("--camera-angles 30 45");
    const std::string command = fmt::format(
        "{}leocad -l {} -i {} -w {} -h {} -f {} -t {} {} {} {} >{} 2>&1",
        display ? "" : "xvfb-run -a ", shell_quote(library.string()),
        shell_quote((scratch / image).string()), alone ? kPartWidth : kWidth,
        alone ? kPartHeight : kHeight, from, to, camera,
        look == Look::Steps
            ? fmt::format("--highlight --highlight-color {} --fade-steps", shell_quote(kHighlight))
        : alone               ? kNothingBefore + std::string(" --line-width 0")
        : look == Look::Falls ? std::string(kNothingBefore)
                              : std::string("--no-highlight --no-fade-steps"),
        shell_quote(fs::absolute(file).string()), shell_quote((scratch / "leocad.log").string()));
    // A renderer that hangs (no X server after all) must not hang the tool.
    return stop::run_command(command, kRenderSeconds) == 0;
  };
  if (progress) progress(fmt::format("rendering {} steps with LeoCAD", booklet.steps.size()));
  const bool steps_ok = leocad(shown, "step.png", 1, last, Look::Steps);
  if (progress) progress("rendering the cover");
  const bool cover_ok = leocad(shown, "cover.png", last, last, Look::Whole);
  if (!booklet.falls_steps.empty()) {
    if (progress)
      progress(fmt::format("rendering what falls in {} steps", booklet.falls_steps.size()));
    ldraw::write_file_atomically(scratch / "falls.ldr",
                                 with_embedded("falls.ldr", booklet.falls, booklet.embedded));
    leocad(scratch / "falls.ldr", "falls.png", 1, int(booklet.falls_steps.size()), Look::Falls);
  }
  const auto kinds = part_kinds(booklet);
  if (!kinds.empty()) {
    if (progress) progress(fmt::format("rendering {} kinds of part", kinds.size()));
    ldraw::write_file_atomically(scratch / "parts.ldr", parts_one_by_one(kinds, booklet.embedded));
    leocad(scratch / "parts.ldr", "part.png", 1, int(kinds.size()), Look::Alone);
  }
  collect_pictures(scratch, dir, booklet, kinds, last, out);
  if (cover_ok && fs::exists(scratch / "cover.png")) {
    fs::rename(scratch / "cover.png", dir / "cover.png", ec);
    if (!ec) out.cover = "cover.png";
  }
  int missing = 0;
  for (const BookletStep& s : booklet.steps) missing += !out.step.count(s.number);
  missing += int(kinds.size() - out.part.size()) + (out.cover.empty() ? 1 : 0);
  missing += int(booklet.falls_steps.size() - out.falls.size());
  if (missing > 0)
    out.note = fmt::format("LeoCAD did not render {} of {} pictures{}.", missing,
                           booklet.steps.size() + 1 + kinds.size() + booklet.falls_steps.size(),
                           steps_ok ? "" : " (it failed)");
  fs::remove_all(scratch, ec);
  return out;
}

// LDraw names colours with underscores ("Dark_Bluish_Grey"); a person reads spaces.
std::string colour_name(const ldraw::ColorTable& colors, int color) {
  std::string name = colors.name(color);
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

std::string swatch(const ldraw::ColorTable& colors, int color) {
  const auto rgb = colors.rgb(color);
  return fmt::format(R"(<span class="swatch" style="background:#{:06x}"></span>)",
                     rgb ? *rgb : 0xA0A5A9u);
}

std::string parts_table(const std::vector<PartCount>& parts, const ldraw::ColorTable& colors) {
  std::string out =
      "<table class=\"parts\"><tr><th>count</th><th>colour</th><th>part</th><th>name</th></tr>\n";
  for (const PartCount& p : parts)
    out += fmt::format(
        "<tr><td class=\"count\">{}&times;</td><td>{} {}</td><td>{}</td><td>{}</td></tr>\n",
        p.quantity, swatch(colors, p.color), html_escape(colour_name(colors, p.color)),
        html_escape(p.part), html_escape(p.name));
  return out + "</table>\n";
}

std::string cm_text(const std::optional<double>& cm) {
  return cm ? fmt::format("{:.3f} gf", *cm) : std::string("no equilibrium");
}

// The printable booklet beside index.html.
constexpr const char* kPdf = "instructions.pdf";
constexpr int kPrintSeconds = 600;

std::string html(const Booklet& b, const Pictures& pictures, bool pdf) {
  int total = 0;
  for (const PartCount& p : b.parts) total += p.quantity;
  std::string out = fmt::format(R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
{}
<title>{} — building instructions</title>
<style>
body {{ font-family: sans-serif; margin: 0; background: #eee; color: #222; }}
section {{ background: #fff; margin: 1em auto; padding: 1em 2em; max-width: 900px;
  page-break-after: always; break-after: page; }}
h1, h2 {{ margin: 0.2em 0; }}
@page {{ size: A4; margin: 12mm; }}
@media print {{ body {{ background: #fff; font-size: 10pt; }} section {{ margin: 0; padding: 0; }}
  section:last-of-type {{ break-after: auto; page-break-after: auto; }}
  img.picture {{ width: auto; max-height: 95mm; }} .callout img {{ width: auto; height: 20mm; }}
  .callout figure, table.parts {{ font-size: 8pt; }} .print {{ display: none; }} }}
img {{ display: block; max-width: 100%; margin: 0.5em auto; }}
.note {{ background: #fff3c4; padding: 0.5em 1em; }}
.swatch {{ display: inline-block; width: 1em; height: 1em; border: 1px solid #666;
  vertical-align: middle; }}
.callout {{ display: flex; flex-wrap: wrap; gap: 0.5em; }}
.callout figure {{ margin: 0; text-align: center; font-weight: bold; }}
.callout img {{ margin: 0; }}
table.parts {{ border-collapse: collapse; }}
table.parts td, table.parts th {{ padding: 0.15em 0.6em; text-align: left; }}
td.count {{ font-weight: bold; text-align: right; }}
.cm {{ color: #555; }} .falls {{ color: #b00; font-weight: bold; }}
</style></head>
<body>
<section class="cover" id="cover">
<h1>{}</h1>
<p>Building instructions for {}: {} steps, {} parts.</p>
)",
                                kGenerator, html_escape(b.title), html_escape(b.title),
                                html_escape(b.source), b.steps.size(), total);
  if (pdf) out += fmt::format("<p class=\"print\">To print: <a href=\"{0}\">{0}</a>.</p>\n", kPdf);
  if (!pictures.note.empty())
    out += fmt::format("<p class=\"note\">{}</p>\n", html_escape(pictures.note));
  if (!pictures.cover.empty())
    out += fmt::format(
        "<img class=\"picture\" src=\"{}\" alt=\"the finished model\" width=\"{}\" "
        "height=\"{}\">\n",
        pictures.cover, kWidth, kHeight);
  if (!b.verdict.empty()) out += fmt::format("<p>{}</p>\n", html_escape(b.verdict));
  out += "<h2>Parts</h2>\n" + parts_table(b.parts, b.colors) + "</section>\n";
  for (const BookletStep& s : b.steps) {
    out += fmt::format(
        "<section class=\"step{2}\" id=\"step-{0}\" data-step=\"{0}\">\n<h2>Step {0} "
        "<small>of {1}{3}</small></h2>\n",
        s.number, b.steps.back().number, s.aside ? " aside" : "", s.aside ? ", built aside" : "");
    if (auto it = pictures.step.find(s.number); it != pictures.step.end())
      out += fmt::format(
          "<img class=\"picture\" src=\"{}\" alt=\"the model after step {}, new "
          "parts highlighted\" width=\"{}\" height=\"{}\">\n",
          it->second, s.number, kWidth, kHeight);
    std::string callout;
    for (const PartCount& p : s.parts)
      if (auto it = pictures.part.find({p.part, p.color}); it != pictures.part.end())
        callout += fmt::format(
            "<figure><img src=\"{}\" alt=\"{}\" width=\"{}\" height=\"{}\">"
            "<figcaption>{}&times;</figcaption></figure>\n",
            it->second, html_escape(p.name), kPartWidth, kPartHeight, p.quantity);
    if (!callout.empty()) out += "<div class=\"callout\">\n" + callout + "</div>\n";
    out += parts_table(s.parts, b.colors);
    if (!s.note.empty()) out += fmt::format("<p class=\"note\">{}</p>\n", html_escape(s.note));
    if (s.stands && (!s.aside || s.sub_assembly_judged)) {
      const char* judged = s.aside                 ? "The sub-assembly so far, on the table"
                           : s.sub_assembly_judged ? "The model so far, on the table"
                                                   : "The model so far";
      // What floats has no C_M: the number would be that of the rest, which stands.
      out += s.floats ? fmt::format(
                            "<p class=\"cm\">{}: it does not stand, part of it reaches "
                            "no ground.</p>\n",
                            judged)
                      : fmt::format("<p class=\"cm\">{}: C_M {} {} ({}).</p>\n", judged,
                                    s.certified ? "&ge;" : "=", cm_text(s.cm_gf),
                                    *s.stands ? "it stands" : "it does not stand");
      if (!*s.stands && !s.why.empty())
        out += fmt::format("<p class=\"falls\">Hold it: {}</p>\n", html_escape(s.why));
      if (auto it = pictures.falls.find(s.number); it != pictures.falls.end())
        out += fmt::format(
            "<figure class=\"falls\"><img class=\"picture\" src=\"{}\" alt=\"what falls in "
            "step {}\" width=\"{}\" height=\"{}\"><figcaption>In red, what falls, tips or holds "
            "least; in clear, the {} so far.</figcaption></figure>\n",
            it->second, s.number, kWidth, kHeight, s.aside ? "sub-assembly" : "model");
    }
    out += "</section>\n";
  }
  // Once the page has loaded, it says how many pictures showed (for a reader's tools and tests:
  // a headless browser's DOM then tells).
  out += R"(<script>
window.addEventListener("load", () => {
  const shown = [...document.images].filter((i) => i.complete && i.naturalWidth > 0);
  document.body.dataset.pictures = document.images.length;
  document.body.dataset.picturesShown = shown.length;
});
</script>
)";
  return out + "</body></html>\n";
}

// Headless Chromium prints the booklet, a page per step (each section breaks the page), into
// kPdf beside it; returns a note when it could not.
std::string print_pdf(const fs::path& dir, const BookletProgress& progress) {
  if (!have("chromium"))
    return "Chromium is not installed (Debian package chromium): the booklet has no PDF.";
  if (progress) progress("printing the booklet with Chromium");
  const fs::path profile = dir / ".chromium";
  // Chromium as root runs only without its sandbox; a profile of its own keeps the user's.
  const std::string command = fmt::format(
      "chromium --headless --no-sandbox --disable-gpu --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir={} --no-pdf-header-footer --print-to-pdf-no-header --print-to-pdf={} {} "
      ">/dev/null 2>&1",
      shell_quote(profile.string()), shell_quote((dir / kPdf).string()),
      shell_quote("file://" + fs::absolute(dir / "index.html").string()));
  const bool printed = stop::run_command(command, kPrintSeconds) == 0;
  std::error_code ec;
  fs::remove_all(profile, ec);
  if (printed && fs::file_size(dir / kPdf, ec) > 0 && !ec) return {};
  fs::remove(dir / kPdf, ec);
  return "Chromium did not print the booklet: it has no PDF.";
}

}  // namespace

void check_booklet_folder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string(), 0, "--instructions: not a folder");
  if (fs::is_empty(dir, ec) || is_booklet(dir)) return;
  throw InputError(dir.string(), 0,
                   "--instructions: the folder holds other files; give an empty or new folder "
                   "(a booklet written there before is replaced)");
}

namespace {

// The model's part i where it is placed, by its body where `bodies` knows it (step_camera.h).
FrameBox box_of(const ldraw::Model& model, const std::vector<std::optional<Box>>& bodies,
                size_t i) {
  return part_box(model.parts[i], i < bodies.size() ? bodies[i] : std::nullopt);
}

// The sub-assemblies (by PlacedPart::apart_from) built where nothing is in place yet or built
// apart before them, whose parts are therefore drawn and built in place (a wrapper model that
// places one submodel with steps, a house begun with its ground floor): beside an empty model
// they would be a model built aside from nothing, and set in place on nothing.
std::set<int> built_in_place(const ldraw::Model& model) {
  std::map<int, int> placed_at;  // sub-assembly -> the step that places it
  for (const ldraw::PlacedPart& p : model.parts)
    if (p.built_in > 0) placed_at[p.apart_from] = p.step;
  std::set<int> out;
  for (const auto& [first, placing] : placed_at) {
    const bool alone =
        std::none_of(model.parts.begin(), model.parts.end(), [&](const ldraw::PlacedPart& q) {
          if (q.built_in > 0) return q.apart_from != first && q.built_in < first;
          return q.step < placing;
        });
    if (alone) out.insert(first);
  }
  return out;
}

// The parts flattened, a step of the file per step of the model (submodels' own steps; steps that
// place nothing are none), and the cameras that frame each step and the cover (step_camera.h). A
// sub-assembly built aside (ldraw::Model::aside) is drawn beside the model, clear of it, each of
// its steps framed on it; the finished model is framed without it.
std::string drawn_by_step(const ldraw::Model& model,
                          const std::vector<std::optional<Box>>& bodies) {
  struct Drawn {
    std::string lines;
    FrameBox box, aside;
  };
  std::map<int, Drawn> steps;
  FrameBox model_box, aside_box;
  // What is built apart: the parts a buffer sets aside, and those of sub-assemblies, drawn where
  // they are built.
  std::vector<std::pair<int, const ldraw::PlacedPart*>> apart;
  const std::set<int> in_place = built_in_place(model);
  for (size_t i = 0; i < model.parts.size(); ++i) {
    const ldraw::PlacedPart& p = model.parts[i];
    const bool here = p.built_in > 0 && in_place.count(p.apart_from);
    Drawn& d = steps[here ? p.built_in : p.step];
    d.lines += ldraw::part_line(p.color, p.transform, p.reference);
    d.box.add(box_of(model, bodies, i));
    model_box.add(d.box);
    if (p.built_in > 0 && !here) apart.emplace_back(p.built_in, &p);
  }
  for (const ldraw::PlacedPart& p : model.aside) apart.emplace_back(p.step, &p);
  for (const auto& [step, p] : apart) aside_box.add(part_box(*p));
  // Along x, past the model by four studs.
  const double shift = aside_box.empty() ? 0 : model_box.max[0] - aside_box.min[0] + 80;
  for (const auto& [step, part] : apart) {
    ldraw::PlacedPart p = *part;
    p.transform.pos[0] += shift;
    Drawn& d = steps[step];
    d.lines += ldraw::part_line(p.color, p.transform, p.reference);
    d.aside.add(part_box(p));
  }
  std::string out = "0 The booklet's steps\n0 Name: steps.ldr\n0 Author: legolization\n\n";
  std::vector<Frame> frames;
  FrameBox so_far, aside_so_far;  // the model in place; the sub-assembly being built aside
  for (auto& [step, d] : steps) {
    out += d.lines + "0 STEP\n";
    if (!d.aside.empty() && d.box.empty()) {
      aside_so_far.add(d.aside);
      frames.push_back(frame_step(d.aside, aside_so_far));
      continue;
    }
    aside_so_far = {};
    so_far.add(d.box);
    so_far.add(d.aside);
    frames.push_back(frame_step(d.box, so_far));
  }
  return out + step_camera(frames) + camera_lines(kCoverCamera, {frame_step(model_box, model_box)});
}

// What falls is drawn in red, what stands around it in clear, through which a part inside shows.
constexpr int kFallingColor = 4;  // Red
constexpr int kAroundColor = 47;  // Trans_Clear
// Each picture of what falls draws the whole model so far: the first this many steps that fall
// have one (a town's booklet would otherwise draw the town once per step), the builder's first.
constexpr size_t kFallsPictures = 20;

}  // namespace

void draw_what_falls(Booklet& booklet, const ldraw::Model& model,
                     const std::vector<std::optional<Box>>& bodies) {
  booklet.falls.clear();
  booklet.falls_steps.clear();
  std::string out = "0 What falls\n0 Name: falls.ldr\n0 Author: legolization\n\n";
  std::vector<Frame> frames;
  std::vector<char> falls(model.parts.size(), 0);
  for (const BookletStep& s : booklet.steps) {
    if (s.falling.empty()) continue;
    if (booklet.falls_steps.size() == kFallsPictures) break;
    std::fill(falls.begin(), falls.end(), 0);
    for (size_t i : s.falling)
      if (i < falls.size()) falls[i] = 1;
    // A step judged on the table shows its sub-assembly so far; any other, the model in place.
    int apart = 0;
    if (s.sub_assembly_judged)
      for (const ldraw::PlacedPart& p : model.parts)
        if (p.built_in == s.number) apart = p.apart_from;
    FrameBox around;
    bool any = false;
    std::string lines;
    for (size_t i = 0; i < model.parts.size(); ++i) {
      const ldraw::PlacedPart& p = model.parts[i];
      const bool there = apart > 0
                             ? p.apart_from == apart && p.built_in > 0 && p.built_in <= s.number
                             : p.step <= s.number;
      if (!there && !falls[i]) continue;
      lines += ldraw::part_line(falls[i] ? kFallingColor : kAroundColor, p.transform, p.reference);
      around.add(box_of(model, bodies, i));
      any = any || falls[i];
    }
    if (!any) continue;
    out += lines + "0 STEP\n";
    // The whole of it: where on the model the red parts are is what the builder looks for, and
    // red shows through clear however small.
    frames.push_back(frame_step(around, around));
    booklet.falls_steps.push_back(s.number);
  }
  if (!booklet.falls_steps.empty()) booklet.falls = out + step_camera(frames);
}

Booklet booklet_of(const ldraw::Model& model, const std::vector<std::optional<Box>>& bodies) {
  Booklet b;
  b.title = model.title.empty() ? model.source : model.title;
  b.source = fs::path(model.source).filename().string();
  b.colors = model.color_table;
  std::map<std::string, std::string> names;
  std::map<int, std::map<std::pair<std::string, int>, PartCount>> by_step;
  std::map<std::pair<std::string, int>, PartCount> all;
  std::map<int, int> set_in_place, aside;  // per step
  auto count = [&](const ldraw::PlacedPart& p, int step) {
    auto [name, fresh] = names.try_emplace(p.part);
    if (fresh) name->second = part_name(p);
    for (auto* counts : {&by_step[step], &all}) {
      PartCount& c = (*counts)[{p.part, p.color}];
      c.part = p.part;
      c.color = p.color;
      c.name = name->second;
      ++c.quantity;
    }
  };
  // A part built apart is listed where it is built; where it is set in place (a sub-assembly
  // placed whole, or its ghost) the step shows it, and lists it not. A sub-assembly built in place
  // (built_in_place) is a part of the model from its steps on, set in place by no step.
  const std::set<int> in_place = built_in_place(model);
  for (const ldraw::PlacedPart& p : model.parts) {
    if (p.built_in > 0 && in_place.count(p.apart_from)) {
      count(p, p.built_in);
      continue;
    }
    if (p.ghost || p.built_in > 0) {
      by_step[p.step];
      ++set_in_place[p.step];
    } else {
      count(p, p.step);
    }
    if (p.built_in > 0 && !p.ghost) {
      count(p, p.built_in);
      ++aside[p.built_in];
    }
  }
  for (const ldraw::PlacedPart& p : model.aside) {
    count(p, p.step);
    ++aside[p.step];
  }
  for (auto& [step, counts] : by_step) {
    BookletStep s;
    s.number = step;
    s.parts = sorted(std::move(counts));
    s.aside = aside.count(step) > 0;
    if (s.aside)
      s.note =
          "Built aside: this sub-assembly is built apart from the model and set in place in "
          "a later step.";
    else if (set_in_place.count(step))
      s.note = "Set in place what was built aside.";
    b.steps.push_back(std::move(s));
  }
  b.parts = sorted(std::move(all));
  b.drawn = drawn_by_step(model, bodies);
  for (const auto& [name, text] : model.embedded_parts)
    b.embedded += text + (text.ends_with('\n') ? "" : "\n") + "0 NOFILE\n";
  return b;
}

std::string write_booklet(const fs::path& dir, const Booklet& booklet, const fs::path& library,
                          const BookletProgress& progress) {
  check_booklet_folder(dir);
  NewFolder made(dir);
  Pictures pictures = render(made.path(), booklet, library, progress);
  ldraw::write_file_atomically(made.path() / "index.html", html(booklet, pictures, true));
  if (const std::string unprinted = print_pdf(made.path(), progress); !unprinted.empty()) {
    pictures.note += (pictures.note.empty() ? "" : " ") + unprinted;
    ldraw::write_file_atomically(made.path() / "index.html", html(booklet, pictures, false));
  }
  const std::string moved = made.publish(dir);
  if (progress) progress(fmt::format("wrote {}", (dir / "index.html").string()));
  if (!moved.empty()) return pictures.note.empty() ? moved : pictures.note + " " + moved;
  return pictures.note;
}

}  // namespace lego::report
