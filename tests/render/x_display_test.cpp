// The private Xvfb the cameras start when there is no display: it accepts every client, however
// quickly they come and go. Each renderer opens and closes its own connection, and a server that
// resets when its last client leaves refuses some of the next ones (4 to 11 in 1000 open-close
// cycles here without -noreset), which VTK answers by aborting the process.
#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "trainsim/camera/x_display.hpp"

// After GoogleTest: Xlib's macros (None, Bool) would break its headers.
#include <X11/Xlib.h>

namespace trainsim {
namespace {

TEST(XDisplay, APrivateServerAcceptsEveryClientThoughEachLeavesBeforeTheNextComes) {
  std::optional<std::string> outer;
  if (const char* d = std::getenv("DISPLAY"))
    outer = d;
  unsetenv("DISPLAY");  // so that ensure() starts a server of its own
  auto own = camera::XDisplay::ensure();
  ASSERT_NE(own, nullptr);
  ASSERT_EQ(std::getenv("DISPLAY"), own->name());
  int refused = 0;
  for (int i = 0; i < 1000; ++i) {
    Display* d = XOpenDisplay(own->name().c_str());
    if (d == nullptr) {
      ++refused;
      continue;
    }
    XCloseDisplay(d);
  }
  own.reset();
  EXPECT_EQ(std::getenv("DISPLAY"), nullptr);  // the server's DISPLAY goes with it
  if (outer)
    setenv("DISPLAY", outer->c_str(), 1);
  EXPECT_EQ(refused, 0);
}

}  // namespace
}  // namespace trainsim
