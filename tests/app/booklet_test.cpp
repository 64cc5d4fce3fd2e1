// Real clients: the instructions booklet (--instructions) rendered by LeoCAD and opened in
// headless Chromium. Tests that need them skip when leocad, xvfb-run or chromium is missing.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "app/run_tool.h"
#include "ldraw/reader.h"
#include "mesh/image.h"
#include "report/instructions.h"
#include "report/step_camera.h"
#include "test_paths.h"

namespace lego {
namespace {

namespace fs = std::filesystem;
using test::run_tool;

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The page as headless Chromium has it once loaded (its DOM, scripts run), and a screenshot of
// it beside the booklet for a person to look at.
std::string chromium_dom(const fs::path& page) {
  const fs::path profile = page.parent_path() / ".chromium";
  const std::string flags =
      "--headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync "
      "--virtual-time-budget=10000 --user-data-dir=" +
      test::quote(profile.string());
  const std::string url = test::quote("file://" + fs::absolute(page).string());
  const fs::path dom = page.parent_path() / ".dom.html";
  std::system(("chromium " + flags + " --dump-dom " + url + " >" + test::quote(dom.string()) +
               " 2>/dev/null")
                  .c_str());
  std::system(("chromium " + flags + " --window-size=1000,1400 --screenshot=" +
               test::quote((page.parent_path() / ".screenshot.png").string()) + " " + url +
               " >/dev/null 2>&1")
                  .c_str());
  const std::string out = text_of(dom);
  fs::remove_all(profile);
  fs::remove(dom);
  return out;
}

// A drawn LDraw file's part lines step by step, each as its colour and x (after the last STEP, a
// last step with what follows it).
std::vector<std::vector<std::pair<int, double>>> parts_by_step(const std::string& ldraw) {
  std::vector<std::vector<std::pair<int, double>>> steps(1);
  std::istringstream lines(ldraw);
  for (std::string line; std::getline(lines, line);) {
    if (line == "0 STEP") steps.emplace_back();
    if (line.rfind("1 ", 0) != 0) continue;
    std::istringstream in(line);
    int type = 0, color = 0;
    double x = 0;
    in >> type >> color >> x;
    steps.back().emplace_back(color, x);
  }
  return steps;
}

// The x of every part line of a drawn LDraw file, in order.
std::vector<double> xs_of(const std::string& ldraw) {
  std::vector<double> xs;
  for (const auto& step : parts_by_step(ldraw))
    for (const auto& part : step) xs.push_back(part.second);
  return xs;
}

class Booklet : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch("lego_booklet_", "");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  fs::path dir_;
};

// legolize's booklet: a page per step with its picture (every one shown in a real browser), its
// parts and its C_M, and a cover with the finished model and every part.
TEST_F(Booklet, LegolizeWritesAPagePerStepThatABrowserShows) {
  if (!test::have("leocad") || !test::have("xvfb-run") || !test::have("chromium"))
    GTEST_SKIP() << "leocad, xvfb-run or chromium is not installed";
  const fs::path book = dir_ / "crate-book", model = dir_ / "crate.mpd", report = dir_ / "r.json";
  auto run =
      run_tool("legolize", {(test::data_dir() / ".." / ".." / "samples" / "crate.obj").string(),
                            "--height", "6", "-o", model.string(), "--report", report.string(),
                            "--instructions", book.string()});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.err.find("rendering"), std::string::npos) << run.err;  // progress
  const auto r = nlohmann::json::parse(text_of(report));
  const size_t steps = r["steps"].size();
  ASSERT_GE(steps, 6u);
  for (size_t k = 1; k <= steps; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "step-%03zu.png", k);
    EXPECT_TRUE(fs::exists(book / name)) << name;
  }
  EXPECT_TRUE(fs::exists(book / "cover.png"));
  // Each kind of part drawn alone: different parts, different pictures.
  ASSERT_TRUE(fs::exists(book / "part-002.png"));
  EXPECT_NE(text_of(book / "part-001.png"), text_of(book / "part-002.png"));

  const std::string dom = chromium_dom(book / "index.html");
  ASSERT_FALSE(dom.empty()) << "chromium printed no DOM";
  // The pictures: the cover, a step each, and the step's parts one by one.
  const std::string pictures = std::to_string(steps + 1 + count(dom, "<figure>"));
  EXPECT_NE(dom.find("data-pictures=\"" + pictures + "\""), std::string::npos);
  EXPECT_NE(dom.find("data-pictures-shown=\"" + pictures + "\""), std::string::npos)
      << "a picture did not show";
  for (size_t k = 1; k <= steps; ++k) {
    const std::string id = "id=\"step-" + std::to_string(k) + "\"";
    const size_t at = dom.find(id);
    ASSERT_NE(at, std::string::npos) << id;
    const size_t end = dom.find("</section>", at);
    const std::string page = dom.substr(at, end - at);
    EXPECT_NE(page.find("<img"), std::string::npos) << "step " << k;
    EXPECT_NE(page.find("class=\"parts\""), std::string::npos) << "step " << k;
    // A step a certificate showed standing says its C_M is at least the certificate's.
    const bool certified = r["steps"][k - 1]["certified"].get<bool>();
    EXPECT_NE(page.find(certified ? "C_M ≥ " : "C_M = "), std::string::npos) << "step " << k;
    // Its parts add up to the bricks the step places.
    std::regex counts(R"(<td class="count">(\d+)×</td>)");
    int placed = 0;
    for (std::sregex_iterator m(page.begin(), page.end(), counts), e; m != e; ++m)
      placed += std::stoi((*m)[1]);
    EXPECT_EQ(placed, r["steps"][k - 1]["new_bricks"].get<int>()) << "step " << k;
    // Its parts drawn one by one: a picture per line of its list, the counts the same.
    std::regex drawn(R"(<figcaption>(\d+)×</figcaption>)");
    int shown = 0;
    for (std::sregex_iterator m(page.begin(), page.end(), drawn), e; m != e; ++m)
      shown += std::stoi((*m)[1]);
    EXPECT_EQ(shown, placed) << "step " << k;
    EXPECT_EQ(count(page, "<figure>"), count(page, "<td class=\"count\">")) << "step " << k;
  }
  EXPECT_EQ(count(dom, "class=\"step\""), steps);
  EXPECT_NE(dom.find("id=\"cover\""), std::string::npos);
  // The printable booklet: a PDF Chromium printed, the cover and each step on pages of their own
  // (a long parts list may take a second page).
  const std::string pdf = text_of(book / "instructions.pdf");
  ASSERT_TRUE(pdf.starts_with("%PDF-")) << "no PDF";
  const std::regex page(R"(/Type\s*/Page[^s])");
  const size_t pages = size_t(
      std::distance(std::sregex_iterator(pdf.begin(), pdf.end(), page), std::sregex_iterator()));
  EXPECT_GE(pages, steps + 1);
  EXPECT_LE(pages, steps + 3);
  EXPECT_NE(dom.find("href=\"instructions.pdf\""), std::string::npos);
}

