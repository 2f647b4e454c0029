// Request ranges (issue 18 item 7): NaN, infinity, negatives and unit slips refused with a reason that names the
// field, the range and the unit; 0 (the default) and sensible values accepted.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "art2part/common/request_limits.h"
#include "art2part/geometry/mesh.h"

using namespace art2part;
namespace limits = art2part::request_limits;

TEST(RequestLimits, RefusesNanInfinityNegativesAndUnitSlips) {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const struct {
    double value;
    RequestRange range;
  } refused[] = {
      {5.0, limits::kStepdown},             // 5 m of step-down
      {0.3, limits::kAllowance},            // 0.3 mm typed as metres
      {-0.001, limits::kAllowance},         // negative
      {nan, limits::kChordalTolerance},     // NaN
      {0.1, limits::kChordalTolerance},     // 0.1 mm typed as metres
      {nan, limits::kTrajectoryRate},       // run_program rate NaN
      {-5, limits::kTrajectoryRate},        // run_program rate -5
      {inf, limits::kTrajectoryRate},       // infinity
      {0.0002, limits::kVerifyResolution},  // 0.2 mm typed as metres in an mm field
      {500, limits::kStockMargin},          // half a metre of stock margin
      {-inf, limits::kSetupTimeLimit},
      {8, limits::kSphereLevel},
      {1e9, limits::kRenderResolution},
      {0.01, limits::kScallop},             // 10 mm of scallop
  };
  for (const auto& r : refused) {
    const std::string reason = rangeViolation(r.value, r.range);
    EXPECT_FALSE(reason.empty()) << r.range.field << " " << r.value;
    EXPECT_EQ(reason.rfind(r.range.field, 0), 0u) << reason;  // starts with the field's name
    EXPECT_NE(reason.find("out of range"), std::string::npos) << reason;
    EXPECT_THROW(checkedRequestValue(r.value, r.range), InputError);
  }
  EXPECT_NE(rangeViolation(5.0, limits::kStepdown).find("metres"), std::string::npos);
  EXPECT_NE(rangeViolation(0.0002, limits::kVerifyResolution).find("mm"), std::string::npos);
}

TEST(RequestLimits, AcceptsDefaultsAndSensibleValues) {
  const struct {
    double value;
    RequestRange range;
  } accepted[] = {
      {0, limits::kStepdown},          {0.002, limits::kStepdown},        {0.0003, limits::kAllowance},
      {0, limits::kChordalTolerance},  {0.00001, limits::kChordalTolerance}, {50, limits::kTrajectoryRate},
      {0.2, limits::kVerifyResolution}, {2, limits::kStockMargin},        {110, limits::kMaxTilt},
      {5, limits::kSetupTimeLimit},    {4, limits::kSphereLevel},         {1024, limits::kRenderResolution},
      {0.00001, limits::kScallop},     {0.01, limits::kVerifyTolerance},
  };
  for (const auto& a : accepted) {
    EXPECT_EQ(rangeViolation(a.value, a.range), "") << a.range.field << " " << a.value;
    EXPECT_EQ(checkedRequestValue(a.value, a.range), a.value);
  }
}

// Every range admits its own bounds and nothing just outside them.
TEST(RequestLimits, BoundsAreInclusive) {
  for (const RequestRange& r :
       {limits::kChordalTolerance, limits::kSphereLevel, limits::kRenderResolution, limits::kMaxTilt,
        limits::kSetupTimeLimit, limits::kAllowance, limits::kStepdown, limits::kScallop, limits::kVerifyResolution,
        limits::kVerifyTolerance, limits::kStockMargin, limits::kTrajectoryRate}) {
    EXPECT_LT(0, r.smallest) << r.field;
    EXPECT_LE(r.smallest, r.largest) << r.field;
    EXPECT_EQ(rangeViolation(r.smallest, r), "") << r.field;
    EXPECT_EQ(rangeViolation(r.largest, r), "") << r.field;
    EXPECT_NE(rangeViolation(r.largest * 1.001, r), "") << r.field;
    EXPECT_NE(rangeViolation(r.smallest * 0.999, r), "") << r.field;
    EXPECT_NE(rangeViolation(-r.smallest, r), "") << r.field;
  }
}
