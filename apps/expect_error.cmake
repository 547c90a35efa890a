# Runs ${APP} with invalid settings and expects exit code 1, a message naming the bad
# parameter on stderr, and no ${OUTPUT} file.
file(REMOVE "${OUTPUT}")
execute_process(COMMAND "${APP}" --size 8 --spp 0 --quiet -o "${OUTPUT}"
                RESULT_VARIABLE result ERROR_VARIABLE err OUTPUT_QUIET)
if(NOT result EQUAL 1)
  message(FATAL_ERROR "expected exit code 1, got '${result}' (stderr: ${err})")
endif()
if(NOT err MATCHES "samples_per_pixel = 0")
  message(FATAL_ERROR "stderr does not name the parameter: ${err}")
endif()
if(EXISTS "${OUTPUT}")
  message(FATAL_ERROR "an output file was written: ${OUTPUT}")
endif()
