// One goal at a time in a stage node's action server: a goal that arrives while one runs waits for it instead of
// preempting it (actionlib's SimpleActionServer asks the running goal to preempt whenever a new goal comes; the stage
// nodes do not), so a client calling a stage alone never cancels the cell supervisor's goal. SimpleActionServer keeps
// one waiting goal: a newer one replaces it (the replaced one ends preempted, actionlib's rule). Only a cancel stops
// the running goal; a cancel that comes while another goal waits is taken for that goal's arrival (actionlib does not
// tell them apart) and the running goal runs to its end.
#pragma once

namespace art2part {

// True when the running goal of `server` (an actionlib::SimpleActionServer) was cancelled by its client.
template <class Server>
bool cancelAsked(Server& server) {
  return server.isPreemptRequested() && !server.isNewGoalAvailable();
}

}  // namespace art2part
