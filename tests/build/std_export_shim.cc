// Stands in for PyTorch's LibTorch, which exports its own copies of libstdc++'s std::filesystem
// functions: a library linked the way LibTorch is, after a program's objects, that defines
// std::filesystem::remove_all. Its copy removes nothing, so a program bound to it is seen to be.
#include <cstdint>
#include <filesystem>
#include <system_error>

namespace std::filesystem {

std::uintmax_t remove_all(const path&) { return 0; }
std::uintmax_t remove_all(const path&, std::error_code& error) {
  error.clear();
  return 0;
}

}  // namespace std::filesystem

// Called by the test, so that the library is loaded whatever the linker's --as-needed.
extern "C" int cmbrl_std_export_shim_loaded() { return 1; }
