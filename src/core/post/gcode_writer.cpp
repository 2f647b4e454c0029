// G-code text for LinuxCNC 2.9 from a MachineProgram: header, modal set-up, steps, program end; and the tool table.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "art2part/post/gcode.h"
#include "program_builder.h"

namespace art2part {

using namespace post_detail;

std::string gcodeNumber(double value, int decimals) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  std::string text(buffer, result.ptr);
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

namespace {

constexpr int kLineStep = 10;

// A comment's text: rs274ngc comments end at the first ')' and cannot nest.
std::string commentText(std::string text) {
  for (char& c : text) {
    if (c == '(') c = '[';
    if (c == ')') c = ']';
    if (c == '\n' || c == '\r') c = ' ';
  }
  return "(" + text + ")";
}

std::string vectorText(const Vec3& v, double scale = 1, int decimals = 3) {
  return "[" + gcodeNumber(v.x() * scale, decimals) + " " + gcodeNumber(v.y() * scale, decimals) + " " +
         gcodeNumber(v.z() * scale, decimals) + "]";
}

std::string fixtureText(const FixturePose& fixture) {
  return "part frame at " + vectorText(fixture.origin) + " mm in the table frame, rpy " +
         vectorText(rpyFromRotation(fixture.rotation), 1 / kDegree) + " deg";
}

std::string toolText(const PostTool& tool) {
  return "T" + std::to_string(tool.number) + " = " + tool.tool.id + ": " + toolTypeName(tool.tool.type) + " D" +
         gcodeNumber(tool.tool.diameter, 3) + " length " + gcodeNumber(tool.length, 3) + " mm, S" +
         gcodeNumber(tool.tool.spindle_rpm, 0) + " F" + gcodeNumber(tool.tool.feed_mm_min, 0) + " plunge F" +
         gcodeNumber(tool.tool.plunge_mm_min, 0);
}

class GcodeWriter {
 public:
  explicit GcodeWriter(const MachineProgram& program)
      : program_(program), machine_(program.machine), joints_(program.start),
        words_(machine_.joints.size()) {}

  void header(const std::vector<int>& setup_indices) {
    out_ += "%\n";
    comment("art2part post for LinuxCNC 2.9 [rs274ngc]");
    comment("part: " + program_.part_name);
    comment("machine: " + machine_.name + " - " + machine_.description + " - kinematics " +
            kinematicsModuleName(machine_.kind));
    comment("run under identity kinematics [M429 on the LinuxCNC sim] with G54 and G92 zero: X Y Z = joints - "
            "tool length in Z, rotary words = joints in degrees");
    comment(program_.mode == PostMode::FiveAxis
                ? "mode: 5-axis, joint moves subdivided to " + gcodeNumber(program_.options.chordal_tolerance, 4) +
                      " mm of the toolpath, G61 exact path; G93 inverse time on moves that turn a rotary"
                : "mode: 3+2, rotaries positioned once per setup, then X Y Z moves blended within G64 P");
    for (int index : setup_indices) {
      const SetupProgram& setup = program_.setups.at(index);
      std::string tools;
      for (int number : setup.tools) tools += " T" + std::to_string(number);
      comment("setup " + std::to_string(setup.setup) + ": " + fixtureText(setup.fixture) + "; tools" + tools);
    }
    for (const PostTool& tool : usedTools(setup_indices)) comment(toolText(tool));
    comment("safe height: G53 Z" + gcodeNumber(program_.retract_z, 3) + " [gauge point, machine coordinates]");
  }

  // The path mode. 3+2: G64 P<chordal tolerance>, blending corners within it: the rotaries stand still while cutting
  // and X Y Z are the tip (plus the tool length in Z), so P bounds the tip. 5-axis: G61, exact path. Under identity
  // kinematics LinuxCNC's G64 P bounds only the X Y Z joints' corner blends, not the rotaries nor the tip: on the
  // xyzac-trt sim, G64 P0.005 took the joints 0.014 mm / 0.033 deg off the post's joint path and the tip 0.007 mm off
  // (test/linuxcnc/run_sim_test.sh); G61 keeps to the joint path (0.0002 mm) for 6% more time.
  std::string pathMode() const {
    if (program_.mode == PostMode::FiveAxis) return "G61";
    return "G64 P" + gcodeNumber(program_.options.chordal_tolerance, 4);
  }

