# Runs a command and checks its exit code, its output and (optionally) that a path was NOT
# created — the "no half-written outputs" rule for failing commands.
# and, with FILE, that a file it wrote matches FILE_REGEX.
#   cmake -DCMD="a|b|c" -DEXIT=0 [-DSTDOUT_REGEX=...] [-DSTDERR_REGEX=...] [-DNO_PATH=path]
#         [-DFILE=path -DFILE_REGEX=...] -P expect_run.cmake
string(REPLACE "|" ";" CMD "${CMD}")
if(DEFINED NO_PATH)
  file(REMOVE_RECURSE "${NO_PATH}")
endif()
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT "${rc}" STREQUAL "${EXIT}")
  message(FATAL_ERROR "exit code ${rc}, expected ${EXIT}\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED STDOUT_REGEX AND NOT out MATCHES "${STDOUT_REGEX}")
  message(FATAL_ERROR "stdout does not match '${STDOUT_REGEX}':\n${out}")
endif()
if(DEFINED STDERR_REGEX AND NOT err MATCHES "${STDERR_REGEX}")
  message(FATAL_ERROR "stderr does not match '${STDERR_REGEX}':\n${err}")
endif()
if(DEFINED NO_PATH AND EXISTS "${NO_PATH}")
  message(FATAL_ERROR "${NO_PATH} was written although the command failed")
endif()
if(DEFINED FILE)
  file(READ "${FILE}" written)
  if(NOT written MATCHES "${FILE_REGEX}")
    message(FATAL_ERROR "${FILE} does not match '${FILE_REGEX}'")
  endif()
endif()
message(STATUS "ok: exit ${rc}")
