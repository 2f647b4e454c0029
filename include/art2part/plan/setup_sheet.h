// The setup sheet: what the machinist at the machine reads, one self-contained HTML file of a plan folder (pictures
// inline, no links out). Per setup: its picture (the part seen along the setup direction, what this setup machines in
// its colour), its frame, how to clamp it, the tools it loads (stickout, holder) and its operations in order (tool,
// strategy, feed, speed, estimated time); then the simulation's figures with the pictures of what is left, the
// machining time and the tool changes. Built from the folder's files alone (plan.json, tools.json, the PNGs), so a
// sheet can be made again from any plan folder.
#pragma once

#include <string>

#include "art2part/plan/plan_part.h"

namespace art2part {

// setup_<k>.png in `dir`: the part seen along setup k's direction, what setup k machines in its colour, the rest grey.
// Throws InputError when a file cannot be written.
void writeSetupPictures(const std::string& dir, const Part& part, const SetupPlan& setups);

// The HTML of the sheet for the plan folder `dir` (reads plan.json and tools.json; embeds setup_<k>.png, setups.png and
// remaining.png when present). Throws InputError when plan.json or tools.json cannot be read.
std::string setupSheetHtml(const std::string& dir);

// Writes dir/setup_sheet.html. Throws InputError as above or when it cannot be written.
void writeSetupSheet(const std::string& dir);

}  // namespace art2part
