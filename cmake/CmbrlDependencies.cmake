# Finds every third-party library cmbrl links, and gives each one a target name that does not
# depend on how it was found.

find_package(fmt REQUIRED)
find_package(Threads REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo)

# CLI11 is header-only; Debian ships no CMake package file for it.
find_path(CLI11_INCLUDE_DIR CLI/CLI.hpp REQUIRED)
add_library(cmbrl_cli11 INTERFACE)
target_include_directories(cmbrl_cli11 SYSTEM INTERFACE "${CLI11_INCLUDE_DIR}")

# MuJoCo: its package file needs qhull and the OpenGL development files; a machine without them
# (the GPU build machine) still has the header and the library, so fall back to those.
find_package(mujoco 2.2 CONFIG QUIET)
add_library(cmbrl_mujoco INTERFACE)
if(TARGET mujoco::mujoco)
  target_link_libraries(cmbrl_mujoco INTERFACE mujoco::mujoco)
  message(STATUS "MuJoCo: package file")
else()
  find_path(MUJOCO_INCLUDE_DIR mujoco/mujoco.h REQUIRED)
  find_library(MUJOCO_LIBRARY mujoco REQUIRED)
  target_include_directories(cmbrl_mujoco SYSTEM INTERFACE "${MUJOCO_INCLUDE_DIR}")
  target_link_libraries(cmbrl_mujoco INTERFACE "${MUJOCO_LIBRARY}")
  message(STATUS "MuJoCo: ${MUJOCO_LIBRARY}")
endif()

# LibTorch: Debian's CPU build, or the CUDA one inside a PyTorch installation
# (-DCMAKE_PREFIX_PATH=$(python3 -c 'import torch;print(torch.utils.cmake_prefix_path)')).
find_package(Torch REQUIRED)
add_library(cmbrl_torch INTERFACE)
target_link_libraries(cmbrl_torch INTERFACE ${TORCH_LIBRARIES})
target_compile_options(cmbrl_torch INTERFACE ${TORCH_CXX_FLAGS})
# PyTorch's LibTorch (the CUDA builds') exports its own copies of libstdc++'s std::filesystem
# functions, and its remove_all calls through a null pointer: linked after it, `cmbrl train`
# bound to them and died at its second checkpoint. The shared libstdc++ is therefore put first on
# every link line, by its path, so that the linker resolves the standard library's functions
# there (a plain `-lstdc++` put no libstdc++ first on the GPU machine's toolchain).
# With Debian's LibTorch, which exports none, the program's bindings are the same.
# tests/build/std_binding_test.cc checks it against a library that exports such copies.
# Only where the program uses libstdc++ (not clang with -stdlib=libc++).
if(CMAKE_SYSTEM_NAME STREQUAL "Linux" AND NOT CMAKE_CXX_FLAGS MATCHES "-stdlib=libc\\+\\+")
  execute_process(COMMAND "${CMAKE_CXX_COMPILER}" -print-file-name=libstdc++.so.6
                  OUTPUT_VARIABLE CMBRL_LIBSTDCXX OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT IS_ABSOLUTE "${CMBRL_LIBSTDCXX}" OR NOT EXISTS "${CMBRL_LIBSTDCXX}")
    unset(CMBRL_LIBSTDCXX)
    find_library(CMBRL_LIBSTDCXX NAMES libstdc++.so.6)
  endif()
  if(CMBRL_LIBSTDCXX)
    add_link_options("SHELL:-Wl,--push-state,--no-as-needed ${CMBRL_LIBSTDCXX} -Wl,--pop-state")
  else()
    message(WARNING "no shared libstdc++ (libstdc++.so.6) found to link first: with PyTorch's "
                    "LibTorch, std::filesystem may bind to its copies and crash")
  endif()
endif()

