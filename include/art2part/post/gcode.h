// G-code for LinuxCNC 2.9 (rs274ngc) from a MachineProgram, and the tool table it needs.
//
// Each program: a header of comments (part, setup(s) and their fixtures, machine and kinematics, mode, tools), the
// modal set-up `G21 G17 G40 G49 G80 G90 G94` with the path mode (3+2: `G64 P<chordal tolerance>`; 5-axis: `G61`, exact
// path, since under identity kinematics G64 P bounds only the X Y Z joints' blends, not the rotaries nor the tip), G54
// set to zero and G92 cancelled, then the steps:
//   retract     G53 G0 Z<retract_z>                       (machine Z of the gauge point)
//   tool change M9 / M5 / T<n> M6 / G43 H<n> / S<rpm> M3 / M8
//   rapid       G0 X Y Z A C                               (only the words that change)
//   feed        G94 G1 X Y Z F<mm/min>                    when no rotary joint moves
//               G93 G1 X Y Z A C F<1/min>                 when one does: inverse time, 1 / the move's minutes, the
//                                                         minutes being max(tip length / feed, slowest joint at its
//                                                         max velocity)
//   drilling    G98 G81 X Y Z R F  /  G98 G83 X Y Z R Q F  (G99 when it retracts to R), once for all the steps of
//               the cycle; G80 before the next line that is not a cycle
// and M9 M5 M30 at the end. Lines are numbered N10, N20, ...; numbers are fixed-point (4 decimals: 0.1 um, 1e-4 deg).
// The job program (program.ngc of the plan contract) runs every setup in order with `M0 (re-fixture: ...)` between
// them; a setup program runs one setup alone.
#pragma once

#include <string>

#include "art2part/post/machine_program.h"

namespace art2part {

// Every setup in order: the program.ngc of the plan contract.
std::string jobProgramText(const MachineProgram& program);
// One setup (index into program.setups), standalone: its own header, tool change and M30.
std::string setupProgramText(const MachineProgram& program, int setup_index);

enum class ToolTableUnits {
  Millimetres,  // for LinuxCNC with a mm machine (LINEAR_UNITS = mm): the controller's own table
  Inches,       // for the stand-alone rs274 interpreter, which reads tool tables in inches whatever the program
};
// LinuxCNC tool table: `T<n> P<n> Z<length> D<diameter> ;<id> <type>` a line.
std::string toolTableText(const MachineProgram& program, ToolTableUnits units);

// A number as G-code writes it: fixed point, `decimals` places, no "-0".
std::string gcodeNumber(double value, int decimals = 4);

}  // namespace art2part
