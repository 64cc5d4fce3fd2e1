#include "core/stop.h"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <thread>

extern char** environ;

namespace lego::stop {
namespace {

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};
using Clock = std::chrono::steady_clock;

struct Child {
  pid_t pid;
  bool group;
};

// The process's one stop: what it waits for, what it undoes.
struct State {
  std::shared_mutex publishing;  // shared by each Publishing, taken whole by the stop
  std::mutex mutex;              // the lists and the deadlines
  std::map<int, std::filesystem::path> removed;
  std::map<int, Child> children;
  int next_id = 0;
  struct Timed {
    Clock::time_point at;
    std::function<Ending()> ending;
  };
  std::map<int, Timed> deadlines;
  // The stop has taken its lists: what is made from now on is undone by whoever makes it.
  bool listed = false;
  std::string program;
  int pipe_read = -1, pipe_write = -1;
};

// Never destroyed: the stop thread may use it while another thread runs exit().
State& state() {
  static State* s = new State;
  return *s;
}

std::atomic<bool> g_installed{false};
std::atomic<bool> g_stopping{false};  // the stop thread is ending the process

// Another thread that would end the process while the stop does (main returning, a wait for a
// child the stop killed coming back) waits here instead: the process ends as the stop says.
void wait_for_the_stop() {
  if (!g_stopping) return;
  for (;;) ::pause();
}
int g_pipe_write = -1;  // for the handler: a plain int, set before the handler is

// Runs in whichever thread the kernel chose (one the process did not start itself: BLAS's
// workers, made before main); the stop thread takes it from there.
extern "C" void pass_to_stop_thread(int signal_number) {
  const int saved = errno;
  const unsigned char byte = static_cast<unsigned char>(signal_number);
  [[maybe_unused]] const ssize_t n = ::write(g_pipe_write, &byte, 1);
  errno = saved;
}

sigset_t stop_signal_set() {
  sigset_t set;
  sigemptyset(&set);
  for (int s : kStopSignals) sigaddset(&set, s);
  return set;
}

// Stops the children, removes the temporaries and ends the process. Called by the stop thread
// only, once.
[[noreturn]] void end(int signal_number, const std::string& message, int exit_code) {
  State& s = state();
  g_stopping = true;
  const std::unique_lock publishing(s.publishing);  // outputs being put in place: all of them
  std::map<int, Child> children;
  std::map<int, std::filesystem::path> removed;
  {
    const std::lock_guard lock(s.mutex);
    children = s.children;
    removed = s.removed;
    s.listed = true;
  }
  if (!message.empty()) {
    const std::string line = s.program + ": " + message + "\n";
    [[maybe_unused]] const ssize_t n = ::write(2, line.data(), line.size());
  }
  for (const auto& [id, c] : children) ::kill(c.group ? -c.pid : c.pid, SIGTERM);
  // A second for them to tidy up (xvfb-run stops its X server on SIGTERM), then no more.
  const auto until = Clock::now() + std::chrono::seconds(1);
  for (const auto& [id, c] : children) {
    while (Clock::now() < until && ::waitpid(c.pid, nullptr, WNOHANG) == 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ::kill(c.group ? -c.pid : c.pid, SIGKILL);
  }
  // Again while it is there: the thread that made it may be removing it too, and remove_all
  // gives up at the first entry the other removed first.
  for (const auto& [id, path] : removed) {
    std::error_code ec;
    for (int tries = 0;
         tries < 10 && std::filesystem::exists(std::filesystem::symlink_status(path, ec)); ++tries)
      std::filesystem::remove_all(path, ec);
  }
  if (signal_number > 0) {
    // Ended by the signal itself, as if nothing had caught it: the shell and make see that.
    struct sigaction action {};
    action.sa_handler = SIG_DFL;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal_number, &action, nullptr);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, signal_number);
    ::pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(signal_number);
    exit_code = 128 + signal_number;
  }
  ::_exit(exit_code);
}

void stop_thread() {
  State& s = state();
  const sigset_t set = stop_signal_set();
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);  // a process none of whose threads takes them
                                                  // would keep them pending for ever
  for (;;) {
    int timeout_ms = -1;
    {
      const std::lock_guard lock(s.mutex);
      for (const auto& [id, timed] : s.deadlines) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(timed.at - Clock::now());
        const int ms = int(std::clamp<long long>(left.count(), 0, 1 << 30));
        if (timeout_ms < 0 || ms < timeout_ms) timeout_ms = ms;
      }
    }
    pollfd p{s.pipe_read, POLLIN, 0};
    const int ready = ::poll(&p, 1, timeout_ms);
    if (ready < 0) continue;  // EINTR: the handler ran here
    if (ready == 0) {
      std::optional<Ending> ending;
      {
        const std::lock_guard lock(s.mutex);
        for (const auto& [id, timed] : s.deadlines)
          if (Clock::now() >= timed.at) {
            ending = timed.ending ? timed.ending() : Ending{"out of time", 1};
            break;
          }
      }
      if (ending) end(0, ending->words, ending->exit_code);
      continue;
    }
    unsigned char byte = 0;
    if (::read(s.pipe_read, &byte, 1) == 1 && byte != 0) end(byte, "", 0);
    // 0: the deadlines changed
  }
}

void wake_stop_thread() {
  const unsigned char byte = 0;
  [[maybe_unused]] const ssize_t n = ::write(state().pipe_write, &byte, 1);
}

template <class T>
int add_to(std::map<int, T>& list, T value) {
  const std::lock_guard lock(state().mutex);
  const int id = state().next_id++;
  list.emplace(id, std::move(value));
  return id;
}

