// Stop requests (SIGINT, SIGTERM, SIGUSR1) for the whole life of a run: at once while
// nothing can be saved, at the end of a step once the run has state to save.
#pragma once

#include <csignal>
#include <filesystem>
#include <string>

namespace softflow::simulation {

/// The exit code of a run stopped on request (main's kInterrupted).
inline constexpr int kInterruptedExitCode = 5;

/// Installs softflow's handler for SIGINT, SIGTERM and SIGUSR1 (again after
/// PetscInitialize, whose own handler would end an MPI job with an error
/// dump). The process starts in start-up mode: meshing and set-up have
/// nothing to save, so a request ends it at once with exit 5 and one line
/// on standard error naming the signal, after removing `lock_file` (the
/// io::RunLock's file, if any; the kernel drops the lock itself).
/// leave_startup() switches to recording the request for the run to act
/// on at a consistent point (stop_requested).
void install_stop_handler(const std::filesystem::path& lock_file = {});

/// Holds SIGINT, SIGTERM and SIGUSR1 back on this thread while it lives (a
/// request arriving meanwhile is delivered when it ends): around taking the
/// run's lock and telling the handler its file, so that a request between
/// the two cannot leave the lock file behind.
class StopSignalsHeld {
 public:
  StopSignalsHeld();
  ~StopSignalsHeld();
  StopSignalsHeld(const StopSignalsHeld&) = delete;
  StopSignalsHeld& operator=(const StopSignalsHeld&) = delete;

 private:
  sigset_t previous_{};
};

/// From now on a request is only recorded (the run checkpoints and stops
/// after its step). Called by a run once it has output to keep or remove.
void leave_startup();

/// The signal received on any rank since leave_startup (0: none).
/// Collective: every rank must call it.
int stop_requested();

/// "SIGINT", "SIGTERM", "SIGUSR1" or "signal N".
std::string signal_name(int signal);

}  // namespace softflow::simulation
