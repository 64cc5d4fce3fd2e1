#pragma once
// Work on several threads whose results come out in the order it was asked for: brickcheck
// checks many files at once and prints their reports as if it had checked them one by one.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace lego {

// Runs work(i) for every i in [0, n) on up to `jobs` threads, the calling thread among them, and
// calls deliver(i, result) on the calling thread in the order of i, each as soon as it and every
// result before it are ready. Work is handed out one item at a time, so a long item does not hold
// up the items after it on other threads. An exception thrown by work(i) is rethrown by the call
// at the place where result i would have been delivered, once the threads have stopped.
template <class Result>
void run_in_order(size_t n, int jobs, const std::function<Result(size_t)>& work,
                  const std::function<void(size_t, Result&&)>& deliver) {
  const size_t threads = std::min(n, size_t(std::max(jobs, 1)));
  if (threads <= 1) {
    for (size_t i = 0; i < n; ++i) deliver(i, work(i));
    return;
  }
  std::vector<std::optional<Result>> results(n);
  std::vector<std::exception_ptr> failures(n);
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};  // a delivery threw: hand out no more work
  std::mutex mutex;
  std::condition_variable ready;
  auto done = [&](size_t i) { return results[i].has_value() || failures[i] != nullptr; };
  auto run = [&](size_t k) {
    std::optional<Result> r;
    std::exception_ptr failure;
    try {
      r.emplace(work(k));
    } catch (...) {
      failure = std::current_exception();
    }
    {
      const std::lock_guard lock(mutex);
      results[k] = std::move(r);
      failures[k] = failure;
    }
    ready.notify_all();
  };
  std::vector<std::thread> others;
  for (size_t t = 1; t < threads; ++t)
    others.emplace_back([&] {
      for (size_t k; !stop && (k = next++) < n;) run(k);
    });
  std::exception_ptr thrown;
  try {
    for (size_t i = 0; i < n; ++i) {
      // The calling thread works too until the result it waits for is ready.
      for (;;) {
        std::unique_lock lock(mutex);
        if (done(i)) break;
        if (next >= n) {
          ready.wait(lock, [&] { return done(i); });
          break;
        }
        lock.unlock();
        if (const size_t k = next++; k < n) run(k);
      }
      std::unique_lock lock(mutex);
      if (failures[i]) std::rethrow_exception(failures[i]);
      Result r = std::move(*results[i]);
      results[i].reset();
      lock.unlock();
      deliver(i, std::move(r));
    }
  } catch (...) {
    thrown = std::current_exception();
    stop = true;
  }
  for (std::thread& t : others) t.join();
  if (thrown) std::rethrow_exception(thrown);
}

}  // namespace lego