template <class T>
void remove_from(std::map<int, T>& list, int id) {
  const std::lock_guard lock(state().mutex);
  list.erase(id);
}

}  // namespace

void install(const std::string& program) {
  if (g_installed.exchange(true)) return;
  State& s = state();
  s.program = program;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    std::perror("pipe");
    return;
  }
  s.pipe_read = fds[0];
  s.pipe_write = g_pipe_write = fds[1];
  const sigset_t set = stop_signal_set();
  ::pthread_sigmask(SIG_BLOCK, &set, nullptr);
  struct sigaction action {};
  action.sa_handler = pass_to_stop_thread;
  action.sa_flags = SA_RESTART;
  sigfillset(&action.sa_mask);
  for (int signal_number : kStopSignals) {
    struct sigaction previous {};
    ::sigaction(signal_number, nullptr, &previous);
    // Started with the signal ignored (nohup, a shell's background job): it stays so.
    if (previous.sa_handler == SIG_IGN) continue;
    ::sigaction(signal_number, &action, nullptr);
  }
  std::atexit(wait_for_the_stop);
  std::thread(stop_thread).detach();
}

Deadline::Deadline(double seconds, std::function<Ending()> ending)
    : id_(add_to(state().deadlines,
                 State::Timed{Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                 std::chrono::duration<double>(seconds)),
                              std::move(ending)})) {
  if (g_installed) wake_stop_thread();
}

// An ending is only called under the mutex: once this returns, it never is again.
Deadline::~Deadline() {
  remove_from(state().deadlines, id_);
}

Publishing::Publishing() {
  state().publishing.lock_shared();
}
Publishing::~Publishing() {
  state().publishing.unlock_shared();
}

RemovedOnStop::RemovedOnStop(std::filesystem::path path) {
  {
    const std::lock_guard lock(state().mutex);
    if (!state().listed) {
      id_ = state().next_id++;
      state().removed.emplace(id_, std::move(path));
      return;
    }
  }
  std::error_code ec;  // made after the stop looked: removed here, and the stop ends the process
  std::filesystem::remove_all(path, ec);
  wait_for_the_stop();
}
RemovedOnStop::~RemovedOnStop() {
  remove_from(state().removed, id_);
}

ChildOnStop::ChildOnStop(pid_t pid, bool group) {
  {
    const std::lock_guard lock(state().mutex);
    if (!state().listed) {
      id_ = state().next_id++;
      state().children.emplace(id_, Child{pid, group});
      return;
    }
  }
  ::kill(group ? -pid : pid, SIGKILL);  // started after the stop looked
  wait_for_the_stop();
}
ChildOnStop::~ChildOnStop() {
  remove_from(state().children, id_);
  wait_for_the_stop();
}

int run_command(const std::string& command, double seconds) {
  posix_spawnattr_t attributes;
  ::posix_spawnattr_init(&attributes);
  sigset_t none, defaults = stop_signal_set();
  sigemptyset(&none);
  ::posix_spawnattr_setsigmask(&attributes, &none);
  ::posix_spawnattr_setsigdefault(&attributes, &defaults);
  ::posix_spawnattr_setpgroup(&attributes, 0);
  ::posix_spawnattr_setflags(
      &attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  const char* argv[] = {"sh", "-c", command.c_str(), nullptr};
  pid_t pid = -1;
  int id = -1;
  {
    // Listed as it starts, and none started once the stop has looked: a stop never misses one.
    State& s = state();
    std::unique_lock lock(s.mutex);
    if (s.listed) {
      lock.unlock();
      wait_for_the_stop();
    }
    if (::posix_spawn(&pid, "/bin/sh", nullptr, &attributes, const_cast<char**>(argv), environ) ==
        0) {
      id = s.next_id++;
      s.children[id] = {pid, true};
    }
  }
  ::posix_spawnattr_destroy(&attributes);
  if (id < 0) return -1;
  int status = 0;
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(seconds > 0 ? seconds : 1e9));
  // Waited for until the limit, then sent SIGTERM and a second later SIGKILL, the whole group.
  pid_t done = 0;
  for (int signal_number : {0, SIGTERM, SIGKILL}) {
    if (signal_number != 0) ::kill(-pid, signal_number);
    const auto limit = signal_number == 0 ? until : Clock::now() + std::chrono::seconds(1);
    while ((done = ::waitpid(pid, &status, WNOHANG)) == 0 && Clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (done != 0) break;
  }
  if (done == 0) ::waitpid(pid, &status, 0);
  remove_from(state().children, id);
  wait_for_the_stop();
  return status;
}

}  // namespace lego::stop

// METIS (through CHOLMOD's orderings) sets handlers for SIGTERM and SIGABRT with signal() around
// each call and puts the earlier ones back after: handlers that longjmp to the calling thread's
// buffer. With two orderings at once one was left installed, and a SIGTERM in any other thread
// jumped to a dead stack. Its calls resolve here (the executables export this symbol): once the
// stop is installed, those signals keep their handlers; any other is set as glibc would.
extern "C" __sighandler_t __sysv_signal(int signal_number, __sighandler_t handler) noexcept {
  struct sigaction action {
  }, previous{};
  if (lego::stop::g_installed && (signal_number == SIGTERM || signal_number == SIGINT ||
                                  signal_number == SIGHUP || signal_number == SIGABRT)) {
    ::sigaction(signal_number, nullptr, &previous);
    return previous.sa_handler;
  }
  action.sa_handler = handler;
  action.sa_flags = SA_RESETHAND | SA_NODEFER;
  sigemptyset(&action.sa_mask);
  if (::sigaction(signal_number, &action, &previous) < 0) return SIG_ERR;
  return previous.sa_handler;
}
