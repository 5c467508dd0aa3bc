# The Fig. 2 period-doubling curve in (Omega, r) and a small sweep of the
# same plane into HDF5, and the figure share/plot_curves.py draws from them.
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
execute_process(COMMAND "${APP}" curves --kind pd --param forcing.omega --to 1.8
  --param2 stop.r --from2 0.5 --to2 0.9 --steps 50 -o "${DIR}/pd.h5"
  OUTPUT_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "vibroimpact curves failed: ${rc}")
endif()
execute_process(COMMAND "${APP}" sweep --param forcing.omega --from 1.58 --to 1.64
  --steps 7 --param2 stop.r --from2 0.5 --to2 0.9 --steps2 3 --transient 300
  --record 20 --method exact --quiet -o "${DIR}/map.h5" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "vibroimpact sweep (map) failed: ${rc}")
endif()
execute_process(COMMAND /usr/bin/python3 "${SCRIPT}" "${DIR}/pd.h5" --sweep "${DIR}/map.h5"
  --out "${DIR}/pd.png" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plot_curves.py failed: ${rc}")
endif()
if(NOT EXISTS "${DIR}/pd.png")
  message(FATAL_ERROR "missing ${DIR}/pd.png")
endif()
file(SIZE "${DIR}/pd.png" size)
if(size LESS 10000)
  message(FATAL_ERROR "${DIR}/pd.png is only ${size} bytes")
endif()
