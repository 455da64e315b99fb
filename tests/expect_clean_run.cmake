# Runs EXE PRM --set SETTING [--set MODEL] and expects exit 0 and summary.json
# "failed": false. MODEL (optional) is a second setting, such as Model=fem,
# EXTRA (optional) a list of more (separated by ; or |); JAMMED=ON also asks for "jammed": true,
# MIN_PHI=x for phi_final >= x, MORPHOLOGY=name for that morphology at the end,
# MAX_OVERLAP=x for a largest contact overlap of at most x d.
set(extra)
if(MODEL)
  set(extra --set ${MODEL})
endif()
string(REPLACE "|" ";" EXTRA "${EXTRA}")
foreach(setting ${EXTRA})
  list(APPEND extra --set ${setting})
endforeach()
execute_process(COMMAND ${EXE} ${PRM} --set ${SETTING} ${extra} --replace --set Output/Directory=${OUT} --set Output/Progress=off
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
# With -DJAMMED=ON the run must have stopped by jamming, not at the maximum
# packing density.
if(JAMMED)
  string(JSON jammed GET "${summary}" jammed)
  if(NOT jammed)
    message(FATAL_ERROR "the run did not jam: ${summary}")
  endif()
endif()
# Fails when the summary's KEY compares to LIMIT by OP (LESS, GREATER).
function(refuse key op limit what)
  string(JSON value GET "${summary}" ${key})
  if(value ${op} limit)
    message(FATAL_ERROR "${what} ${value} is beyond ${limit}: ${summary}")
  endif()
endfunction()
if(MIN_PHI)
  refuse(phi_final LESS ${MIN_PHI} "phi at the end")
endif()
if(MAX_OVERLAP)
  refuse(max_penetration GREATER ${MAX_OVERLAP} "the largest overlap (d)")
endif()
if(MORPHOLOGY)
  string(JSON morphology GET "${summary}" morphology)
  if(NOT morphology STREQUAL MORPHOLOGY)
    message(FATAL_ERROR "the run ended ${morphology}, not ${MORPHOLOGY}: ${summary}")
  endif()
endif()
# The summary names the code that made it: the version `wirefem --version`
# prints, with a commit.
execute_process(COMMAND ${EXE} --version RESULT_VARIABLE rc OUTPUT_VARIABLE printed
                OUTPUT_STRIP_TRAILING_WHITESPACE)
string(JSON recorded ERROR_VARIABLE missing GET "${summary}" version)
if(NOT rc EQUAL 0 OR missing OR NOT recorded MATCHES "^[0-9]+\\.[0-9]+\\.[0-9]+ \\(commit [^)]+\\)$"
   OR NOT printed STREQUAL "wirefem ${recorded}")
  message(FATAL_ERROR "summary.json version '${recorded}' (${missing}) is not that of --version '${printed}' (exit ${rc})")
endif()
