// The progress and cancel contract every long stage keeps: it reports which stage it is in, how far through (0..1)
// and what it is doing, at least once a second while it works; the sink answers whether to go on. A stage asked to
// stop returns what it finished so far, flagged as cancelled, within a second; it throws nothing because of it.
#pragma once

#include <functional>
#include <string>

namespace art2part {

struct ProgressReport {
  std::string stage;    // "visibility", "setups", "roughing", "finishing", "verification", "post"
  double fraction = 0;  // of the stage's work, 0..1, never decreasing within a stage
  std::string message;  // what it works on now, one line ("setup 2 of 3: face milling, flat10")
  long done = 0;        // units of work finished in the stage when it counts them (roughing: levels), else 0
};

// Returns false to ask the stage to stop. An empty sink means: never stop, nobody listens.
using ProgressSink = std::function<bool(const ProgressReport&)>;

// Calls `sink` when there is one; true (go on) when there is none.
inline bool reportProgress(const ProgressSink& sink, const std::string& stage, double fraction,
                           const std::string& message, long done = 0) {
  return !sink || sink(ProgressReport{stage, fraction, message, done});
}

}  // namespace art2part
