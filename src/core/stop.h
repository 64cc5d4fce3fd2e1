#pragma once
// How a run ends early: a stop signal (SIGINT, SIGTERM, SIGHUP) or the run's time budget. One
// thread of the process, started by `install` first thing in main, owns both. When either comes
// it waits until no output is being put in place (`Publishing`), stops the programs the run
// started (`ChildOnStop`), removes the temporaries it listed (`RemovedOnStop`), and ends the
// process: by the signal itself (a shell sees 130 or 143), or with the budget's exit code and a
// line saying where the run was.
//
// The process ends from that thread, at once, whatever the others are doing (a factorization
// that cannot be interrupted, a reader that hangs): no stage has to check for a stop, and nothing
// a stopped run computed is kept, so nothing is lost by not unwinding.
//
// Once a stop has begun, a thread that would end the process otherwise (main returning, exit())
// waits for the stop instead. Without `install` (the unit tests) nothing stops the process here;
// the lists are kept all the same.
#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <string>

namespace lego::stop {

// Blocks the stop signals in the calling thread (every thread it starts inherits that), routes
// them to the stop thread and starts it. `program` names the process in its last line.
// Also keeps libraries from installing handlers of their own for them (METIS does, for SIGTERM
// and SIGABRT, around each ordering: two at once left one installed that jumped to a dead
// stack).
void install(const std::string& program);

// How a deadline ends the process: the line printed after "PROGRAM: ", and the exit code.
struct Ending {
  std::string words;
  int exit_code = 0;
};

// While alive: once `seconds` have passed, the process ends as `ending` says then (called from the
// stop thread, never after this is destroyed). Several may be alive at once (a file each); the
// first to pass ends the process.
class Deadline {
 public:
  Deadline(double seconds, std::function<Ending()> ending);
  ~Deadline();
  Deadline(const Deadline&) = delete;
  Deadline& operator=(const Deadline&) = delete;

 private:
  int id_ = -1;
};

// While one is alive, a stop waits: renames that put a set of outputs in place all happen, or
// none.
class Publishing {
 public:
  Publishing();
  ~Publishing();
  Publishing(const Publishing&) = delete;
  Publishing& operator=(const Publishing&) = delete;
};

// A file or folder removed (with what it holds) if the run is stopped while this is alive.
class RemovedOnStop {
 public:
  explicit RemovedOnStop(std::filesystem::path path);
  ~RemovedOnStop();
  RemovedOnStop(const RemovedOnStop&) = delete;
  RemovedOnStop& operator=(const RemovedOnStop&) = delete;

 private:
  int id_ = -1;
};

// A child process (with `group`, its whole process group) stopped if the run is: SIGTERM, then
// SIGKILL to what is left a second later. Destroyed during a stop (the wait for the child came
// back because the stop ended it), it waits for the stop to end the process.
class ChildOnStop {
 public:
  ChildOnStop(pid_t pid, bool group);
  ~ChildOnStop();
  ChildOnStop(const ChildOnStop&) = delete;
  ChildOnStop& operator=(const ChildOnStop&) = delete;

 private:
  int id_ = -1;
};

// Runs `command` with /bin/sh in a process group of its own, with the stop signals as a new
// process has them, and waits for it, at most `seconds` (0: no limit; past it the group gets
// SIGTERM, then SIGKILL a second later); stopped with the run. Returns its wait status (-1: it
// could not be started). std::system would not do: it ignores SIGINT while it waits, and
// `timeout` would take the command into a process group the stop does not reach.
int run_command(const std::string& command, double seconds = 0);

}  // namespace lego::stop
