// How a stage node gets its part: by id from part_server's get_part, rebuilt into the core Part once and cached.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "art2part/geometry/part.h"

namespace art2part {

class PartClient {
 public:
  // The part with this id (empty: the part server's last loaded). Throws InputError with the server's reason when
  // the server does not know the id or is not running.
  std::shared_ptr<const Part> get(const std::string& part_id, std::string* resolved_id = nullptr);

 private:
  std::map<std::string, std::shared_ptr<const Part>> cache_;
};

}  // namespace art2part
