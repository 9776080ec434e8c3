// `softflow check A.toml B.toml ...`: several case files in one process.
#pragma once

#include <string>
#include <vector>

namespace softflow::app {

/// Each file validated as `check` validates one, in one process (a
/// process's start-up, ~0.25 s, is most of a check's time), one line per
/// file: "FILE: valid" on stdout, or the message on stderr. The cases with
/// PETSc options (and the options after "--", `petsc` from argv[0] on) are
/// checked last, in one PETSc session, each in an options database of its
/// own. Returns the exit code: 0 if every file is valid, 1 if any was
/// refused, 4 if any check failed otherwise (e.g. the file system).
int check_several(const std::vector<std::string>& files, const std::vector<char*>& petsc);

}  // namespace softflow::app
