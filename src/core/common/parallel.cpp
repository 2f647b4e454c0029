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

bool parallelForTicking(int count, int threads, const std::function<void(int)>& body, double period,
                        const std::function<bool(int done)>& tick) {
  const int n = std::min(threadCount(threads), std::max(1, count));
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};
  bool stopped = false;  // tick said so
  std::mutex mutex;
  std::condition_variable changed;
  int done = 0, running = n;
  std::exception_ptr failure;
  auto work = [&] {
    for (;;) {
      if (stop.load()) break;
      const int k = next.fetch_add(1);
      if (k >= count) break;
      try {
        body(k);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        stop.store(true);
      }
      std::lock_guard<std::mutex> lock(mutex);
      ++done;
      changed.notify_one();
    }
    std::lock_guard<std::mutex> lock(mutex);
    --running;
    changed.notify_one();
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < n; ++t) pool.emplace_back(work);
  try {
    std::unique_lock<std::mutex> lock(mutex);
    const auto wait = std::chrono::duration<double>(period);
    while (running > 0) {
      if (changed.wait_for(lock, wait, [&] { return running == 0; })) break;
      if (stopped) continue;  // the items running finish, unreported
      const int now = done;
      lock.unlock();
      if (!tick(now)) {
        stopped = true;
        stop.store(true);
      }
      lock.lock();
    }
  } catch (...) {  // from tick: the workers stop before it goes on up
    stop.store(true);
    for (std::thread& thread : pool) thread.join();
    throw;
  }
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
  if (!stopped) tick(done);
  return done == count;
}

}  // namespace art2part
