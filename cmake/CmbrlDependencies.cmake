# Finds every third-party library cmbrl links, and gives each one a target name that does not
# depend on how it was found.

find_package(fmt REQUIRED)
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
