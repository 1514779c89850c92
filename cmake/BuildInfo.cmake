# Run at every build (cmake -P, from the cmbrl_build_info_source target): writes OUT from
# TEMPLATE with the project version and the source tree's commit as `git describe --always
# --dirty` names it ("unknown" outside a git checkout). configure_file leaves OUT untouched when
# the text is the same, so only a new commit or a change of the tree's cleanliness recompiles it.
# Arguments: SOURCE_DIR, VERSION, TEMPLATE, OUT.
set(CMBRL_VERSION "${VERSION}")
set(CMBRL_COMMIT "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(
    COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" describe --always --dirty --abbrev=12
    OUTPUT_VARIABLE described
    RESULT_VARIABLE result
    ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(result EQUAL 0 AND NOT described STREQUAL "")
    set(CMBRL_COMMIT "${described}")
  endif()
endif()
configure_file("${TEMPLATE}" "${OUT}" @ONLY)
