// The process's stop (core/stop.h), each case in a child process of its own: installing it is for
// a whole process.
#include "core/stop.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

extern "C" __sighandler_t __sysv_signal(int, __sighandler_t) noexcept;

namespace lego::stop {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// Runs `body` in a child process and returns its wait status.
int in_child(const std::function<void()>& body) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    body();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

// Running, not a zombie waiting for a parent that no longer is to reap it.
bool running(pid_t pid) {
  if (::kill(pid, 0) != 0) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string pid_text, name, state;
  stat >> pid_text >> name >> state;
  return state != "Z";
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("lego_stop_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Stop, ASignalEndsTheProcessByItselfAndRemovesWhatWasListed) {
  const fs::path dir = fresh_dir("signal");
  const int status = in_child([&] {
    install("test");
    std::ofstream(dir / "temporary") << "x";
    const RemovedOnStop removed(dir / "temporary");
    ::kill(::getpid(), SIGTERM);
    std::this_thread::sleep_for(10s);
    ::_exit(1);
  });
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_FALSE(fs::exists(dir / "temporary"));
}

// A signal to a thread that blocks nothing (as BLAS's workers, made before main, do) still goes
// through the stop thread.
TEST(Stop, ASignalTakenByAForeignThreadIsPassedOn) {
  const fs::path dir = fresh_dir("foreign");
  const int status = in_child([&] {
    std::thread foreign([] {
      std::this_thread::sleep_for(10s);
      ::_exit(1);
    });
    install("test");
    fs::create_directories(dir / "folder");
    const RemovedOnStop removed(dir / "folder");
    ::pthread_kill(foreign.native_handle(), SIGINT);
    foreign.join();
  });
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
  EXPECT_FALSE(fs::exists(dir / "folder"));
}

// Outputs being put in place are all put in place: the stop waits for the Publishing.
TEST(Stop, AStopWaitsWhileOutputsArePublished) {
  const fs::path dir = fresh_dir("publishing");
  const int status = in_child([&] {
    install("test");
    {
      const Publishing publishing;
      ::kill(::getpid(), SIGTERM);
      std::this_thread::sleep_for(300ms);
      std::ofstream(dir / "second") << "x";
    }
    std::this_thread::sleep_for(10s);
  });
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_TRUE(fs::exists(dir / "second"));
}

// A deadline gone never ends the run; of those alive, the first to pass does.
TEST(Stop, TheFirstDeadlineEndsTheRunWithItsCodeAndWords) {
  const fs::path dir = fresh_dir("deadline");
  const auto start = std::chrono::steady_clock::now();
  const int status = in_child([&] {
    ::freopen((dir / "err").c_str(), "w", stderr);
    install("test");
    {
      const Deadline ended(0.1, [] { return Ending{"never said", 3}; });
    }
    const Deadline later(5, [] { return Ending{"said too late", 5}; });
    const Deadline deadline(0.2, [] { return Ending{"out of time (0.2 s) in the refinement", 4}; });
    std::this_thread::sleep_for(10s);
  });
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 4) << status;
  std::ifstream in(dir / "err");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "test: out of time (0.2 s) in the refinement");
}

// A program started with run_command is stopped with the run, and its signals are a new
// process's (SIGINT not ignored as std::system leaves it).
TEST(Stop, ChildrenAreStoppedWithTheRun) {
  const fs::path dir = fresh_dir("children");
  const int status = in_child([&] {
    install("test");
    std::thread([] {
      std::this_thread::sleep_for(300ms);
      ::kill(::getpid(), SIGTERM);
    }).detach();
    run_command("echo $$ > " + (dir / "pid").string() + "; sleep 30; touch " +
                (dir / "survived").string());
    ::_exit(1);
  });
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  std::ifstream in(dir / "pid");
  pid_t child = 0;
  in >> child;
  ASSERT_GT(child, 0);
  std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(running(child)) << "the child outlived the run";
  EXPECT_FALSE(fs::exists(dir / "survived"));
  EXPECT_EQ(run_command("exit 3"), 3 << 8);
}

// A command past its time limit is stopped, its whole process group (a shell's background job
// too, as xvfb-run's X server is).
TEST(Stop, ACommandPastItsLimitIsStoppedWithWhatItStarted) {
  const fs::path dir = fresh_dir("limit");
  const auto start = std::chrono::steady_clock::now();
  const int status =
      run_command("sleep 30 & echo $! > " + (dir / "pid").string() + "; sleep 30", 0.3);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  std::ifstream in(dir / "pid");
  pid_t background = 0;
  in >> background;
  ASSERT_GT(background, 0);
  std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(running(background)) << "the background job outlived the limit";
}

// METIS's signal() calls leave the stop's handlers in place.
TEST(Stop, LibrariesCannotTakeTheStopSignals) {
  const int status = in_child([] {
    install("test");
    struct sigaction before {
    }, after{};
    ::sigaction(SIGTERM, nullptr, &before);
    __sysv_signal(SIGTERM, SIG_DFL);
    __sysv_signal(SIGABRT, SIG_IGN);
    ::sigaction(SIGTERM, nullptr, &after);
    struct sigaction abort_action {};
    ::sigaction(SIGABRT, nullptr, &abort_action);
    ::_exit(before.sa_handler == after.sa_handler && abort_action.sa_handler == SIG_DFL ? 0 : 1);
  });
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

}  // namespace
}  // namespace lego::stop
