#pragma once
// The X server VTK's offscreen rendering needs: Debian's VTK 9.1 is built for GLX only (no EGL,
// no OSMesa), so even a headless render opens an X display.
#include <memory>
#include <string>

namespace trainsim::camera {

/// A private Xvfb server (software OpenGL through Mesa's llvmpipe) for this process, stopped
/// when the object goes.
class XDisplay {
 public:
  /// Nothing (null) if DISPLAY is set. Otherwise starts Xvfb on a free display number (it picks
  /// one with -displayfd), waits until it accepts connections and sets DISPLAY. Throws
  /// RuntimeError naming the problem if Xvfb is missing or does not start.
  static std::unique_ptr<XDisplay> ensure();
  ~XDisplay();
  XDisplay(const XDisplay&) = delete;
  XDisplay& operator=(const XDisplay&) = delete;
  /// ":N".
  const std::string& name() const { return name_; }

 private:
  XDisplay(int pid, std::string name) : pid_(pid), name_(std::move(name)) {}
  int pid_;
  std::string name_;
};

}  // namespace trainsim::camera