  void modalSetup() {
    line("G21 G17 G40 G49 G80 G90 G94 " + pathMode());
    std::string zero = "G10 L2 P1";
    for (const Joint& joint : machine_.joints) zero += " " + joint.name + "0";
    line(zero);
    line("G92.1");
    line("G54");
    for (const std::string& text : program_.options.preamble) line(text);
    feed_mode_ = FeedMode::UnitsPerMinute;
  }

  void setupBody(const SetupProgram& setup) {
    comment("setup " + std::to_string(setup.setup) + ": " + fixtureText(setup.fixture));
    printed_cycle_ = -1;
    for (const ProgramStep& step : setup.steps) {
      if (!step.comment.empty()) comment(step.comment);
      if (step.cycle >= 0) {
        cycleStep(setup.cycles.at(step.cycle), step);
        continue;
      }
      endCycles();
      switch (step.kind) {
        case StepKind::Retract: retract(step); break;
        case StepKind::ToolChange: toolChange(step); break;
        case StepKind::Move: move(step); break;
      }
    }
  }

  void programStop(const std::string& why) {
    endCycles();
    line("M9");
    line("M5");
    line("M0 " + commentText(why));
  }

  std::string end() {
    endCycles();
    line("M9");
    line("M5");
    line("M30");
    out_ += "%\n";
    return out_;
  }

 private:
  enum class FeedMode { UnitsPerMinute, InverseTime };

  std::vector<PostTool> usedTools(const std::vector<int>& setup_indices) const {
    std::vector<PostTool> tools;
    for (const PostTool& tool : program_.tools)
      for (int index : setup_indices) {
        const auto& numbers = program_.setups.at(index).tools;
        if (std::find(numbers.begin(), numbers.end(), tool.number) != numbers.end()) {
          tools.push_back(tool);
          break;
        }
      }
    return tools;
  }

  void line(const std::string& words) {
    line_ += kLineStep;
    out_ += "N" + std::to_string(line_) + " " + words + "\n";
  }
  void comment(const std::string& text) { line(commentText(text)); }

  // The axis words of `joints` that differ from the last ones written (all after a tool change); remembers them.
  std::string axisWords(const JointPosition& joints, bool* rotary_moves) {
    const Vec3 xyz = programXyz(joints, tool_length_);
    const std::vector<double> values = jointVector(machine_, joints);
    std::string words;
    for (int j = 0; j < machine_.jointCount(); ++j) {
      const Joint& joint = machine_.joints[j];
      const std::string number = joint.rotary ? gcodeNumber(values[j] / kDegree) : gcodeNumber(xyz[j]);
      if (number == words_[j]) continue;
      words_[j] = number;
      words += " " + joint.name + number;
      if (joint.rotary && rotary_moves) *rotary_moves = true;
    }
    return words;
  }

  void retract(const ProgramStep& step) {
    line("G53 G0 Z" + gcodeNumber(step.joints.linear.z()));
    joints_ = step.joints;
    words_[2] = gcodeNumber(programXyz(joints_, tool_length_).z());
  }

  void toolChange(const ProgramStep& step) {
    const PostTool& tool = program_.tool(step.tool);
    line("M9");
    line("M5");
    line("T" + std::to_string(tool.number) + " M6");
    line("G43 H" + std::to_string(tool.number));
    line("S" + gcodeNumber(tool.tool.spindle_rpm, 0) + " M3");
    line("M8");
    tool_length_ = tool.length;
    std::fill(words_.begin(), words_.end(), std::string());  // the program coordinates moved: write every word
  }

  // Inverse time: 1 / the move's minutes, the minutes being the longer of the tip at its feed and the slowest
  // joint at its maximum velocity.
  double inverseTimeFeed(const ProgramStep& step) const {
    double seconds = step.feed_mm_min > 0 ? 60 * step.tip_length / step.feed_mm_min : 0.0;
    const std::vector<double> from = jointVector(machine_, joints_), to = jointVector(machine_, step.joints);
    for (int j = 0; j < machine_.jointCount(); ++j)
      seconds = std::max(seconds, std::abs(to[j] - from[j]) / machine_.joints[j].max_velocity);
    return 60 / seconds;
  }

