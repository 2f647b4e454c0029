// A URDF of a machine model (machine.h), generated from its YAML: what robot_state_publisher needs to turn the
// controller's sensor_msgs/JointState into tf frames, and rviz to draw the machine moving with the part on its table.
//
// Units and names are ROS's: metres and radians; each URDF joint is named as the machine's joint (its G-code letter,
// X Y Z A B C), so that the simulated controller's joint_states drive it directly. The kinematic tree reproduces
// forwardKinematics() exactly (the same frames as inverse_kinematics.h, scaled from mm to m):
//   base_link            the machine frame (fixed; origin at machine zero)
//   x_slide, y_slide     prismatic X along x, Y along y (the spindle side carries the three slides: only the relative
//   z_slide              motion of tool and table matters); z_slide's origin is the spindle gauge point
//   table-table (xyzac-trt, xyzbc-trt):
//     tilt_axis          fixed at rot_point + offset
//     trunnion           revolute A about +x (or B about +y) on tilt_axis
//     platter            revolute (continuous when its travel is a turn or more) C about +z at rot_point
//     table              the table frame (the platter shifted by -rot_point): the machine frame when A/B = C = 0
//   head-head (5axiskins):
//     pivot              fixed pivot_length above the gauge point (on z_slide)
//     head_c             revolute C about +z
//     head_b             revolute B about -y (tool axis R_z(C) R_y(-B) z, as 5axiskins)
//     spindle            the tilted spindle's gauge point, pivot_length below the pivot along the head's -z
//     table              fixed = base_link
//   3-axis: table fixed = base_link
//   part                 fixed on table at the fixture pose (the part frame of toolpaths.csv; part_server's frame)
// Joint limits: the YAML travel (lower/upper) and max_velocity; the effort is a placeholder (URDF requires it) and
// URDF has no acceleration limit. Visuals are simple boxes and cylinders sized from the travel.
#pragma once

#include <optional>
#include <string>

#include "art2part/kinematics/machine.h"

namespace art2part {

struct UrdfOptions {
  int setup = -1;                  // the fixture of this setup (toolpaths.csv index); -1: the machine's default
  std::string part_frame = "part";  // the name of the part's link
  std::optional<FixturePose> fixture;  // the part's pose on the table (a plan's); unset: the machine file's of `setup`
};

// The URDF text (XML) of the machine, robot name = machine.name.
std::string machineUrdf(const Machine& machine, const UrdfOptions& options = {});

// The ROS name of a joint (URDF joint, JointState / JointTrajectory name): the machine's joint letter.
inline const std::string& rosJointName(const Joint& joint) { return joint.name; }

}  // namespace art2part
