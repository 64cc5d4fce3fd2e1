// A corpus fuzz test: mutations of real and hand-written LDraw text must never crash or hang the
// reader, and every problem must come back as a diagnostic.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "ldraw/reader.h"
#include "parts/assembly_builder.h"
#include "test_paths.h"

namespace lego::ldraw {
namespace {

std::vector<std::string> seeds() {
  std::vector<std::string> corpus = {
      "0 FILE a.ldr\n0 A\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 b.ldr\n0 STEP\n0 ROTSTEP 0 90 0 ABS\n"
      "0 FILE b.ldr\n1 16 20 0 -10 0 0 1 0 1 0 -1 0 0 3001.dat\n2 24 0 0 0 1 1 1\n0 NOFILE\n",
      "0 T\r\n0 Name: t.ldr\r\n1 0x2FF0000 0 0 0 1 0 0 0 1 0 0 0 1 3005.dat\r\n4 16 0 0 0 1 0 0 1 "
      "0 1 0 0 1",
      "0 B\n1 4 0 -24 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n0 BUFEXCHG A STORE\n"
      "0 BUFEXCHG B RETRIEVE\n1 1 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n"
      "0 BUFEXCHG A RETRIEVE\n0 GHOST 1 1 0 -48 0 1 0 0 0 1 0 0 0 1 3001.dat\n0 STEP\n",
  };
  // Our own models always; the real ones of ../shared when it is there.
  for (const auto& dir :
       {test::data_dir(), test::data_dir() / "bridges", test::data_dir() / "library" / "parts",
        test::shared_dir() / "ldraw-models"}) {
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      auto ext = entry.path().extension();
      if ((ext != ".ldr" && ext != ".mpd" && ext != ".dat") || entry.file_size() > 20000) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      std::ostringstream s;
      s << in.rdbuf();
      corpus.push_back(s.str());
    }
  }
  return corpus;
}

std::string mutate(std::string text, std::mt19937& rng) {
  static const std::vector<std::string> tokens = {"0 FILE ",
                                                  "0 NOFILE\n",
                                                  "1 ",
                                                  " 16 ",
                                                  "0 STEP\n",
                                                  "nan",
                                                  "1e308",
                                                  "-",
                                                  "a.ldr",
                                                  "b.ldr",
                                                  "\n",
                                                  "\r",
                                                  "\0",
                                                  " 0 0 0 ",
                                                  "0 ROTSTEP ",
                                                  "0 BUFEXCHG A STORE\n",
                                                  "0 BUFEXCHG A RETRIEVE\n",
                                                  "0 GHOST ",
                                                  "3001.dat",
                                                  "\\",
                                                  "0x2",
                                                  "99999999999999999999",
                                                  "\t"};
  int edits = 1 + int(rng() % 8);
  for (int e = 0; e < edits; ++e) {
    size_t pos = text.empty() ? 0 : rng() % (text.size() + 1);
    switch (rng() % 5) {
      case 0:  // flip a byte
        if (!text.empty() && pos < text.size()) text[pos] = char(rng() % 256);
        break;
      case 1:  // delete a span
        if (pos < text.size()) text.erase(pos, 1 + rng() % 40);
        break;
      case 2:  // insert a token
        text.insert(pos, tokens[rng() % tokens.size()]);
        break;
      case 3: {  // duplicate a span (recursion, repeated references)
        if (pos < text.size())
          text.insert(rng() % (text.size() + 1), text.substr(pos, 1 + rng() % 200));
        break;
      }
      default:  // truncate
        text.resize(pos);
    }
  }
  return text;
}

TEST(ReaderFuzz, TenThousandMutatedInputs) {
  auto corpus = seeds();
  std::mt19937 rng(20261122);
  ReadOptions options;
  options.max_parts = 20000;
  auto start = std::chrono::steady_clock::now();
  size_t diagnostics = 0, parts = 0;
  parts::PartLibrary library({}, BrickCatalog::standard());
  for (int i = 0; i < 10000; ++i) {
    std::string input = mutate(corpus[rng() % corpus.size()], rng);
    Model m = read_text(input, "fuzz.mpd", options);
    diagnostics += m.diagnostics.size();
    parts += m.parts.size();
    ASSERT_LE(m.parts.size(), options.max_parts);
    for (const auto& d : m.diagnostics) ASSERT_FALSE(d.message.empty());
    auto conv = parts::to_assembly(m, library);
    // Every placed part is analysed, carried or left out with a reason.
    ASSERT_EQ(conv.assembly.bricks.size() + conv.assembly.carried.size() + conv.skipped.size(),
              m.parts.size());
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(diagnostics, 1000u);  // the mutations do reach the error paths
  EXPECT_GT(parts, 10000u);       // and the reading paths
  RecordProperty("seconds", std::to_string(seconds));
}

}  // namespace
}  // namespace lego::ldraw
