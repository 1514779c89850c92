// Test helper: the message of the cmbrl::Error a call throws.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "cmbrl/core/check.h"

namespace cmbrl::testing {

// Runs `call`; returns the message of the cmbrl::Error it throws, and fails the test (returning
// "") when it throws nothing.
template <typename Call>
std::string ErrorMessage(Call&& call) {
  try {
    call();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a cmbrl::Error";
  return "";
}

}  // namespace cmbrl::testing
