# A short Fig. 2 sweep (both directions) and a small two-parameter map into
# HDF5, and the bifurcation figures made from them by share/plot_sweep.py.
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
execute_process(COMMAND "${APP}" sweep --param forcing.omega --from 0.8 --to 1.0
  --steps 12 --both --transient 100 --record 10 --method exact --orbits=90 --quiet
  -o "${DIR}/fig2sweep.h5" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "vibroimpact sweep failed: ${rc}")
endif()
execute_process(COMMAND "${APP}" sweep --param forcing.omega --from 0.8 --to 1.0
  --steps 4 --param2 stop.xs --from2 0.05 --to2 0.2 --steps2 3 --transient 50
  --record 10 --method exact --quiet -o "${DIR}/fig2map.h5" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "vibroimpact sweep (map) failed: ${rc}")
endif()
foreach(f fig2sweep:bifurcation fig2map:map)
  string(REPLACE ":" ";" p ${f})
  list(GET p 0 stem)
  list(GET p 1 kind)
  execute_process(COMMAND /usr/bin/python3 "${SCRIPT}" "${DIR}/${stem}.h5" --out "${DIR}"
    RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "plot_sweep.py failed on ${stem}.h5: ${rc}")
  endif()
  set(png "${DIR}/${stem}_${kind}.png")
  if(NOT EXISTS "${png}")
    message(FATAL_ERROR "missing ${png}")
  endif()
  file(SIZE "${png}" size)
  if(size LESS 20000)
    message(FATAL_ERROR "${png} is only ${size} bytes")
  endif()
endforeach()
message(STATUS "2 sweep figures written to ${DIR}")
