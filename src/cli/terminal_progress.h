// The CLI's side of the progress contract (progress.h): what a long command shows while it works.
#pragma once

#include "art2part/common/progress.h"

namespace art2part {

// On a terminal (stderr), the stage, its share done and what it works on, one line rewritten in place at most four
// times a second; on a pipe or a file, none (a log should not fill with carriage returns). Never asks to stop.
ProgressSink terminalProgress();

// Clears the line terminalProgress wrote, when it wrote one.
void endTerminalProgress(const ProgressSink& progress);

}  // namespace art2part
