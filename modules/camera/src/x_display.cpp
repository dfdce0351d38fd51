#include "trainsim/camera/x_display.hpp"

#include <X11/Xlib.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "trainsim/core/error.hpp"
#include "trainsim/core/log.hpp"

extern char** environ;

namespace trainsim::camera {
namespace {

// How long Xvfb may take to accept connections (it is usually ready in well under a second).
constexpr int kStartTimeoutMs = 30'000;

void stop(pid_t pid) {
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
}

// Whether an X client can connect to `name` (VTK aborts the process when it cannot).
bool reachable(const char* name) {
  Display* d = XOpenDisplay(name);
  if (d == nullptr)
    return false;
  XCloseDisplay(d);
  return true;
}

// The executable `file` on PATH, or empty. Looked up before fork: execvp would search PATH
// itself, but it may allocate, which a forked child of a threaded process must not.
std::string onPath(const std::string& file) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + file;
    struct stat st {};
    if (stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        access(candidate.c_str(), X_OK) == 0)
      return candidate;
  }
  return {};
}

}  // namespace

std::unique_ptr<XDisplay> XDisplay::ensure() {
  std::optional<std::string> previous;
  if (const char* d = std::getenv("DISPLAY"); d != nullptr && *d != '\0') {
    if (reachable(d))
      return nullptr;
    // A stale DISPLAY (an SSH session's forwarding gone, a server stopped): render on our own.
    logWarn(
        fmt::format("cannot open the X display DISPLAY={}; the cameras render on a private "
                    "Xvfb instead",
                    d));
    previous = d;
  }
  const std::string xvfb = onPath("Xvfb");
  if (xvfb.empty())
    throw RuntimeError(
        "cameras render through X, there is no usable DISPLAY and Xvfb is not installed "
        "(Debian package xvfb)");
  int fds[2];
  if (pipe(fds) != 0)
    throw RuntimeError(fmt::format("cannot start Xvfb: pipe: {}", std::strerror(errno)));
  // -noreset: by default the server resets when its last client disconnects, and clients
  // connecting during the reset are refused (some in 100 quick open-close cycles). Each renderer
  // opens and closes its own connection, so the next renderer's could be refused, and VTK aborts
  // the process then. tests/studio/with-xvfb.sh passes it too.
  char* argv[] = {const_cast<char*>("Xvfb"),       const_cast<char*>("-displayfd"),
                  const_cast<char*>("3"),          const_cast<char*>("-screen"),
                  const_cast<char*>("0"),          const_cast<char*>("2048x2048x24"),
                  const_cast<char*>("-nolisten"),  const_cast<char*>("tcp"),
                  const_cast<char*>("+extension"), const_cast<char*>("GLX"),
                  const_cast<char*>("-noreset"),   nullptr};
  // fork and exec rather than posix_spawn, for the parent-death signal: Xvfb goes with this
  // process however it ends (kill -9 included) instead of living on, orphaned. The child calls
  // only async-signal-safe functions. Xvfb writes its display number to fd 3 once it accepts
  // connections; its own messages go to /dev/null (a failure shows as no number).
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent)  // the parent is already gone
      _exit(127);
    close(fds[0]);
    if (fds[1] != 3) {
      dup2(fds[1], 3);
      close(fds[1]);
    }
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execve(xvfb.c_str(), argv, environ);
    _exit(127);
  }
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    throw RuntimeError(fmt::format("cannot start Xvfb: {}", std::strerror(errno)));
  }
  // Read "N\n" with a deadline.
  std::string number;
  pollfd p{fds[0], POLLIN, 0};
  while (number.find('\n') == std::string::npos) {
    if (poll(&p, 1, kStartTimeoutMs) <= 0)
      break;
    char buf[16];
    const ssize_t n = read(fds[0], buf, sizeof buf);
    if (n <= 0)
      break;
    number.append(buf, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  const auto end = number.find('\n');
  if (end == std::string::npos || end == 0) {
    stop(pid);
    throw RuntimeError("Xvfb did not start (run `Xvfb -displayfd 1` to see why)");
  }
  const std::string name = ":" + number.substr(0, end);
  setenv("DISPLAY", name.c_str(), 1);
  return std::unique_ptr<XDisplay>(new XDisplay(pid, name, std::move(previous)));
}

XDisplay::~XDisplay() {
  if (previous_)
    setenv("DISPLAY", previous_->c_str(), 1);
  else
    unsetenv("DISPLAY");
  stop(pid_);
}

}  // namespace trainsim::camera
