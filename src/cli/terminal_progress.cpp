#include "terminal_progress.h"

#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include <unistd.h>

namespace art2part {

ProgressSink terminalProgress() {
  using Clock = std::chrono::steady_clock;
  if (!isatty(STDERR_FILENO)) return {};
  auto last = std::make_shared<Clock::time_point>();
  auto last_stage = std::make_shared<std::string>();
  return [last, last_stage](const ProgressReport& p) {
    const auto now = Clock::now();
    if (p.stage == *last_stage && now - *last < std::chrono::milliseconds(250)) return true;
    *last = now;
    *last_stage = p.stage;
    std::string line = p.stage + " " + std::to_string(static_cast<int>(100 * p.fraction)) + "% " + p.message;
    if (line.size() > 110) line.resize(110);
    std::cerr << "\r\033[K" << line << std::flush;
    return true;
  };
}

void endTerminalProgress(const ProgressSink& progress) {
  if (progress) std::cerr << "\r\033[K" << std::flush;
}

}  // namespace art2part