  void move(const ProgramStep& step) {
    bool rotary_moves = false;
    const std::string words = axisWords(step.joints, &rotary_moves);
    if (words.empty()) {  // nothing moves at the program's resolution
      joints_ = step.joints;
      return;
    }
    if (step.move == MoveKind::Rapid) {
      line("G0" + words);
    } else if (rotary_moves) {
      const std::string mode = feed_mode_ == FeedMode::InverseTime ? "" : "G93 ";
      feed_mode_ = FeedMode::InverseTime;
      last_feed_ = std::numeric_limits<double>::quiet_NaN();
      line(mode + "G1" + words + " F" + gcodeNumber(inverseTimeFeed(step), 6));
    } else {
      std::string mode;
      if (feed_mode_ != FeedMode::UnitsPerMinute) mode = "G94 ";
      feed_mode_ = FeedMode::UnitsPerMinute;
      const std::string feed = gcodeNumber(step.feed_mm_min, 3);
      const bool new_feed = !(last_feed_ == step.feed_mm_min);
      last_feed_ = step.feed_mm_min;
      line(mode + "G1" + words + (new_feed ? " F" + feed : std::string()));
    }
    joints_ = step.joints;
  }

  // A canned cycle's one line, at its first step; its other steps are the motion the line makes.
  void cycleStep(const DrillCycle& cycle, const ProgramStep& step) {
    if (step.cycle != printed_cycle_) {
      printed_cycle_ = step.cycle;
      const Vec3 xyz = programXyz(cycle.bottom, tool_length_);
      std::string words = std::string(feed_mode_ == FeedMode::UnitsPerMinute ? "" : "G94 ") +
                          (cycle.retract_to_start ? "G98" : "G99") + (cycle.peck > 0 ? " G83" : " G81");
      for (int c = 0; c < 3; ++c) {
        words_[c] = gcodeNumber(c == 2 ? cycle.clear_z - tool_length_ : xyz[c]);
        words += " " + machine_.joints[c].name + gcodeNumber(xyz[c]);
      }
      words += " R" + gcodeNumber(cycle.r_z - tool_length_);
      if (cycle.peck > 0) words += " Q" + gcodeNumber(cycle.peck);
      words += " F" + gcodeNumber(cycle.feed_mm_min, 3);
      line(words);
      feed_mode_ = FeedMode::UnitsPerMinute;
      last_feed_ = cycle.feed_mm_min;
      in_cycles_ = true;
    }
    joints_ = step.joints;
  }

  // G80 after canned cycles, before anything else moves.
  void endCycles() {
    if (!in_cycles_) return;
    line("G80");
    in_cycles_ = false;
  }

  const MachineProgram& program_;
  const Machine& machine_;
  std::string out_;
  int line_ = 0;
  double tool_length_ = 0;
  JointPosition joints_;
  std::vector<std::string> words_;  // the last number written per joint ("" = unknown)
  FeedMode feed_mode_ = FeedMode::UnitsPerMinute;
  double last_feed_ = std::numeric_limits<double>::quiet_NaN();
  int printed_cycle_ = -1;  // the setup's cycle whose line is out
  bool in_cycles_ = false;  // a canned cycle is the motion mode (G80 cancels it)
};

}  // namespace

std::string jobProgramText(const MachineProgram& program) {
  GcodeWriter writer(program);
  std::vector<int> all(program.setups.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  writer.header(all);
  writer.modalSetup();
  for (size_t i = 0; i < program.setups.size(); ++i) {
    if (i > 0) {
      const SetupProgram& next = program.setups[i];
      writer.programStop("re-fixture for setup " + std::to_string(next.setup) + ": " + fixtureText(next.fixture) +
                         "; then cycle start");
    }
    writer.setupBody(program.setups[i]);
  }
  return writer.end();
}

std::string setupProgramText(const MachineProgram& program, int setup_index) {
  GcodeWriter writer(program);
  writer.header({setup_index});
  writer.modalSetup();
  writer.setupBody(program.setups.at(setup_index));
  return writer.end();
}

std::string toolTableText(const MachineProgram& program, ToolTableUnits units) {
  const double scale = units == ToolTableUnits::Inches ? 1 / 25.4 : 1.0;
  std::string text;
  for (const PostTool& tool : program.tools) {
    text += "T" + std::to_string(tool.number) + " P" + std::to_string(tool.number) + " Z" +
            gcodeNumber(tool.length * scale, 6) + " D" + gcodeNumber(tool.tool.diameter * scale, 6) + " ;" +
            tool.tool.id + " " + toolTypeName(tool.tool.type) + (units == ToolTableUnits::Inches ? " [inch]" : "") +
            "\n";
  }
  return text;
}

}  // namespace art2part