// Without LeoCAD the booklet still comes out, without pictures, and says so.
TEST_F(Booklet, WithoutLeoCadItHasNoPicturesAndSaysSo) {
  const fs::path book = dir_ / "tower-book";
  const fs::path tower = test::data_dir() / ".." / ".." / "samples" / "tower.ldr";
  auto run = run_tool("brickcheck", {"--instructions", book.string(), tower.string()},
                      "PATH=/nonexistent");
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.err.find("LeoCAD is not installed"), std::string::npos) << run.err;
  const std::string html = text_of(book / "index.html");
  EXPECT_NE(html.find("LeoCAD is not installed"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_NE(html.find("Chromium is not installed"), std::string::npos);
  EXPECT_FALSE(fs::exists(book / "instructions.pdf"));
  // A page per step brickcheck --steps analyses.
  const auto steps =
      nlohmann::json::parse(run_tool("brickcheck", {"--json", "--steps", tower.string()}).out);
  EXPECT_EQ(count(html, "class=\"step\""), steps["steps"].size());
  EXPECT_GT(steps["steps"].size(), 1u);
  EXPECT_NE(html.find("it stands"), std::string::npos);
}

// Parts are named as a builder reads them, without the library's marks: an alias ("=Plate 1 x
// 1") is a plate, an obsolete part ("~Brick 1 x 2 x 5 (Obsolete)") a brick, the library's
// aligning spaces ("Brick  1 x  2") one.
TEST_F(Booklet, PartNamesWithoutTheLibrarysMarks) {
  SKIP_WITHOUT_SHARED();
  const fs::path model = dir_ / "marks.ldr", book = dir_ / "marks-book";
  std::ofstream(model) << "0 marks\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
                          "1 1 -30 -144 0 1 0 0 0 1 0 0 0 1 2454.dat\n"
                          "1 14 30 -32 0 1 0 0 0 1 0 0 0 1 30008.dat\n0 STEP\n";
  const auto run = run_tool("brickcheck",
                            {"--ldraw-dir", (test::shared_dir() / "ldraw-library").string(),
                             "--instructions", book.string(), model.string()},
                            "PATH=/nonexistent");
  const std::string html = text_of(book / "index.html");
  ASSERT_FALSE(html.empty()) << run.out << run.err;
  EXPECT_NE(html.find(">Plate 1 x 1<"), std::string::npos) << html;
  EXPECT_NE(html.find(">Brick 1 x 2 x 5<"), std::string::npos) << html;  // spaces as read
  EXPECT_EQ(html.find("=Plate"), std::string::npos);
  EXPECT_EQ(html.find("~Brick"), std::string::npos);
  EXPECT_EQ(html.find("(Obsolete)"), std::string::npos);
}

// An MPD whose submodel has steps of its own, placed after a leading empty step: the pictures
// follow the booklet's steps (LeoCAD, given the file, drew one picture for the submodel's three
// steps): each differs from the one before, and the submodel's pages say it is built aside.
TEST_F(Booklet, PicturesFollowTheBookletsStepsThroughSubmodels) {
  SKIP_WITHOUT_SHARED();
  if (!test::have("leocad") || !test::have("xvfb-run"))
    GTEST_SKIP() << "leocad or xvfb-run is not installed";
  const fs::path model = dir_ / "tower.mpd", book = dir_ / "tower-book";
  std::ofstream(model) << "0 FILE tower.mpd\n0 tower\n0 STEP\n"
                          "1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
                          "1 16 0 -24 0 1 0 0 0 1 0 0 0 1 wall.ldr\n0 STEP\n"
                          "1 1 0 -96 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
                          "0 FILE wall.ldr\n0 wall\n"
                          "1 14 0 -24 0 1 0 0 0 1 0 0 0 1 3003.dat\n0 STEP\n"
                          "1 2 0 -48 0 1 0 0 0 1 0 0 0 1 3003.dat\n0 STEP\n"
                          "1 15 0 -72 0 1 0 0 0 1 0 0 0 1 3003.dat\n0 STEP\n";
  const auto run =
      run_tool("brickcheck", {"--ldraw-dir", (test::shared_dir() / "ldraw-library").string(),
                              "--instructions", book.string(), model.string()});
  ASSERT_TRUE(fs::exists(book / "index.html")) << run.out << run.err;
  std::vector<fs::path> pictures;  // step-NNN.png, by the booklet's step numbers
  for (const auto& e : fs::directory_iterator(book))
    if (e.path().filename().string().rfind("step-", 0) == 0) pictures.push_back(e.path());
  std::sort(pictures.begin(), pictures.end());
  // The red brick, the wall's three built apart, the wall set in place, the blue brick.
  ASSERT_EQ(pictures.size(), 6u) << run.err;
  std::string before;
  for (const fs::path& p : pictures) {
    const std::string picture = text_of(p);
    ASSERT_FALSE(picture.empty()) << p;
    EXPECT_NE(picture, before) << p << " is the picture before it";
    before = picture;
  }
  EXPECT_EQ(count(text_of(book / "index.html"), ", built aside</small>"), 3u);
}

// A packed MPD embeds its parts: the booklet's own file carries them, so every step has its
// picture and every part its own.
TEST_F(Booklet, APackedModelsEmbeddedPartsAreDrawn) {
  SKIP_WITHOUT_SHARED();
  if (!test::have("leocad") || !test::have("xvfb-run"))
    GTEST_SKIP() << "leocad or xvfb-run is not installed";
  const fs::path book = dir_ / "packed-book";
  const auto run = run_tool(
      "brickcheck",
      {"--ldraw-dir", (test::shared_dir() / "ldraw-library").string(), "--instructions",
       book.string(), (test::shared_dir() / "ldraw-models" / "car.ldr_Packed.mpd").string()});
  const std::string html = text_of(book / "index.html");
  ASSERT_FALSE(html.empty()) << run.out << run.err;
  size_t steps = 0, parts = 0;
  for (const auto& e : fs::directory_iterator(book)) {
    const std::string name = e.path().filename().string();
    steps += name.rfind("step-", 0) == 0;
    parts += name.rfind("part-", 0) == 0;
  }
  EXPECT_EQ(steps, 8u) << run.err;
  EXPECT_EQ(steps, count(html, "<section class=\"step\""));
  EXPECT_GT(parts, 20u) << run.err;
  EXPECT_EQ(html.find("did not render"), std::string::npos);
}

// A sub-assembly built aside in MLCad's buffers has its own pages: its parts listed where it is
// built, drawn beside the model (clear of it) and framed on it; the step that sets it in place
// (GHOST lines) lists nothing new; the cover is framed on the finished model alone.
TEST(BookletOf, ASubAssemblyBuiltAsideHasItsOwnPages) {
  const ldraw::Model model = ldraw::read_text(
      "0 aside\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG A STORE\n0 BUFEXCHG B RETRIEVE\n"
      "1 14 20 -48 0 1 0 0 0 1 0 0 0 1 3003.dat\n0 STEP\n"
      "1 1 40 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG A RETRIEVE\n"
      "0 GHOST 1 14 20 -72 0 1 0 0 0 1 0 0 0 1 3003.dat\n"
      "0 GHOST 1 1 40 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
      "aside.ldr");
  ASSERT_FALSE(model.has_errors());
  const report::Booklet b = report::booklet_of(model);
  ASSERT_EQ(b.steps.size(), 4u);
  EXPECT_FALSE(b.steps[0].aside);
  EXPECT_TRUE(b.steps[1].aside);
  EXPECT_TRUE(b.steps[2].aside);
  EXPECT_FALSE(b.steps[3].aside);
  ASSERT_EQ(b.steps[1].parts.size(), 1u);
  EXPECT_EQ(b.steps[1].parts[0].part, "3003");
  EXPECT_TRUE(b.steps[3].parts.empty()) << "the ghosts are the parts built aside";
  EXPECT_NE(b.steps[3].note.find("Set in place"), std::string::npos);
  int total = 0;
  for (const auto& p : b.parts) total += p.quantity;
  EXPECT_EQ(total, 3);
  // Drawn: the aside parts past the model along x, the ghosts in place; and both cameras.
  const std::vector<double> xs = xs_of(b.drawn);
  // By step: the base, the two built aside, the two ghosts.
  ASSERT_EQ(xs.size(), 5u);
  EXPECT_EQ(xs[3], 20);
  EXPECT_EQ(xs[4], 40);
  // Clear of the model (whose x ends at 80) by four studs: the 2 x 2's left side, the 2 x 4's.
  EXPECT_NEAR(xs[1] - 20, 80 + 80, 1e-9);
  EXPECT_NEAR(xs[2] - 40, 80 + 80, 1e-9);
  EXPECT_NE(b.drawn.find(std::string("CAMERA NAME ") + report::kStepCamera), std::string::npos);
  EXPECT_NE(b.drawn.find(std::string("CAMERA NAME ") + report::kCoverCamera), std::string::npos);
}

// A sub-assembly built where nothing is in place yet (a wrapper model's one submodel, the first
// floor of a house) is built in place: its pages are the model's, drawn where it stands, and no
// page sets it in place; one built after it is built aside as before.
TEST(BookletOf, TheFirstSubAssemblyIsBuiltInPlace) {
  const std::string car =
      "0 FILE car.ldr\n0 car\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "1 15 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n";
  const ldraw::Model wrapper = ldraw::read_text(
      "0 FILE main.ldr\n0 main\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 car.ldr\n0 STEP\n" + car, "w.mpd");
  ASSERT_FALSE(wrapper.has_errors());
  const report::Booklet w = report::booklet_of(wrapper);
  ASSERT_EQ(w.steps.size(), 2u);  // the car's two; the step that places it adds nothing
  for (const auto& st : w.steps) {
    EXPECT_FALSE(st.aside) << st.number;
    EXPECT_TRUE(st.note.empty()) << st.note;
    ASSERT_EQ(st.parts.size(), 1u);
  }
  EXPECT_EQ(parts_by_step(w.drawn).size(), 3u);            // two STEPs, and what follows the last
  EXPECT_EQ(xs_of(w.drawn), (std::vector<double>{0, 0}));  // in place, not beside the model
  // A second sub-assembly, after the first: built aside, and set in place with the first.
  const ldraw::Model two = ldraw::read_text(
      "0 FILE main.ldr\n0 main\n1 16 0 0 0 1 0 0 0 1 0 0 0 1 car.ldr\n"
      "1 16 100 0 0 1 0 0 0 1 0 0 0 1 trailer.ldr\n0 STEP\n" +
          car +
          "0 FILE trailer.ldr\n0 trailer\n1 1 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
          "1 2 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
      "two.mpd");
  ASSERT_FALSE(two.has_errors());
  const report::Booklet t = report::booklet_of(two);
  ASSERT_EQ(t.steps.size(), 5u);  // car 2, trailer 2, both set in place
  EXPECT_FALSE(t.steps[0].aside);
  EXPECT_FALSE(t.steps[1].aside);
  EXPECT_TRUE(t.steps[2].aside);
  EXPECT_TRUE(t.steps[3].aside);
  EXPECT_FALSE(t.steps[4].aside);
  EXPECT_NE(t.steps[4].note.find("Set in place"), std::string::npos);
}

// A step that falls names its parts: the picture of what falls draws them in red and the model
// so far in clear (a step judged on the table, its sub-assembly alone); steps that stand have none.
TEST(BookletOf, WhatFallsIsDrawnInRedInTheModelSoFar) {
  const ldraw::Model model = ldraw::read_text(
      "0 FILE falls.mpd\n0 falls\n1 14 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "1 1 0 -120 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "1 16 200 0 0 1 0 0 0 1 0 0 0 1 arm.ldr\n0 STEP\n"
      "0 FILE arm.ldr\n0 arm\n1 2 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "1 15 0 -72 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
      "falls.mpd");
  ASSERT_FALSE(model.has_errors());
  report::Booklet b = report::booklet_of(model);
  ASSERT_EQ(b.steps.size(), 5u);  // base, floating brick, the arm's two apart, the arm in place
  report::draw_what_falls(b, model);
  EXPECT_TRUE(b.falls.empty()) << "no step names parts that fall";
  b.steps[1].falling = {1};
  b.steps[3].falling = {3};
  b.steps[3].sub_assembly_judged = true;
  report::draw_what_falls(b, model);
  ASSERT_EQ(b.falls_steps, (std::vector<int>{b.steps[1].number, b.steps[3].number}));
  // Per picture: colour and x of each part drawn.
  const auto pictures = parts_by_step(b.falls);
  ASSERT_EQ(pictures.size(), 3u);  // two pictures and what follows the last STEP
  // The floating brick in red over the base in clear.
  EXPECT_EQ(pictures[0], (std::vector<std::pair<int, double>>{{47, 0}, {4, 0}}));
  // The arm's top brick in red over its first, alone: nothing of the model in place.
  EXPECT_EQ(pictures[1], (std::vector<std::pair<int, double>>{{47, 200}, {4, 200}}));
  EXPECT_NE(b.falls.find(std::string("CAMERA NAME ") + report::kStepCamera), std::string::npos);
}

// Each picture of what falls draws the model so far: the first 20 steps that fall have one.
TEST(BookletOf, TheFirstTwentyStepsThatFallAreDrawn) {
  std::string text = "0 tower\n";
  for (int k = 0; k < 25; ++k)
    text += fmt::format("1 4 0 {} 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n", -24 * (k + 1));
  const ldraw::Model model = ldraw::read_text(text, "tower.ldr");
  report::Booklet b = report::booklet_of(model);
  ASSERT_EQ(b.steps.size(), 25u);
  for (size_t k = 0; k < b.steps.size(); ++k) b.steps[k].falling = {k};
  report::draw_what_falls(b, model);
  ASSERT_EQ(b.falls_steps.size(), 20u);
  EXPECT_EQ(b.falls_steps.front(), 1);
  EXPECT_EQ(b.falls_steps.back(), 20);
}

// brickcheck --steps --instructions: the step that falls has a picture of what falls, with its
// part in red where the model has none; the steps that stand have none.
TEST_F(Booklet, AStepThatFallsShowsItsPartInRed) {
  SKIP_WITHOUT_SHARED();
  if (!test::have("leocad") || !test::have("xvfb-run"))
    GTEST_SKIP() << "leocad or xvfb-run is not installed";
  const fs::path model = dir_ / "float.ldr", book = dir_ / "float-book";
  std::ofstream(model) << "0 float\n1 14 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
                          "1 1 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
                          "1 1 0 -144 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n";
  const auto run = run_tool(
      "brickcheck", {"--steps", "--ldraw-dir", (test::shared_dir() / "ldraw-library").string(),
                     "--instructions", book.string(), model.string()});
  const std::string html = text_of(book / "index.html");
  ASSERT_FALSE(html.empty()) << run.out << run.err;
  EXPECT_NE(html.find("src=\"falls-003.png\""), std::string::npos) << run.err;
  EXPECT_EQ(html.find("src=\"falls-001.png\""), std::string::npos);
  EXPECT_EQ(html.find("src=\"falls-002.png\""), std::string::npos);
  // A step where a part floats has no C_M of its own (the number would be the rest's).
  EXPECT_NE(html.find("The model so far: it does not stand, part of it reaches no ground."),
            std::string::npos);
  EXPECT_EQ(html.find("(it does not stand)"), std::string::npos);
  auto reds = [](const fs::path& png) {
    mesh::Texture image;
    std::string why;
    if (!mesh::load_image(png, image, why)) return -1;
    int n = 0;
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3)
      n += image.rgb[i] > 110 && image.rgb[i + 1] < 50 && image.rgb[i + 2] < 50;
    return n;
  };
  EXPECT_GT(reds(book / "falls-003.png"), 500) << "the floating brick in red";
  EXPECT_EQ(reds(book / "step-003.png"), 0) << "yellow, blue and the highlight are not red";
}

