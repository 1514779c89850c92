// The command line's own Python interpreter, for runs whose config declares Python parts by name
// (section python): started the first time such a run needs one, with cmbrl's package of this
// build on its path (for environments that import cmbrl), and kept for the process's life.
#pragma once

namespace cmbrl::python {

// Lets cmbrl's core make declared Python parts in this program (SetPythonInputsMaker); starts
// nothing until one is needed. Python's signal handlers are not installed: the program's own
// (a checkpoint on SIGTERM and Ctrl-C) stay.
void InstallEmbeddedPython();

}  // namespace cmbrl::python
