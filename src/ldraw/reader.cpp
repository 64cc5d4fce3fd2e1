#include "ldraw/reader.h"

#include "core/brick_catalog.h"
#include "core/case_insensitive_paths.h"
#include "core/error.h"
#include "core/text.h"
#include "ldraw/tokens.h"

#include <fmt/format.h>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <system_error>
#include <unordered_map>
#include <variant>

namespace lego::ldraw {
namespace fs = std::filesystem;

std::string Diagnostic::text() const {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  return fmt::format("{}: {}: {}", where, severity == Severity::Error ? "error" : "warning",
                     message);
}

bool Model::has_errors() const {
  return std::any_of(diagnostics.begin(), diagnostics.end(),
                     [](const Diagnostic& d) { return d.severity == Severity::Error; });
}

std::vector<fs::path> library_dirs_from_env() {
  if (const char* env = std::getenv("LDRAWDIR"); env && *env) return {fs::path(env)};
  return {};
}

namespace {

// Coordinates beyond this (LDU, about 40 km) are taken as corrupt input, not a model.
constexpr double kAbsurdCoordinate = 1e6;

std::optional<double> parse_number(std::string_view token) {
  if (token.starts_with("+")) token.remove_prefix(1);
  double value = 0;
  auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || p != token.data() + token.size()) return std::nullopt;
  return value;
}

// Whether an `0 !LDRAW_ORG` value marks a part file (Part, Subpart, Primitive, Shortcut and
// their Unofficial_ forms) rather than a model: parts are leaves, models are flattened.
bool names_a_part(std::string_view ldraw_org) {
  const std::string org = ascii_lower(ldraw_org);
  for (const char* kind : {"part", "primitive", "shortcut"})  // "part" also matches Subpart
    if (org.find(kind) != std::string::npos) return true;
  return false;
}

struct RefLine {
  int line = 0;
  int color = kMainColor;
  Transform transform;
  std::string name;
  bool ghost = false;  // written `0 GHOST 1 ...`: drawn, not in the parts list
};
struct StepMark {
  int line = 0;
  std::string rotstep;
};
// `0 BUFEXCHG A STORE` / `RETRIEVE` (MLCad): what is shown is kept in, or taken back from, a
// buffer A to Z.
struct BufferMark {
  int line = 0;
  char buffer = 'A';
  bool store = true;
};
using Entry = std::variant<RefLine, StepMark, BufferMark>;

struct Block {
  std::string name;  // FILE name as written; the file name for a plain .ldr
  int first_line = 1;
  std::string title, name_meta, author, ldraw_org;
  bool seen_line = false;  // any line after the FILE line (for the title rule)
  int drawn_lines = 0;     // type 2-5 lines: edges, triangles, quads
  std::vector<Entry> entries;
  size_t text_begin = 0, text_end = 0;

  bool is_part() const { return names_a_part(ldraw_org); }
};

struct Document {
  std::string file;  // for diagnostics
  fs::path dir;      // for resolving relative references
  std::string text;
  std::vector<Block> blocks;
  std::unordered_map<std::string, size_t> by_name;
  const Block* find(std::string_view name) const {
    auto it = by_name.find(normalize_reference(name));
    return it == by_name.end() ? nullptr : &blocks[it->second];
  }
};

class Parser {
 public:
  Parser(Document& doc, std::vector<Diagnostic>& diags, std::vector<Color>& colors)
      : doc_(doc), diags_(diags), colors_(colors) {}

