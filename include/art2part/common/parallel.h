// Work spread over the machine's cores: one loop form for every stage that runs independent items side by side.
#pragma once

#include <atomic>
#include <functional>

namespace art2part {

// `requested` threads, or the hardware's for 0 (at least 1).
int threadCount(int requested);

// Runs body(k) for k in [0, count) on `threads` threads (0 = the hardware's), k interleaved over the threads; on the
// calling thread alone when one thread (or one item) is all there is. The body must not throw.
void parallelFor(int count, int threads, const std::function<void(int)>& body);

// The one way a stage runs work that it reports on and may stop (visibility's directions, finishing's groups through
// parallelForTicking, the verification's sweep): work(t, stop) for t in [0, threads) (at least one), each on a thread
// of its own, while the calling thread calls tick() every `period` seconds until all have returned. A thread that
// cannot be started stops those running and its error is thrown once they have returned.
// Once tick returns false it is not called again and `stop` is raised: every work is to watch it and return soon. An
// exception from a work raises `stop` too and is rethrown here once every work has returned (the first one thrown),
// and so is one from tick. Returns whether tick stopped the work. tick is only ever called from the calling thread.
bool runTicking(int threads, const std::function<void(int t, const std::atomic<bool>& stop)>& work, double period,
                const std::function<bool()>& tick);

// For items of very different cost that a stage reports on while they run (progress.h): body(k) for k in [0, count)
// on `threads` worker threads (0 = the hardware's), each taking the next item when it finishes one, while the calling
// thread calls tick(done) every `period` seconds and once when all have stopped, `done` the items finished. Once tick
// returns false it is not called again and no item is started; those running finish. An exception from an item also
// stops new items from starting and is rethrown here after every worker has stopped (the first one thrown), and so
// is one from tick. Returns whether every item ran. tick is only ever called from the calling thread.
bool parallelForTicking(int count, int threads, const std::function<void(int)>& body, double period,
                        const std::function<bool(int done)>& tick);

}  // namespace art2part
