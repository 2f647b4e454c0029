// What every node's main does: ros::init as `name`, a Node(nh, pnh) serving with `threads` spinner threads (goals,
// cancels and services arrive while a request works) until shutdown. A node whose construction throws (a bad
// parameter) logs one ROS_FATAL line and exits 1.
#pragma once

#include <ros/ros.h>

#include <chrono>
#include <exception>

namespace art2part {

template <class Node>
int runNode(int argc, char** argv, const char* name, int threads) {
  ros::init(argc, argv, name);
  ros::NodeHandle nh, pnh("~");
  try {
    Node node(nh, pnh);
    ros::AsyncSpinner spinner(threads);
    spinner.start();
    ros::waitForShutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", name, e.what());
    return 1;
  }
  return 0;
}

// Seconds of wall time since `start`, for a request's `seconds` field.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace art2part
