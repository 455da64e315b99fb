# Runs EXE PRM --set SETTING [--set MODEL] and expects exit 0 and summary.json
# "failed": false. MODEL (optional) is a second setting, such as Model=fem.
set(extra)
if(MODEL)
  set(extra --set ${MODEL})
endif()
execute_process(COMMAND ${EXE} ${PRM} --set ${SETTING} ${extra} --set Output/Directory=${OUT} --set Output/Progress=off
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit ${rc}: ${err}")
endif()
file(READ ${OUT}/summary.json summary)
string(JSON failed GET "${summary}" failed)
if(failed)
  message(FATAL_ERROR "run stopped by a numerical limit: ${summary}")
endif()
