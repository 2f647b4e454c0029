#include "part_client.h"

#include <ros/ros.h>

#include <art2part/GetPart.h>

#include "part_conversions.h"

namespace art2part {

namespace {

GetPart::Response callGetPart(const std::string& part_id, bool summary_only) {
  GetPart srv;
  srv.request.part_id = part_id;
  srv.request.summary_only = summary_only;
  if (!ros::service::exists("get_part", false))
    throw InputError("part_server is not running (no get_part service)");
  if (!ros::service::call("get_part", srv)) throw InputError("get_part call failed");
  if (!srv.response.success) throw InputError(srv.response.message);
  return srv.response;
}

}  // namespace

std::shared_ptr<const Part> PartClient::get(const std::string& part_id, std::string* resolved_id) {
  // Ask for the summary first: the server may have reloaded the id with another file since we cached it.
  const GetPart::Response head = callGetPart(part_id, true);
  const std::string id = head.part.id;
  if (resolved_id) *resolved_id = id;
  auto it = cache_.find(id);
  if (it != cache_.end() && it->second->source == head.part.source &&
      it->second->mesh.triangleCount() == static_cast<int>(head.part.summary.triangles))
    return it->second;
  auto part = std::make_shared<const Part>(fromMsg(callGetPart(id, false).part));
  cache_[id] = part;
  return part;
}

}  // namespace art2part
