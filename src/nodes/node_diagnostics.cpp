#include "node_diagnostics.h"

#include <cstdio>
#include <utility>

#include "art2part/geometry/mesh.h"

namespace art2part {

namespace {

const char* outcomeName(RequestOutcome outcome) {
  switch (outcome) {
    case RequestOutcome::Served: return "served";
    case RequestOutcome::Refused: return "refused";
    case RequestOutcome::Failed: return "failed";
    case RequestOutcome::Cancelled: return "cancelled";
  }
  return "?";
}

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", s);
  return text;
}

}  // namespace

RequestOutcome outcomeOf(const std::exception& error) {
  return dynamic_cast<const InputError*>(&error) ? RequestOutcome::Refused : RequestOutcome::Failed;
}

NodeDiagnostics::NodeDiagnostics() {
  updater_.setHardwareID("none");  // a software node: no device
  updater_.add("requests", [this](diagnostic_updater::DiagnosticStatusWrapper& status) { report(status); });
  timer_ = ros::NodeHandle().createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    std::lock_guard<std::mutex> lock(updater_mutex_);
    updater_.update();
  });
}

void NodeDiagnostics::setConfiguration(const std::string& key, const std::string& value) {
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    configuration_.emplace_back(key, value);
  }
  publishNow();
}

void NodeDiagnostics::addProblem(const std::string& problem) {
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    problems_.push_back(problem);
  }
  publishNow();
}

NodeDiagnostics::Request::Request(NodeDiagnostics& owner, std::string name)
    : owner_(owner), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {
  owner_.begin();
}

NodeDiagnostics::Request::~Request() {
  if (!finished_) finish(RequestOutcome::Failed, "ended without an answer");
}

void NodeDiagnostics::Request::finish(RequestOutcome outcome, const std::string& message) {
  if (finished_) return;
  finished_ = true;
  owner_.end(name_, outcome, message,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
}

void NodeDiagnostics::begin() {
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ++running_;
  }
  publishNow();
}

void NodeDiagnostics::end(const std::string& request, RequestOutcome outcome, const std::string& message,
                          double seconds) {
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    --running_;
    ++counts_[outcome];
    any_request_ = true;
    last_request_ = request;
    last_outcome_ = outcome;
    last_message_ = message;
    last_seconds_ = seconds;
  }
  publishNow();
}

void NodeDiagnostics::report(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  using Status = diagnostic_msgs::DiagnosticStatus;
  const std::string state = running_ > 0 ? "busy" : "idle";
  const std::string last = any_request_ ? "; last " + last_request_ + " " + outcomeName(last_outcome_) +
                                              (last_message_.empty() ? "" : ": " + last_message_)
                                        : "; no request yet";
  unsigned char level = Status::OK;
  if (any_request_ && last_outcome_ == RequestOutcome::Refused) level = Status::WARN;
  if (any_request_ && last_outcome_ == RequestOutcome::Failed) level = Status::ERROR;
  std::string message = state + last;
  if (!problems_.empty()) {
    level = Status::ERROR;
    message = problems_.front() + (problems_.size() > 1 ? " (and more)" : "") + "; " + message;
  }
  status.summary(level, message);
  status.add("state", state);
  status.add("running requests", running_);
  for (RequestOutcome o :
       {RequestOutcome::Served, RequestOutcome::Refused, RequestOutcome::Failed, RequestOutcome::Cancelled})
    status.add(outcomeName(o), counts_.count(o) ? counts_.at(o) : 0L);
  if (any_request_) {
    status.add("last request", last_request_);
    status.add("last outcome", outcomeName(last_outcome_));
    status.add("last message", last_message_);
    status.add("last seconds", seconds(last_seconds_));
  }
  for (const auto& [key, value] : configuration_) status.add(key, value);
  for (const std::string& problem : problems_) status.add("problem", problem);
}

void NodeDiagnostics::publishNow() {
  std::lock_guard<std::mutex> lock(updater_mutex_);
  updater_.force_update();
}

}  // namespace art2part