// Each step's picture is framed on the model so far, and on a step's few new parts where they are
// a small share of it: the camera LeoCAD renders the booklet's steps with has a key per step.
TEST(StepCamera, FramesTheModelSoFarAndSmallStepsCloser) {
  // A tower of eight 2 x 4 bricks, one per step, then a 1 x 1 brick beside its foot.
  std::string text = "0 tower\n";
  for (int k = 0; k < 8; ++k)
    text += fmt::format("1 4 0 {} 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n", -24 * (k + 1));
  text += "1 1 60 -24 0 1 0 0 0 1 0 0 0 1 3005.dat\n0 STEP\n";
  const ldraw::Model model = ldraw::read_text(text, "tower.ldr");
  ASSERT_FALSE(model.has_errors());
  const std::string drawn = report::booklet_of(model).drawn;
  // A key per step, and the cover's one.
  EXPECT_EQ(count(drawn, "0 !LEOCAD CAMERA POSITION_KEY "), 9u + 1);
  EXPECT_EQ(count(drawn, "0 !LEOCAD CAMERA TARGET_POSITION_KEY "), 9u + 1);
  EXPECT_EQ(count(drawn, "0 !LEOCAD CAMERA UP_VECTOR_KEY "), 9u + 1);
  EXPECT_NE(drawn.find(std::string("0 !LEOCAD CAMERA NAME ") + report::kStepCamera),
            std::string::npos);
  // The frames: the first step's is the one brick; each step's holds the model so far and grows
  // with it; the last, one small brick at the tower's foot, is around that brick.
  std::vector<report::FrameBox> boxes(9);
  for (const auto& p : model.parts) boxes[size_t(p.step - 1)].add(report::part_box(p));
  report::FrameBox so_far;
  double before = 0;
  for (size_t k = 0; k < 8; ++k) {
    so_far.add(boxes[k]);
    const report::Frame f = report::frame_step(boxes[k], so_far);
    EXPECT_GT(f.radius, before) << k;
    EXPECT_NEAR(f.radius, std::max(so_far.radius(), 30.0), 1e-9) << k;
    before = f.radius;
  }
  so_far.add(boxes[8]);
  const report::Frame last = report::frame_step(boxes[8], so_far);
  EXPECT_NEAR(last.radius, so_far.radius() / 3, 1e-9);
  EXPECT_NEAR(last.centre[0], 60, 1e-9);   // on the small brick
  EXPECT_NEAR(last.centre[1], -12, 1e-9);  // LDraw's y: half a brick up
  // A part the catalog does not know is framed on the body brickcheck derived of it (a 32 x 32
  // baseplate), else on a box of two studs around its origin.
  ldraw::PlacedPart baseplate = model.parts.front();
  baseplate.part = "3811";
  const Box body{{-320, 0, -320}, {320, 4, 320}};
  EXPECT_NEAR(report::part_box(baseplate, body).radius(), std::hypot(640, 4, 640) / 2, 1e-9);
  EXPECT_NEAR(report::part_box(baseplate).radius(), std::hypot(40, 40, 40) / 2, 1e-9);
  // The camera looks from above (LeoCAD's z is up), from +x and LDraw's -z, at its frame's
  // distance: twice the radius, twice as far.
  const std::string two = report::step_camera({{{0, 0, 0}, 100}, {{0, 0, 0}, 200}});
  std::vector<std::array<double, 3>> eyes;
  std::istringstream lines(two);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("0 !LEOCAD CAMERA POSITION_KEY ", 0) == 0) {
      std::istringstream in(line.substr(30));
      int step = 0;
      std::array<double, 3> e{};
      in >> step >> e[0] >> e[1] >> e[2];
      eyes.push_back(e);
    }
  ASSERT_EQ(eyes.size(), 2u);
  EXPECT_GT(eyes[0][0], 0);
  EXPECT_LT(eyes[0][1], 0);  // LeoCAD's y is LDraw's z
  EXPECT_GT(eyes[0][2], 0);
  const double d0 = std::hypot(eyes[0][0], eyes[0][1], eyes[0][2]);
  const double d1 = std::hypot(eyes[1][0], eyes[1][1], eyes[1][2]);
  EXPECT_NEAR(d1 / d0, 2, 1e-3);
}

