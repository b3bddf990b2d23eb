// What ended a case is named alike by every study (case_failure.h): a full disk or memory the system
// refuses is an environment failure (issue 53: sweep.csv called both "bad input"), a RunError a numerical
// failure at its time, anything else bad input.
#include "tools/output/atomic_file.h"
#include "tools/scene/scene_error.h"
#include "tools/studies/case_failure.h"
#include "engine/steppers/stepper.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <functional>
#include <new>

namespace csim {
namespace {

CaseFailure failure_of(const std::function<void()>& fail) {
  try {
    fail();
  } catch (const std::exception&) {
    return current_case_failure();
  }
  ADD_FAILURE() << "nothing thrown";
  return {};
}

TEST(CaseFailure, AFullDiskAndOutOfMemoryAreEnvironmentFailures) {
  const CaseFailure disk = failure_of([] {
    throw FileWriteError("out/case-0003/probes.csv", "cannot write", std::error_code(ENOSPC, std::generic_category()));
  });
  EXPECT_EQ(disk.kind, CaseFailureKind::environment_failure);
  EXPECT_EQ(disk.message, "out/case-0003/probes.csv: cannot write: No space left on device");
  EXPECT_STREQ(case_failure_status(disk.kind), "environment failure");
  const CaseFailure memory = failure_of([] { throw std::bad_alloc(); });
  EXPECT_EQ(memory.kind, CaseFailureKind::environment_failure);
  EXPECT_NE(memory.message.find("out of memory"), std::string::npos) << memory.message;
  EXPECT_TRUE(std::isnan(memory.time));
}

TEST(CaseFailure, ARunErrorIsNumericalAndTheRestBadInput) {
  const CaseFailure numerical = failure_of([] { throw RunError(0.677, "the contact solver failed"); });
  EXPECT_EQ(numerical.kind, CaseFailureKind::numerical_failure);
  EXPECT_EQ(numerical.time, 0.677);
  EXPECT_EQ(numerical.message, "numerical failure at t = 0.677 s: the contact solver failed");
  EXPECT_STREQ(case_failure_status(numerical.kind), "numerical failure");
  const CaseFailure scene = failure_of([] { throw SceneError("scene.yaml", 12, "parameters.mu", "must be >= 0"); });
  EXPECT_EQ(scene.kind, CaseFailureKind::bad_input);
  EXPECT_EQ(scene.message, "scene.yaml:12: parameters.mu: must be >= 0");
  EXPECT_STREQ(case_failure_status(scene.kind), "bad input");
}

}  // namespace
}  // namespace csim
