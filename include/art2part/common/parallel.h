// Work spread over the machine's cores: one loop form for every stage that runs independent items side by side.
#pragma once

#include <functional>

namespace art2part {

// `requested` threads, or the hardware's for 0 (at least 1).
int threadCount(int requested);

// Runs body(k) for k in [0, count) on `threads` threads (0 = the hardware's), k interleaved over the threads; on the
// calling thread alone when one thread (or one item) is all there is. The body must not throw.
void parallelFor(int count, int threads, const std::function<void(int)>& body);

}  // namespace art2part