// A folder with the user's own files is refused and left as it was; a booklet written before is
// replaced.
TEST_F(Booklet, NeverWritesOverAFolderOfOtherFiles) {
  const fs::path tower = test::data_dir() / ".." / ".." / "samples" / "tower.ldr";
  const fs::path mine = dir_ / "mine";
  fs::create_directories(mine);
  std::ofstream(mine / "notes.txt") << "my notes\n";
  auto refused = run_tool("brickcheck", {"--instructions", mine.string(), tower.string()},
                          "PATH=/nonexistent");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("holds other files"), std::string::npos) << refused.err;
  EXPECT_EQ(text_of(mine / "notes.txt"), "my notes\n");
  EXPECT_FALSE(fs::exists(mine / "index.html"));

  const fs::path book = dir_ / "again";
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(run_tool("brickcheck", {"--instructions", book.string(), tower.string()},
                       "PATH=/nonexistent")
                  .exit_code,
              0);
  auto two =
      run_tool("brickcheck", {"--instructions", book.string(), tower.string(), tower.string()});
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_NE(two.err.find("one FILE"), std::string::npos);
}

// A booklet written again keeps what else the user put in its folder (their own .render/ too);
// an index.html that is a link to a device or a FIFO is not read (it never ends) but refused.
TEST_F(Booklet, AWrittenAgainBookletKeepsTheUsersFilesAndNeverReadsADevice) {
  const fs::path tower = test::data_dir() / ".." / ".." / "samples" / "tower.ldr";
  const fs::path book = dir_ / "book";
  ASSERT_EQ(
      run_tool("brickcheck", {"--instructions", book.string(), tower.string()}, "PATH=/nonexistent")
          .exit_code,
      0);
  std::ofstream(book / "notes.txt") << "my notes\n";
  std::ofstream(book / "step-5.png") << "my picture\n";
  fs::create_directories(book / ".render");
  std::ofstream(book / ".render" / "mine.txt") << "mine\n";
  ASSERT_EQ(
      run_tool("brickcheck", {"--instructions", book.string(), tower.string()}, "PATH=/nonexistent")
          .exit_code,
      0);
  EXPECT_NE(text_of(book / "index.html").find("legolization booklet"), std::string::npos);
  EXPECT_EQ(text_of(book / "notes.txt"), "my notes\n");
  EXPECT_EQ(text_of(book / "step-5.png"), "my picture\n");
  EXPECT_EQ(text_of(book / ".render" / "mine.txt"), "mine\n");
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find("tmp-legolization"), std::string::npos) << e.path();

  for (const std::string kind : {"device", "fifo"}) {
    const fs::path odd = dir_ / kind;
    fs::create_directories(odd);
    if (kind == "device")
      fs::create_symlink("/dev/zero", odd / "index.html");
    else
      ASSERT_EQ(::mkfifo((odd / "index.html").c_str(), 0600), 0);
    const auto start = std::chrono::steady_clock::now();
    auto refused = run_tool("brickcheck", {"--instructions", odd.string(), tower.string()},
                            "PATH=/nonexistent");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20)) << kind;
    EXPECT_EQ(refused.exit_code, 2) << kind;
    EXPECT_NE(refused.err.find("holds other files"), std::string::npos) << refused.err;
  }
}

