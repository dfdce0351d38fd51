#pragma once
// A GoogleTest environment that starts a private Xvfb for the whole test program when there is
// no display (the render tests: Debian's VTK renders through GLX only). Register it once per
// test program: ::testing::AddGlobalTestEnvironment(new test::XEnvironment).
#include <gtest/gtest.h>

#include <memory>

#include "trainsim/camera/x_display.hpp"

namespace trainsim::test {

class XEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { display_ = camera::XDisplay::ensure(); }
  void TearDown() override { display_.reset(); }

 private:
  std::unique_ptr<camera::XDisplay> display_;
};

}  // namespace trainsim::test
