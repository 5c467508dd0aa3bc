# The truncation study of the shipped FE beam as JSON, drawn by
# share/plot_truncation.py (Debian's python3-matplotlib).
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
execute_process(COMMAND "${APP}" truncation "${SCENES}/beam_fe.yaml" --modes 1..6
                        --reference 16 --json
                OUTPUT_FILE "${DIR}/beam.json" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "vibroimpact truncation failed (${rc})")
endif()
execute_process(COMMAND /usr/bin/python3 "${SCRIPT}" "${DIR}/beam.json" --out "${DIR}"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plot_truncation.py failed (${rc})")
endif()
file(SIZE "${DIR}/beam_truncation.png" size)
if(size LESS 20000)
  message(FATAL_ERROR "beam_truncation.png is only ${size} bytes")
endif()
