#include "art2part/common/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace art2part {

int threadCount(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

void parallelFor(int count, int threads, const std::function<void(int)>& body) {
  const int n = std::min(threadCount(threads), std::max(1, count));
  if (n <= 1) {
    for (int k = 0; k < count; ++k) body(k);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < n; ++t)
    pool.emplace_back([&, t] {
      for (int k = t; k < count; k += n) body(k);
    });
  for (std::thread& thread : pool) thread.join();
}

bool runTicking(int threads, const std::function<void(int t, const std::atomic<bool>& stop)>& work, double period,
                const std::function<bool()>& tick) {
  const int n = std::max(1, threads);
  std::atomic<bool> stop{false};
  bool stopped = false;  // tick said so
  std::mutex mutex;
  std::condition_variable changed;
  int running = n;
  std::exception_ptr failure;
  std::vector<std::thread> pool;
  auto joinAll = [&] {
    for (std::thread& thread : pool) thread.join();
  };
  try {
    for (int t = 0; t < n; ++t)
      pool.emplace_back([&, t] {
        try {
          work(t, stop);
        } catch (...) {
          const std::lock_guard<std::mutex> lock(mutex);
          if (!failure) failure = std::current_exception();
          stop.store(true);
        }
        {
          const std::lock_guard<std::mutex> lock(mutex);
          --running;
        }
        changed.notify_one();
      });
  } catch (...) {  // no thread to be had: stop the ones running before they are destroyed joinable
    stop.store(true);
    joinAll();
    throw;
  }
  try {
    std::unique_lock<std::mutex> lock(mutex);
    const auto wait = std::chrono::duration<double>(period);
    while (running > 0) {
      if (changed.wait_for(lock, wait, [&] { return running == 0; })) break;
      if (stopped) continue;  // the works return, unreported
      lock.unlock();
      if (!tick()) {
        stopped = true;
        stop.store(true);
      }
      lock.lock();
    }
  } catch (...) {  // from tick: the works stop before it goes on up
    stop.store(true);
    joinAll();
    throw;
  }
  joinAll();
  if (failure) std::rethrow_exception(failure);
  return stopped;
}

bool parallelForTicking(int count, int threads, const std::function<void(int)>& body, double period,
                        const std::function<bool(int done)>& tick) {
  std::atomic<int> next{0}, done{0};
  auto items = [&](int, const std::atomic<bool>& stop) {
    for (int k = 0; !stop.load() && (k = next.fetch_add(1)) < count;) {
      body(k);
      done.fetch_add(1);
    }
  };
  const bool stopped = runTicking(std::min(threadCount(threads), std::max(1, count)), items, period,
                                  [&] { return tick(done.load()); });
  if (!stopped) tick(done.load());
  return done.load() == count;
}

}  // namespace art2part
