// Stage records: each stage's whole result as bytes, so the cell's stage nodes hand a stage's result to the next
// instead of recomputing it, and the supervisor assembles, from the records, the plan that planPart makes in one
// process — to the bit: the records keep the core's own fields in its own units (mm, doubles as IEEE float64), which
// the ROS messages' metres cannot (x * 1e-3 / 1e-3 differs from x in about 1 % of coordinates).
//
// A record is MessagePack (RFC-free, msgpack.org) of {"record": kind, "version": kRecordVersion, "data": ...}, the
// data named after the structs' fields (docs/contracts.md, "Stage records"). The nodes carry them in `uint8[] record`
// fields beside the typed fields a client reads. Readers throw InputError, naming the kind expected, for bytes that
// are not a record of that kind and version (another stage's record, a truncated message).
#pragma once

#include <cstdint>
#include <vector>

#include "art2part/geometry/part.h"
#include "art2part/plan/plan_part.h"
#include "art2part/tooling/tool.h"
#include "art2part/tooling/toolpath.h"

namespace art2part {

using RecordBytes = std::vector<std::uint8_t>;

constexpr int kRecordVersion = 1;

// The part as loaded (mesh, faces, repairs): what part_server hands every stage. The adjacency and the mesh check
// are rebuilt from the mesh (deterministic), with the sharp angle it was built with.
RecordBytes partRecord(const Part& part);
Part partFromRecord(const RecordBytes& bytes);

// Setups (planPartSetups): the cover and any added for finishing.
RecordBytes setupsRecord(const SetupPlan& plan);
SetupPlan setupsFromRecord(const RecordBytes& bytes);

// Roughing (planPartRoughing): the holes kept out of it, their methods, the operations and the stock each setup left.
RecordBytes roughingRecord(const RoughingStage& stage);
RoughingStage roughingFromRecord(const RecordBytes& bytes);

// Finishing (planPartFinishing): operations, every face's verdict, the holes as made.
RecordBytes finishingRecord(const FinishingPlan& plan);
FinishingPlan finishingFromRecord(const RecordBytes& bytes);

// A toolpath and its tools (what toolpaths.csv and tools.json hold, without the CSV's rounding).
struct ToolpathAndTools {
  Toolpath path;
  std::vector<Tool> tools;
};
RecordBytes toolpathRecord(const Toolpath& path, const std::vector<Tool>& tools);
ToolpathAndTools toolpathFromRecord(const RecordBytes& bytes);

// Verification options (all but stock_mesh, which stays with the caller, and threads, the machine's own).
RecordBytes verifyOptionsRecord(const VerifyOptions& options);
VerifyOptions verifyOptionsFromRecord(const RecordBytes& bytes);

// Verification (verifyToolpath's report).
RecordBytes verificationRecord(const VerificationReport& report);
VerificationReport verificationFromRecord(const RecordBytes& bytes);

}  // namespace art2part
