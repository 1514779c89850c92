// Which cmbrl this is: the project's version and the source commit it was built from, for
// `cmbrl --version` and for the record a run keeps of what made it (run/run_sessions.h).
#pragma once

namespace cmbrl {

// The project's version (CMakeLists.txt), e.g. "0.1.0".
const char* CmbrlVersion();

// The source tree's commit when this program was built, as `git describe --always --dirty`
// names it: "744c47e1a2b3", with "-dirty" for uncommitted changes; "unknown" outside git.
const char* CmbrlCommit();

}  // namespace cmbrl
