# Runs EXE analyze OUT and expects its shape numbers to be those of
# OUT/summary.json (the run's own, at its end): symmetry and
# inner_wire_fraction within 1e-3 (the VTU file rounds the points).
execute_process(COMMAND ${EXE} analyze ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE printed ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "analyze exit ${rc}: ${err}")
endif()
file(READ ${OUT}/summary.json summary)
foreach(key symmetry inner_wire_fraction)
  string(JSON a GET "${printed}" ${key})
  string(JSON b GET "${summary}" ${key})
  execute_process(COMMAND python3 -c "import sys; sys.exit(0 if abs(${a} - ${b}) <= 1e-3 else 1)"
                  RESULT_VARIABLE differs)
  if(differs)
    message(FATAL_ERROR "${key}: analyze gives ${a}, the run ${b}")
  endif()
endforeach()
