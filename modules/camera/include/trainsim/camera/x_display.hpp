#pragma once
// The X server VTK's offscreen rendering needs: Debian's VTK 9.1 is built for GLX only (no EGL,
// no OSMesa), so even a headless render opens an X display.
#include <memory>
#include <optional>
#include <string>

namespace trainsim::camera {

/// A private Xvfb server (software OpenGL through Mesa's llvmpipe) for this process, stopped
/// when the object goes, and by the kernel when the process dies (kill -9 included).
class XDisplay {
 public:
  /// Nothing (null) if DISPLAY names a display that accepts connections. Otherwise (DISPLAY
  /// unset, or stale: a warning says so) starts Xvfb on a free display number (it picks one with
  /// -displayfd), waits until it accepts connections and sets DISPLAY, until the object goes.
  /// Throws RuntimeError naming the problem if Xvfb is missing or does not start.
  static std::unique_ptr<XDisplay> ensure();
  ~XDisplay();
  XDisplay(const XDisplay&) = delete;
  XDisplay& operator=(const XDisplay&) = delete;
  /// ":N".
  const std::string& name() const { return name_; }

 private:
  XDisplay(int pid, std::string name, std::optional<std::string> previous)
      : pid_(pid), name_(std::move(name)), previous_(std::move(previous)) {}
  int pid_;
  std::string name_;
  std::optional<std::string> previous_;  // the stale DISPLAY it stood in for
};

}  // namespace trainsim::camera
