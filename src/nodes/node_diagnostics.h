// /diagnostics for a node (diagnostic_msgs/DiagnosticArray through diagnostic_updater), the same for every node: one
// status "<node>: requests" once a second and at every request's start and end, with
//   level    ERROR when the node's configuration has a problem or the last request failed in the node;
//            WARN when the last request was refused (the caller's input); OK otherwise
//   message  busy or idle, and the last request's outcome
//   values   served / refused / failed / cancelled counts, running requests, the last request, its outcome and
//            seconds, and what the node was configured with (folders, machine...)
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <chrono>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace art2part {

// How a request ended.
enum class RequestOutcome { Served, Refused, Failed, Cancelled };

// Refused for an InputError (the request was bad), Failed for anything else.
RequestOutcome outcomeOf(const std::exception& error);

class NodeDiagnostics {
 public:
  NodeDiagnostics();
  NodeDiagnostics(const NodeDiagnostics&) = delete;
  NodeDiagnostics& operator=(const NodeDiagnostics&) = delete;

  // A key/value shown with every status (what the node runs with).
  void setConfiguration(const std::string& key, const std::string& value);
  // A standing problem of the node's set-up: the status is ERROR while the node runs.
  void addProblem(const std::string& problem);

  // One request, from its start to its outcome: the node is busy while one lives. A request destroyed without an
  // outcome counts as failed ("ended without an answer").
  class Request {
   public:
    Request(NodeDiagnostics& owner, std::string name);
    ~Request();
    Request(const Request&) = delete;
    Request& operator=(const Request&) = delete;
    // How it ended, with the reply's message; the first call counts.
    void finish(RequestOutcome outcome, const std::string& message);

   private:
    NodeDiagnostics& owner_;
    std::string name_;
    std::chrono::steady_clock::time_point start_;
    bool finished_ = false;
  };
  Request request(const std::string& name) { return Request(*this, name); }

 private:
  void begin();
  void end(const std::string& request, RequestOutcome outcome, const std::string& message, double seconds);
  void report(diagnostic_updater::DiagnosticStatusWrapper& status);
  void publishNow();

  std::mutex state_mutex_;  // everything below up to updater_mutex_
  std::map<RequestOutcome, long> counts_;
  int running_ = 0;
  std::string last_request_, last_message_;
  RequestOutcome last_outcome_ = RequestOutcome::Served;
  bool any_request_ = false;
  double last_seconds_ = 0;
  std::vector<std::pair<std::string, std::string>> configuration_;
  std::vector<std::string> problems_;

  std::mutex updater_mutex_;  // the updater is not thread-safe; requests run on several threads
  diagnostic_updater::Updater updater_;
  ros::WallTimer timer_;
};

}  // namespace art2part
