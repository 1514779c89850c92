// Stands in for OpenBLAS's core-name query (loaded with LD_PRELOAD) so that a test sees what a
// machine on which OpenBLAS detects an ancient core sees: cmbrl must restart itself with
// OPENBLAS_CORETYPE set.
extern "C" const char* openblas_get_corename() { return "Prescott"; }