  void parse() {
    std::string_view text = doc_.text;
    if (auto nul = text.find('\0'); nul != std::string_view::npos) {
      error(0, fmt::format("not a text file (NUL byte at offset {})", nul));
      return;
    }
    size_t pos = 0;
    if (text.starts_with("\xEF\xBB\xBF")) pos = 3;
    doc_.blocks.push_back(Block{});
    doc_.blocks.back().name = fs::path(doc_.file).filename().string();
    int line_no = 0;
    // Lines end at LF, CR LF or a bare CR (old Mac files): a CR never reaches a name.
    while (pos <= text.size()) {
      size_t end = text.find_first_of("\r\n", pos);
      if (end == std::string_view::npos) end = text.size();
      std::string_view line = text.substr(pos, end - pos);
      ++line_no;
      parse_line(line, line_no, pos);
      if (end == text.size()) break;
      pos = end + (text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n' ? 2 : 1);
    }
    close_block(text.size());
    for (size_t i = 0; i < doc_.blocks.size(); ++i) {
      auto key = normalize_reference(doc_.blocks[i].name);
      if (!doc_.by_name.emplace(key, i).second && i > 0)
        warn(doc_.blocks[i].first_line,
             fmt::format("a second FILE block named '{}' is ignored", doc_.blocks[i].name));
    }
  }

 private:
  Document& doc_;
  std::vector<Diagnostic>& diags_;
  std::vector<Color>& colors_;
  bool implicit_ = true;  // the current block is the text before any FILE line
  bool in_block_ = true;  // false between NOFILE and the next FILE
  bool has_geometry_front_ = false;

  Block& block() { return doc_.blocks.back(); }
  void error(int line, std::string msg) {
    diags_.push_back({Severity::Error, doc_.file, line, std::move(msg)});
  }
  void warn(int line, std::string msg) {
    diags_.push_back({Severity::Warning, doc_.file, line, std::move(msg)});
  }
  void close_block(size_t at) {
    if (!doc_.blocks.empty() && doc_.blocks.back().text_end == 0) doc_.blocks.back().text_end = at;
  }

  void parse_line(std::string_view raw, int line_no, size_t offset) {
    std::string_view rest = trim(raw);
    if (rest.empty()) return;
    std::string_view type = next_token(rest);
    if (type == "0") return parse_meta(trim(rest), line_no, offset);
    if (!in_block_) {
      warn(line_no, "line outside any FILE block (after 0 NOFILE) is ignored");
      return;
    }
    block().seen_line = true;
    if (implicit_ && type != "0") has_geometry_front_ = true;
    if (type == "1") return parse_reference(rest, line_no);
    if (type == "2" || type == "3" || type == "4" || type == "5") {
      ++block().drawn_lines;
      size_t numbers = type == "2" ? 6 : type == "3" ? 9 : 12;
      std::string_view color = next_token(rest);
      if (!parse_color_code(color))
        return warn(line_no, fmt::format("bad colour '{}' on a type-{} line", color, type));
      for (size_t i = 0; i < numbers; ++i) {
        auto token = next_token(rest);
        auto v = parse_number(token);
        if (!v || !std::isfinite(*v))
          return warn(line_no, fmt::format("malformed type-{} line: expected {} coordinates", type,
                                           numbers));
      }
      if (!trim(rest).empty()) warn(line_no, fmt::format("extra text after a type-{} line", type));
      return;
    }
    warn(line_no, fmt::format("unknown line type '{}' is ignored", type));
  }

  void parse_meta(std::string_view meta, int line_no, size_t offset) {
    std::string_view rest = meta;
    std::string_view word = next_token(rest);
    rest = trim(rest);
    if (word == "FILE") {
      if (rest.empty()) return warn(line_no, "0 FILE without a name is ignored");
      close_block(offset);
      if (implicit_ && doc_.blocks.size() == 1 && doc_.blocks.front().entries.empty() &&
          !has_geometry_front_) {
        doc_.blocks.clear();  // the text before the first FILE held no model
      }
      implicit_ = false;
      in_block_ = true;
      Block b;
      b.name = std::string(rest);
      b.first_line = line_no;
      b.text_begin = offset;
      doc_.blocks.push_back(std::move(b));
      return;
    }
    if (word == "NOFILE") {
      close_block(offset);
      in_block_ = false;
      return;
    }
    if (!in_block_) return;
    Block& b = block();
    bool first = !b.seen_line;
    b.seen_line = true;
    if (word == "STEP") {
      b.entries.push_back(StepMark{line_no, {}});
    } else if (word == "ROTSTEP") {
      std::string_view args = rest;
      std::string_view a = next_token(args);
      bool ok = a == "END";
      if (!ok) {
        auto y = next_token(args), z = next_token(args);
        auto mode = trim(args);
        ok = parse_number(a) && parse_number(y) && parse_number(z) &&
             (mode.empty() || mode == "REL" || mode == "ADD" || mode == "ABS");
      }
      if (!ok) warn(line_no, fmt::format("malformed ROTSTEP '{}' (taken as a plain STEP)", rest));
      b.entries.push_back(StepMark{line_no, ok ? std::string(rest) : std::string()});
    } else if (word == "GHOST") {
      std::string_view line = rest;
      if (next_token(line) == "1") parse_reference(line, line_no, /*ghost=*/true);
    } else if (word == "BUFEXCHG") {
      std::string_view args = rest;
      const std::string_view buffer = next_token(args);
      const std::string action = ascii_lower(trim(args));
      const bool letter = buffer.size() == 1 && std::isalpha(static_cast<unsigned char>(buffer[0]));
      if (!letter || (action != "store" && action != "retrieve"))
        warn(line_no, fmt::format("malformed BUFEXCHG '{}' is ignored", rest));
      else
        b.entries.push_back(BufferMark{
            line_no, char(std::toupper(static_cast<unsigned char>(buffer[0]))), action == "store"});
    } else if (word == "Name:") {
      b.name_meta = std::string(rest);
    } else if (word == "Author:") {
      b.author = std::string(rest);
    } else if (word == "!LDRAW_ORG") {
      b.ldraw_org = std::string(rest);
    } else if (word == "!COLOUR") {
      ColorTable table;
      if (table.add_definition(meta))
        colors_.push_back(table.colors().begin()->second);
      else
        warn(line_no, "malformed !COLOUR definition is ignored");
    } else if (first && b.title.empty() && !word.starts_with("!") && word != "//" &&
               word != "BFC" && word != "Name:" && word != "Author:") {
      b.title = std::string(meta);
    }
  }

  void parse_reference(std::string_view rest, int line_no, bool ghost = false) {
    std::string_view color_token = next_token(rest);
    auto color = parse_color_code(color_token);
    if (!color) {  // LDraw viewers draw the part anyway: so do we, in the colour it inherits
      warn(line_no, fmt::format("unknown colour '{}' (taken as 16, the colour it inherits)",
                                color_token.size() > 40 ? color_token.substr(0, 40) : color_token));
      color = kMainColor;
    }
    double v[12];
    for (double& x : v) {
      std::string_view token = next_token(rest);
      auto number = parse_number(token);
      if (!number) {
        return error(line_no,
                     token.empty()
                         ? std::string("malformed type-1 line: expected 12 numbers and a file name")
                         : fmt::format("malformed type-1 line: '{}' is not a number", token));
      }
      if (!std::isfinite(*number) || std::abs(*number) > kAbsurdCoordinate)
        return error(line_no, fmt::format("absurd number {} on a type-1 line", token));
      x = *number;
    }
    std::string_view name = trim(rest);
    if (name.empty()) return error(line_no, "malformed type-1 line: no file name");
    RefLine ref;
    ref.line = line_no;
    ref.color = *color;
    ref.transform.pos = {v[0], v[1], v[2]};
    std::copy(v + 3, v + 12, ref.transform.rot.begin());
    ref.name = std::string(name);
    ref.ghost = ghost;
    block().entries.push_back(std::move(ref));
  }
};

// Finds `relative` under `dir`, matching each path component case-insensitively.
// A referenced file under `dir`, in any case, when it is a regular file.
class CaseInsensitiveFinder {
 public:
  std::optional<fs::path> find(const fs::path& dir, std::string_view relative) {
    auto found = paths_.locate(dir, normalize_reference(relative));
    std::error_code ec;
    if (!found || !fs::is_regular_file(*found, ec)) return std::nullopt;
    return found;
  }

