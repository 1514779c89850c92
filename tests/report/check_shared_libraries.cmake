# cmake -DPROGRAM=<file> -P check_shared_libraries.cmake: fails when the program loads LibTorch,
# MuJoCo, XGBoost or oneDNN (ldd's list of its shared libraries).
execute_process(COMMAND ldd "${PROGRAM}" OUTPUT_VARIABLE libraries RESULT_VARIABLE failed)
if(failed)
  message(FATAL_ERROR "ldd ${PROGRAM} failed")
endif()
# Library names only (lib...<name>....so): a load address such as (0x00007fc10d70b000) holds
# "c10" now and then, which made this test fail by chance.
string(REGEX MATCHALL "lib[^\n\t /()]*(torch|c10|mujoco|xgboost|dnnl)[^\n\t /()]*\\.so[^\n\t ()]*"
       heavy "${libraries}")
if(heavy)
  message(FATAL_ERROR "${PROGRAM} loads ${heavy}")
endif()
message(STATUS "${PROGRAM} loads none of LibTorch, MuJoCo, XGBoost or oneDNN")
