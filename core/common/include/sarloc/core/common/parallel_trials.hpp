#pragma once
// Monte Carlo trials on a pool of threads, shared by every evaluation (single and multiple
// burials). Trial i depends on i only, so results do not depend on the thread count.
//
//   TrialRun<TrialResult> run = run_parallel_trials<TrialResult>(n, threads,
//       [&](std::uint32_t i) { return run_trial(setup, i); }, on_done, cancelled);
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sarloc {

template <typename Result>
struct TrialRun {
  std::vector<Result> results;  ///< the completed trials, in index order
  bool cancelled = false;       ///< `cancelled` returned true: some trials were skipped
};

/// threads = 0: all cores. The first exception of any trial stops the pool and is rethrown.
/// on_done is called from the workers after each trial; cancelled is polled before each.
template <typename Result, typename Trial>
TrialRun<Result> run_parallel_trials(std::uint32_t n, std::uint32_t threads, const Trial& trial,
                                     const std::function<void()>& on_done,
                                     const std::function<bool()>& cancelled) {
  if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
  threads = std::min(threads, n);
  std::vector<Result> results(n);
  std::vector<char> done(n, 0);
  std::atomic<bool> stop{false};
  std::atomic<std::uint32_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (;;) {
      if (cancelled && cancelled()) stop = true;
      if (stop) return;
      const std::uint32_t i = next.fetch_add(1);
      if (i >= n) return;
      try {
        results[i] = trial(i);
        done[i] = 1;
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;
        return;
      }
      if (on_done) on_done();
    }
  };
  std::vector<std::thread> pool;
  for (std::uint32_t t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  TrialRun<Result> run;
  run.cancelled = stop;
  for (std::uint32_t i = 0; i < n; ++i)
    if (done[i]) run.results.push_back(std::move(results[i]));
  return run;
}

}  // namespace sarloc