# cmbrl's own CUDA kernels (cmbrl/models/tree_kernel_cuda.cu: the classifier's trees in one
# launch). Built only where LibTorch has CUDA and a CUDA compiler is found; elsewhere, and with
# -DCMBRL_WITH_CUDA_KERNELS=OFF, a GPU runs the trees as LibTorch operations. The kernels link
# the shared CUDA runtime, the one LibTorch loads. CMBRL_CUDA_ARCHITECTURES: the GPUs to compile
# for ("native": those of the building machine, which needs one).
option(CMBRL_WITH_CUDA_KERNELS "Build cmbrl's CUDA kernels where LibTorch has CUDA" ON)
set(CMBRL_CUDA_ARCHITECTURES "native" CACHE STRING "CUDA architectures of cmbrl's kernels")
set(CMBRL_HAVE_CUDA_KERNELS OFF)
if(CMBRL_WITH_CUDA_KERNELS AND (TORCH_CUDA_LIBRARIES OR C10_CUDA_LIBRARY OR TARGET torch_cuda))
  # nvcc need not be on PATH: the toolkit LibTorch found (/usr/local/cuda) names it.
  if(NOT CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
    find_package(CUDAToolkit QUIET)
    if(CUDAToolkit_NVCC_EXECUTABLE)
      set(CMAKE_CUDA_COMPILER "${CUDAToolkit_NVCC_EXECUTABLE}")
    endif()
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    if(NOT CMAKE_CUDA_HOST_COMPILER)
      set(CMAKE_CUDA_HOST_COMPILER "${CMAKE_CXX_COMPILER}")
    endif()
    enable_language(CUDA)
    find_package(CUDAToolkit REQUIRED)
    set(CMBRL_HAVE_CUDA_KERNELS ON)
    message(STATUS "cmbrl CUDA kernels: ${CMAKE_CUDA_COMPILER} for ${CMBRL_CUDA_ARCHITECTURES}")
  else()
    message(WARNING "LibTorch has CUDA but no CUDA compiler was found: the classifier's trees "
                    "will run on the GPU as LibTorch operations, not as one kernel")
  endif()
endif()

# oneDNN (Debian's libdnnl-dev): the fast CPU prediction backend (cmbrl/models/onednn_forward.h).
# Optional: without it, or with -DCMBRL_WITH_ONEDNN=OFF (a PyTorch LibTorch that carries its own
# copy), predictions run on LibTorch. Header and library directly: the package file would also
# want OpenCL, which the CPU backend never uses.
option(CMBRL_WITH_ONEDNN "Build the oneDNN prediction backend when libdnnl-dev is installed" ON)
add_library(cmbrl_onednn INTERFACE)
if(CMBRL_WITH_ONEDNN)
  find_path(DNNL_INCLUDE_DIR oneapi/dnnl/dnnl.hpp)
  find_library(DNNL_LIBRARY NAMES dnnl libdnnl.so.2)
  if(DNNL_INCLUDE_DIR AND DNNL_LIBRARY)
    target_include_directories(cmbrl_onednn SYSTEM INTERFACE "${DNNL_INCLUDE_DIR}")
    # gomp: the backend sets oneDNN's OpenMP thread count per call (onednn_forward.cc).
    target_link_libraries(cmbrl_onednn INTERFACE "${DNNL_LIBRARY}" gomp)
    set(CMBRL_HAVE_ONEDNN ON)
    message(STATUS "oneDNN: ${DNNL_LIBRARY}")
  else()
    message(WARNING "oneDNN not found (install libdnnl-dev): predictions will run on LibTorch")
  endif()
endif()

# XGBoost: its package file needs the xgboost program package as well; fall back to the header
# and library.
find_package(xgboost CONFIG QUIET)
add_library(cmbrl_xgboost INTERFACE)
if(TARGET xgboost::xgboost)
  target_link_libraries(cmbrl_xgboost INTERFACE xgboost::xgboost)
else()
  find_path(XGBOOST_INCLUDE_DIR xgboost/c_api.h REQUIRED)
  find_library(XGBOOST_LIBRARY xgboost REQUIRED)
  target_include_directories(cmbrl_xgboost SYSTEM INTERFACE "${XGBOOST_INCLUDE_DIR}")
  target_link_libraries(cmbrl_xgboost INTERFACE "${XGBOOST_LIBRARY}")
endif()
