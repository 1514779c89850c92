// The project's link options put the shared libstdc++ first (cmake/CmbrlDependencies.cmake), so
// that a program's standard-library calls bind to it even where a library linked after the
// objects exports copies of them, as PyTorch's LibTorch does (its remove_all crashed `cmbrl
// train` on a GPU machine). This program is linked with such a library (std_export_shim.cc).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/temp_path.h"

extern "C" int cmbrl_std_export_shim_loaded();

namespace cmbrl {
namespace {
namespace fs = std::filesystem;

TEST(StdBindingTest, RemoveAllBindsToLibstdcxxNotToALibraryExportingACopy) {
  ASSERT_EQ(cmbrl_std_export_shim_loaded(), 1);  // the copy is in the process
  using RemoveAll = std::uintmax_t (*)(const fs::path&);
  Dl_info info{};
  ASSERT_NE(dladdr(reinterpret_cast<void*>(static_cast<RemoveAll>(&fs::remove_all)), &info), 0);
  EXPECT_NE(std::string(info.dli_fname).find("libstdc++"), std::string::npos)
      << "std::filesystem::remove_all is bound to " << info.dli_fname;

  const fs::path dir = fs::path(testing::TestTempPath("tree"));
  fs::create_directories(dir / "inner");
  std::ofstream(dir / "inner" / "file") << "x";
  EXPECT_EQ(fs::remove_all(dir), 3u);
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace cmbrl