// Stopped while LeoCAD renders, the run leaves the old booklet whole, no folder of its own and
// no renderer running: the new booklet is made beside the old one and swapped in when whole.
TEST_F(Booklet, AStopWhileRenderingLeavesTheOldBookletAndNoRenderer) {
  if (!test::have("leocad") || !test::have("xvfb-run"))
    GTEST_SKIP() << "leocad or xvfb-run is not installed";
  const fs::path tower = test::data_dir() / ".." / ".." / "samples" / "tower.ldr";
  const fs::path book = dir_ / "book";
  ASSERT_EQ(
      run_tool("brickcheck", {"--instructions", book.string(), tower.string()}, "PATH=/nonexistent")
          .exit_code,
      0);
  const std::string old = text_of(book / "index.html");
  const std::string tool = test::tool("brickcheck").string();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl(tool.c_str(), tool.c_str(), "--quiet", "--instructions", book.c_str(), tower.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  fs::path scratch;
  for (int i = 0; i < 600 && scratch.empty(); ++i) {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().starts_with(".tmp-legolization") &&
          fs::exists(e.path() / ".render"))
        scratch = e.path() / ".render";
    if (scratch.empty()) ::usleep(50000);
  }
  ::usleep(300000);  // LeoCAD started
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_FALSE(scratch.empty()) << "brickcheck never began rendering";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_EQ(text_of(book / "index.html"), old);
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find("tmp-legolization"), std::string::npos) << e.path();
  ::usleep(500000);
  // "[/]tmp/...": the pattern does not match the shell that runs pgrep with it.
  const std::string pattern =
      fmt::format("[{}]{}", scratch.string().substr(0, 1), scratch.string().substr(1));
  const fs::path survivors = dir_ / "survivors.txt";
  EXPECT_NE(
      std::system(
          ("pgrep -af " + test::quote(pattern) + " >" + test::quote(survivors.string())).c_str()),
      0)
      << "a renderer outlived the run: " << text_of(survivors);
}

}  // namespace
}  // namespace lego
