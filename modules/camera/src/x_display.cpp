#include "trainsim/camera/x_display.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "trainsim/core/error.hpp"

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

}  // namespace

std::unique_ptr<XDisplay> XDisplay::ensure() {
  if (const char* d = std::getenv("DISPLAY"); d != nullptr && *d != '\0')
    return nullptr;
  int fds[2];
  if (pipe(fds) != 0)
    throw RuntimeError(fmt::format("cannot start Xvfb: pipe: {}", std::strerror(errno)));
  // Xvfb writes its display number to fd 3 once it accepts connections; its own messages go to
  // /dev/null (a failure shows as no number).
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addclose(&actions, fds[0]);  // first: it may be fd 3 itself
  posix_spawn_file_actions_adddup2(&actions, fds[1], 3);
  if (fds[1] != 3)
    posix_spawn_file_actions_addclose(&actions, fds[1]);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  char* argv[] = {const_cast<char*>("Xvfb"),
                  const_cast<char*>("-displayfd"),
                  const_cast<char*>("3"),
                  const_cast<char*>("-screen"),
                  const_cast<char*>("0"),
                  const_cast<char*>("2048x2048x24"),
                  const_cast<char*>("-nolisten"),
                  const_cast<char*>("tcp"),
                  const_cast<char*>("+extension"),
                  const_cast<char*>("GLX"),
                  nullptr};
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "Xvfb", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (spawned != 0) {
    close(fds[0]);
    throw RuntimeError(
        spawned == ENOENT
            ? std::string("cameras render through X, DISPLAY is unset and Xvfb is not installed "
                          "(Debian package xvfb)")
            : fmt::format("cannot start Xvfb: {}", std::strerror(spawned)));
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
  return std::unique_ptr<XDisplay>(new XDisplay(pid, name));
}

XDisplay::~XDisplay() {
  unsetenv("DISPLAY");
  stop(pid_);
}

}  // namespace trainsim::camera