 private:
  CaseInsensitivePaths paths_;
};

// The largest Datsville model is a few MB; a file of this size is not a model anyone builds.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(512) << 20;

std::optional<std::string> read_bytes(const fs::path& path, std::string& error) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    error = "is a directory, not an LDraw file";
    return std::nullopt;
  }
  // A device would be read until it ends, /dev/zero never; a pipe (`<(git show ...)`, /dev/stdin)
  // is read, but no further than a file may be long.
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_character_file(status) || fs::is_block_file(status) || fs::is_socket(status)) {
    error = "is a device, not an LDraw file";
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot open file";
    return std::nullopt;
  }
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, size_t(in.gcount()));
    if (text.size() > kMaxFileBytes) {
      error = fmt::format("is more than the {} MB an LDraw file may be", kMaxFileBytes >> 20);
      return std::nullopt;
    }
  }
  if (in.bad()) {
    error = "cannot read file";
    return std::nullopt;
  }
  return text;
}

class Flattener {
 public:
  Flattener(const ReadOptions& options, Model& model) : options_(options), model_(model) {
    colors_ = ColorTable::standard();
    // The library's colour table names what ours does not (the transparent and speckled ones).
    for (const auto& dir : options_.library_dirs) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(dir / "LDConfig.ldr", ec)) continue;
      try {
        colors_.add_missing(ColorTable::load(dir / "LDConfig.ldr"));
      } catch (const lego::InputError&) {
      }
    }
  }

  void run(std::unique_ptr<Document> root) {
    for (const auto& c : model_.colors) {
      colors_.add_definition(fmt::format("!COLOUR {} CODE {} VALUE #{:06X} EDGE #{:06X}", c.name,
                                         c.code, c.rgb, c.edge_rgb));
    }
    model_.color_table = colors_;
    const Document& doc = *root;
    documents_.push_back(std::move(root));
    if (doc.blocks.empty()) return;
    const Block* main = &doc.blocks.front();
    if (options_.main_model) {
      main = doc.find(*options_.main_model);
      if (!main) {
        model_.diagnostics.push_back(
            {Severity::Error, doc.file, 0,
             fmt::format("no model named '{}' in the file", *options_.main_model)});
        return;
      }
    } else {
      check_main_model(doc);
    }
    register_embedded_parts(doc);
    model_.title = main->title;
    model_.name = main->name_meta;
    model_.author = main->author;
    model_.ldraw_org = main->ldraw_org;
    model_.main_block = main->name;
    stack_.push_back(main);
    for (const Entry& entry : main->entries) {
      if (const auto* mark = std::get_if<StepMark>(&entry)) {
        // A step that places nothing (a leading ROTSTEP, two STEPs in a row) is no step a builder
        // takes: it is not counted, as LPub3D's instructions do not.
        if (parts_in_step() > 0) end_step(mark->rotstep);
        continue;
      }
      if (const auto* mark = std::get_if<BufferMark>(&entry)) {
        exchange(*mark);
        continue;
      }
      expand(doc, std::get<RefLine>(entry), Transform{}, kMainColor, "");
    }
    if (parts_in_step() > 0 || model_.steps.empty()) end_step({});
    set_aside_what_is_not_shown();
    count_steps();
  }

 private:
  const ReadOptions& options_;
  Model& model_;
  ColorTable colors_;
  std::vector<std::unique_ptr<Document>> documents_;
  std::map<fs::path, const Document*> external_;
  std::vector<const Block*> stack_;
  int inside_ = -1;     // the placement being expanded (Model::placements), -1: the main model
  bool ghost_ = false;  // expanding a GHOST line: its parts are ghosts
  CaseInsensitiveFinder finder_;
  bool budget_exceeded_ = false;
  // Building steps: the main model's, and a submodel's own where it is first placed, before the
  // step that places it (building_apart_); only those that place a part.
  int step_ = 1;
  size_t step_start_ = 0;  // parts placed before the current step
  std::set<const Block*> placed_;
  std::map<const Block*, bool> part_blocks_;

  // MLCad's buffers (BUFEXCHG), in the main model: which parts are shown, and what each buffer
  // holds, once the file exchanges one (before that, every part is shown).
  bool buffered_ = false;
  std::vector<char> shown_;
  std::map<char, std::vector<char>> buffers_;
  // What each view (begun by an exchange) shows of the parts placed before it, and per step
  // ended: its number, its view (-1: before any exchange) and the parts placed by its end. The
  // views are kept up to kViewBytes; past that, sub-assemblies built aside are not followed.
  static constexpr size_t kViewBytes = size_t(64) << 20;
  std::vector<std::vector<char>> views_;
  size_t view_bytes_ = 0;
  bool views_lost_ = false;
  struct StepEnd {
    int step = 0, view = -1;
    size_t parts = 0;
  };
  std::vector<StepEnd> step_ends_;

  void exchange(const BufferMark& mark) {
    buffered_ = true;
    shown_.resize(model_.parts.size(), 1);  // what was placed since is shown
    if (mark.store) {
      buffers_[mark.buffer] = shown_;
    } else {
      // A buffer never stored holds nothing: "retrieve an empty buffer" shows a sub-assembly alone.
      auto it = buffers_.find(mark.buffer);
      shown_ = it == buffers_.end() ? std::vector<char>() : it->second;
      shown_.resize(model_.parts.size(), 0);
    }
    view_bytes_ += shown_.size();
    views_lost_ = views_lost_ || view_bytes_ > kViewBytes;
    if (!views_lost_) views_.push_back(shown_);
  }

  // Whether part `i` (placed by `end.parts`) is shown at the end of that step.
  bool shown_at(const StepEnd& end, size_t i) const {
    if (i >= end.parts) return false;
    if (end.view < 0) return true;
    const std::vector<char>& view = views_[size_t(end.view)];
    return i >= view.size() || view[i];  // placed in the view: shown
  }

  // The finished model is what is shown at its end: parts placed while a buffer showed something
  // else, and not shown since (a sub-assembly built aside, put in place by GHOST lines), are set
  // aside (Model::aside); a ghost not shown at the end is nothing.
  void set_aside_what_is_not_shown() {
    if (!buffered_) return;
    shown_.resize(model_.parts.size(), 1);
    std::vector<PlacedPart> kept;
    std::vector<size_t> aside_part;  // per part set aside: its index while reading
    for (size_t i = 0; i < model_.parts.size(); ++i) {
      PlacedPart& p = model_.parts[i];
      if (shown_[i]) {
        kept.push_back(std::move(p));
      } else if (!p.ghost) {
        if (p.built_in > 0) p.step = p.built_in;  // built, and never shown in place
        p.built_in = p.apart_from = 0;
        model_.aside.push_back(std::move(p));
        aside_part.push_back(i);
      }
    }
    model_.parts = std::move(kept);
    if (views_lost_) return;
    std::set<int> building;  // the steps that build aside
    for (const PlacedPart& p : model_.aside) building.insert(p.step);
    for (const StepEnd& end : step_ends_) {
      if (!building.count(end.step)) continue;
      std::vector<int>& shown = aside_shown_[end.step];
      for (size_t k = 0; k < aside_part.size(); ++k)
        if (shown_at(end, aside_part[k])) shown.push_back(int(k));
    }
  }
  std::map<int, std::vector<int>> aside_shown_;  // by step number as read

  // A submodel with steps of its own is a sub-assembly built apart the first time it is placed,
  // as LPub3D's instructions build it: its steps come before the step that places it, which has
  // it whole, in place; its parts are in place from that step (PlacedPart::built_in says where
  // each was built). Submodels inside it are part of its building.
  bool building_apart_ = false;
  static bool has_steps(const Block& b) {
    bool placed = false;
    for (const Entry& e : b.entries) {
      if (std::holds_alternative<RefLine>(e)) placed = true;
      if (placed && std::holds_alternative<StepMark>(e)) return true;
    }
    return false;
  }

  // Steps counted from the parts (Step::parts in place, Step::aside built aside); steps left with
  // nothing go, and the others are numbered again.
  void count_steps() {
    std::map<int, int> number;
    for (const PlacedPart& p : model_.parts) {
      number[p.step] = 0;
      if (p.built_in > 0) number[p.built_in] = 0;
    }
    for (const PlacedPart& p : model_.aside) number[p.step] = 0;
    std::map<int, std::string> rotstep;
    for (const Step& st : model_.steps) rotstep[st.number] = st.rotstep;
    std::vector<Step> steps;
    for (auto& [old, now] : number) {
      now = int(steps.size()) + 1;
      steps.push_back({now, 0, rotstep[old], 0, aside_shown_[old]});
    }
    for (PlacedPart& p : model_.parts) {
      ++steps[size_t((p.step = number[p.step]) - 1)].parts;
      if (p.built_in == 0) continue;
      // The sub-assembly's first step is its first that places a part.
      p.apart_from = number.lower_bound(p.apart_from)->second;
      ++steps[size_t((p.built_in = number[p.built_in]) - 1)].aside;
    }
    for (PlacedPart& p : model_.aside) ++steps[size_t((p.step = number[p.step]) - 1)].aside;
    if (steps.empty()) steps.push_back(Step{});
    model_.steps = std::move(steps);
  }

  int parts_in_step() const { return int(model_.parts.size() - step_start_); }
  void end_step(const std::string& rotstep) {
    model_.steps.push_back(Step{step_, parts_in_step(), rotstep, 0, {}});
    step_ends_.push_back({step_, int(views_.size()) - 1, model_.parts.size()});
    ++step_;
    step_start_ = model_.parts.size();
  }
  std::set<std::pair<std::string, int>> singular_reported_;

  void diag(Severity s, const Document& doc, int line, std::string msg) {
    model_.diagnostics.push_back({s, doc.file, line, std::move(msg)});
  }

  // The parts a document embeds, for the part library to read (those of a model file placed by
  // the main model as well as the main file's own).
  void register_embedded_parts(const Document& doc) {
    for (const Block& b : doc.blocks)
      if (is_part(doc, b))
        model_.embedded_parts.emplace_back(
            b.name, doc.text.substr(b.text_begin, b.text_end - b.text_begin));
  }

  // A FILE block is a part when its !LDRAW_ORG says so or, without one, when it draws only lines,
  // primitives and subparts: an unofficial part pasted into an MPD (a printed torso, a patterned
  // slope) places no part of its own, and its primitives are not parts of the model.
  bool is_part(const Document& doc, const Block& b) {
    if (!b.ldraw_org.empty()) return b.is_part();
    if (auto it = part_blocks_.find(&b); it != part_blocks_.end()) return it->second;
    bool draws = b.drawn_lines > 0, only_drawing = true;
    for (const Entry& e : b.entries)
      if (const auto* ref = std::get_if<RefLine>(&e)) {
        draws = true;
        only_drawing = only_drawing && draws_no_part(doc, ref->name);
      }
    return part_blocks_[&b] = draws && only_drawing;
  }

  // Whether `name` is drawing (a primitive or a subpart), not a part or a model.
  bool draws_no_part(const Document& doc, const std::string& name) {
    if (const Block* block = doc.find(name)) {
      const std::string org = ascii_lower(block->ldraw_org);
      return org.find("subpart") != std::string::npos || org.find("primitive") != std::string::npos;
    }
    const std::string reference = normalize_reference(name);
    for (const char* folder : {"s/", "48/", "8/"})  // the library's subpart and primitive folders
      if (reference.starts_with(folder)) return true;
    for (const fs::path& lib : options_.library_dirs) {
      for (const char* folder : {"p", "unofficial/p"})
        if (finder_.find(lib / folder, reference)) return true;
    }
    return false;
  }

  void check_main_model(const Document& doc) {
    if (doc.blocks.size() < 2) return;
    std::map<std::string, std::vector<std::string>> used_by;
    for (const Block& b : doc.blocks)
      for (const Entry& e : b.entries)
        if (const auto* ref = std::get_if<RefLine>(&e); ref && doc.find(ref->name))
          used_by[normalize_reference(ref->name)].push_back(b.name);
    const Block& first = doc.blocks.front();
    auto it = used_by.find(normalize_reference(first.name));
    if (it == used_by.end()) return;
    for (const Block& b : doc.blocks) {
      if (&b == &first || is_part(doc, b) || used_by.count(normalize_reference(b.name))) continue;
      diag(Severity::Warning, doc, first.first_line,
           fmt::format("the main model '{}' (the first FILE) is used as a submodel by '{}', while "
                       "'{}' is used by nothing and may be the real main model",
                       first.name, it->second.front(), b.name));
      return;
    }
  }

  int resolve_color(int color, int parent) const {
    if (color == kMainColor) return parent;
    if (color == kEdgeColor) {
      if (parent == kMainColor) return kEdgeColor;
      if (const Color* c = colors_.find(parent)) return kDirectColorBase + int(c->edge_rgb);
      return kEdgeColor;
    }
    return color;
  }

  // The document of a model file referenced from `from`, parsed once.
  const Document* external_document(const fs::path& path) {
    auto canonical = fs::weakly_canonical(path);
    if (auto it = external_.find(canonical); it != external_.end()) return it->second;
    auto doc = std::make_unique<Document>();
    doc->file = path.string();
    doc->dir = path.parent_path();
    std::string err;
    auto bytes = read_bytes(path, err);
    if (!bytes) {
      model_.diagnostics.push_back({Severity::Error, path.string(), 0, err});
      external_[canonical] = nullptr;
      return nullptr;
    }
    doc->text = std::move(*bytes);
    model_.files.push_back(path);
    Parser(*doc, model_.diagnostics, model_.colors).parse();
    register_embedded_parts(*doc);
    const Document* raw = doc.get();
    documents_.push_back(std::move(doc));
    external_[canonical] = raw;
    return raw;
  }

  static bool header_says_part(const fs::path& path) {
    std::ifstream in(path);
    std::string line;
    for (int i = 0; i < 20 && std::getline(in, line); ++i)
      if (auto at = ascii_lower(line).find("!ldraw_org"); at != std::string::npos)
        return names_a_part(std::string_view(line).substr(at + 10));
    return false;
  }

  void add_part(const Document& doc, const RefLine& ref, const Transform& world, int color,
                const std::string& submodel, fs::path definition, std::string embedded) {
    if (model_.parts.size() >= options_.max_parts) {
      if (!budget_exceeded_)
        diag(Severity::Error, doc, ref.line,
             fmt::format("the model expands to more than {} parts; reading stopped",
                         options_.max_parts));
      budget_exceeded_ = true;
      return;
    }
    if (options_.budget && model_.parts.size() % 1024 == 0)
      options_.budget->check(kReading, model_.parts.size());
    PlacedPart p;
    p.part = normalize_part_name(ref.name);
    p.reference = ref.name;
    p.color = color;
    p.transform = world;
    p.inside = inside_;
    p.local = ref.transform;
    p.file = doc.file;
    p.line = ref.line;
    p.step = step_;
    p.ghost = ghost_ || ref.ghost;
    p.submodel = submodel;
    p.definition = std::move(definition);
    p.embedded_definition = std::move(embedded);
    model_.parts.push_back(std::move(p));
  }

  void expand(const Document& doc, const RefLine& ref, const Transform& parent, int parent_color,
              const std::string& submodel) {
    if (budget_exceeded_) return;
    // Checked here, not while parsing: part definitions may scale primitives to nothing.
    if (std::abs(ref.transform.determinant()) < 1e-9) {
      if (singular_reported_.insert({doc.file, ref.line}).second)
        diag(Severity::Error, doc, ref.line,
             fmt::format("singular matrix: '{}' cannot be placed", ref.name));
      return;
    }
    Transform world = parent.then(ref.transform);
    int color = resolve_color(ref.color, parent_color);
    for (double v : world.pos)
      if (std::abs(v) > kAbsurdCoordinate) {
        diag(Severity::Error, doc, ref.line,
             fmt::format("'{}' lands at an absurd position", ref.name));
        return;
      }
    // 1. A block of the same MPD.
    if (const Block* target = doc.find(ref.name)) {
      if (is_part(doc, *target))
        return add_part(doc, ref, world, color, submodel, {}, target->name);
      return descend(doc, *target, ref, world, color);
    }
    // 2. A file next to the including file, then 3. the LDraw libraries.
    if (auto local = finder_.find(doc.dir, ref.name)) {
      if (header_says_part(*local)) return add_part(doc, ref, world, color, submodel, *local, {});
      const Document* sub = external_document(*local);
      if (!sub || sub->blocks.empty()) return;
      if (is_part(*sub, sub->blocks.front()))
        return add_part(doc, ref, world, color, submodel, *local, {});
      return descend(*sub, sub->blocks.front(), ref, world, color);
    }
    for (const fs::path& lib : options_.library_dirs) {
      for (const char* folder : {"parts", "p", "unofficial/parts", "unofficial/p"})
        if (auto found = finder_.find(lib / folder, ref.name))
          return add_part(doc, ref, world, color, submodel, *found, {});
      if (auto found = finder_.find(lib / "models", ref.name)) {
        const Document* sub = external_document(*found);
        if (!sub || sub->blocks.empty()) return;
        return descend(*sub, sub->blocks.front(), ref, world, color);
      }
    }
    // A part, or a submodel, with no definition here: left out by whoever needs its file, with
    // this line, as a missing part is (a town whose terrain file is not in every copy).
    add_part(doc, ref, world, color, submodel, {}, {});
  }

  void descend(const Document& doc, const Block& target, const RefLine& ref, const Transform& world,
               int color) {
    if (std::find(stack_.begin(), stack_.end(), &target) != stack_.end()) {
      std::string chain;
      for (const Block* b : stack_) chain += b->name + " -> ";
      diag(Severity::Error, doc, ref.line, fmt::format("reference loop: {}{}", chain, target.name));
      return;
    }
    if (int(stack_.size()) >= options_.max_depth) {
      diag(Severity::Error, doc, ref.line,
           fmt::format("submodels nested deeper than {} levels", options_.max_depth));
      return;
    }
    if (std::find(model_.submodels.begin(), model_.submodels.end(), target.name) ==
        model_.submodels.end())
      model_.submodels.push_back(target.name);
    stack_.push_back(&target);
    // Recorded only where it places a part: an expansion of nothing costs no memory.
    const size_t placements_before = model_.placements.size();
    const size_t parts_before = model_.parts.size();
    const int outer = inside_;
    const bool outer_ghost = ghost_;
    model_.placements.push_back({outer, ref.transform});
    inside_ = int(placements_before);
    ghost_ = ghost_ || ref.ghost;
    const bool first = placed_.insert(&target).second;
    // Built apart: its steps hold its own parts only; the main model's parts placed so far in
    // this step wait for the step that places it.
    const bool apart = first && !building_apart_ && has_steps(target);
    const size_t main_from = step_start_;
    const int apart_from = step_;
    if (apart) {
      building_apart_ = true;
      step_start_ = parts_before;
    }
    // A submodel's BUFEXCHG lines are not followed: MLCad's buffers are the main model's view.
    for (const Entry& entry : target.entries) {
      if (const auto* child = std::get_if<RefLine>(&entry))
        expand(doc, *child, world, color, target.name);
      else if (const auto* mark = std::get_if<StepMark>(&entry);
               mark && first && parts_in_step() > 0)  // its own step, the first time it is placed
        end_step(mark->rotstep);
    }
    if (apart) {
      building_apart_ = false;
      if (parts_in_step() > 0) end_step({});  // the sub-assembly whole
      for (size_t i = parts_before; i < model_.parts.size(); ++i) {
        model_.parts[i].built_in = model_.parts[i].step;
        model_.parts[i].apart_from = apart_from;
        model_.parts[i].step = step_;
      }
      for (size_t i = main_from; i < parts_before; ++i) model_.parts[i].step = step_;
      step_start_ = main_from;  // the placing step: the main model's parts and the sub-assembly
    }
    inside_ = outer;
    ghost_ = outer_ghost;
    if (model_.parts.size() == parts_before) model_.placements.resize(placements_before);
    stack_.pop_back();
  }
};

Model read_document(std::unique_ptr<Document> doc, const ReadOptions& options) {
  Model model;
  model.source = doc->file;
  Parser(*doc, model.diagnostics, model.colors).parse();
  if (!model.has_errors() || !doc->blocks.empty()) Flattener(options, model).run(std::move(doc));
  return model;
}

}  // namespace

Model read_text(std::string_view text, const std::string& name, const ReadOptions& options) {
  auto doc = std::make_unique<Document>();
  doc->file = name;
  doc->dir = fs::path(name).parent_path();
  if (doc->dir.empty()) doc->dir = ".";
  doc->text = std::string(text);
  return read_document(std::move(doc), options);
}

Model read_file(const fs::path& path, const ReadOptions& options) {
  std::string err;
  auto bytes = read_bytes(path, err);
  if (!bytes) {
    Model model;
    model.source = path.string();
    model.diagnostics.push_back({Severity::Error, path.string(), 0, err});
    return model;
  }
  Model model = read_text(*bytes, path.string(), options);
  model.files.insert(model.files.begin(), path);
  return model;
}

}  // namespace lego::ldraw
