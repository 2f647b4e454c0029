#include "art2part/common/parallel.h"

#include <algorithm>
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

}  // namespace art2part
