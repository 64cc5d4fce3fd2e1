#pragma once
// Runs one of our executables the way a user or a pre-commit hook does.
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace lego::test {

struct ToolRun {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Whether a program is on the PATH (tests of real clients skip without it).
inline bool have(const char* program) {
  return std::system((std::string("command -v ") + program + " >/dev/null 2>&1").c_str()) == 0;
}

inline std::filesystem::path tool(const std::string& name) {
  return std::filesystem::path(LEGOLIZATION_BINARY_DIR) / "src" / "app" / name;
}

inline std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// `env`: VAR=VALUE settings for the tool's environment ("PATH=/nowhere"), or empty.
inline ToolRun run_tool(const std::string& name, const std::vector<std::string>& args,
                        const std::string& env = {}) {
  auto err_file = std::filesystem::temp_directory_path() / "lego_tool_err";
  err_file += std::to_string(::getpid());
  std::string cmd = (env.empty() ? std::string() : "env " + env + " ") + quote(tool(name).string());
  for (const auto& a : args) {
    cmd += ' ';
    cmd += quote(a);
  }
  cmd += " 2>";
  cmd += quote(err_file.string());
  ToolRun run;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    run.out.append(buffer.data(), n);
  int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (FILE* f = std::fopen(err_file.c_str(), "r")) {
    while ((n = std::fread(buffer.data(), 1, buffer.size(), f)) > 0)
      run.err.append(buffer.data(), n);
    std::fclose(f);
  }
  std::filesystem::remove(err_file);
  return run;
}

}  // namespace lego::test
