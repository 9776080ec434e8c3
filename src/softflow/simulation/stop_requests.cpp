#include "softflow/simulation/stop_requests.hpp"

#include <pthread.h>

#include <array>
#include <csignal>
#include <cstring>

#include <fmt/format.h>
#include <mpi.h>
#include <unistd.h>

namespace softflow::simulation {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
volatile std::sig_atomic_t g_in_startup = 1;

// What the handler may touch: fixed buffers, filled before it is installed.
char g_lock_file[4096] = {};

constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGUSR1};

/// The start-up message for `signal`, built once (a handler cannot format).
const char* startup_message(int signal) {
  static const std::array<std::string, 3> messages = [] {
    std::array<std::string, 3> m;
    for (std::size_t i = 0; i < kSignals.size(); ++i)
      m[i] = fmt::format(
          "softflow: stopped by {} during start-up (meshing, set-up), before the first step: "
          "nothing to continue from and no results written; run the case again to start it\n",
          signal_name(kSignals[i]));
    return m;
  }();
  for (std::size_t i = 0; i < kSignals.size(); ++i)
    if (kSignals[i] == signal) return messages[i].c_str();
  return messages[1].c_str();
}

void on_stop_request(int signal) {
  if (g_in_startup) {
    // Only async-signal-safe calls: write, unlink, _exit.
    const char* message = startup_message(signal);  // built before installation
    (void)!::write(STDERR_FILENO, message, std::strlen(message));
    if (g_lock_file[0] != '\0') ::unlink(g_lock_file);
    ::_exit(kInterruptedExitCode);
  }
  g_stop_signal = signal;
  // A second Ctrl-C ends the process at once, for whoever cannot wait for the step.
  std::signal(signal, SIG_DFL);
}

}  // namespace

std::string signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGUSR1: return "SIGUSR1";
    default: return fmt::format("signal {}", signal);
  }
}

void install_stop_handler(const std::filesystem::path& lock_file) {
  (void)startup_message(SIGTERM);  // build the messages outside the handler
  if (!lock_file.empty()) {
    const std::string path = lock_file.string();
    if (path.size() < sizeof g_lock_file) std::memcpy(g_lock_file, path.c_str(), path.size() + 1);
  }
  struct sigaction action {};
  action.sa_handler = on_stop_request;
  action.sa_flags = SA_RESTART;  // as std::signal: a request never fails a write
  sigemptyset(&action.sa_mask);
  for (int s : kSignals) {
    if (g_stop_signal == s) continue;  // a second request of this kind ends the process
    sigaction(s, &action, nullptr);
  }
}

StopSignalsHeld::StopSignalsHeld() {
  sigset_t stops;
  sigemptyset(&stops);
  for (int s : kSignals) sigaddset(&stops, s);
  pthread_sigmask(SIG_BLOCK, &stops, &previous_);
}

StopSignalsHeld::~StopSignalsHeld() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

void leave_startup() { g_in_startup = 0; }

int stop_requested() {
  int local = g_stop_signal, any = 0;
  MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return any;
}

}  // namespace softflow::simulation
