# Fig. 2's basins at Omega = 2.4 (the harmonic response and a P(3,1) orbit)
# into HDF5, and the figure share/plot_basins.py makes of them.
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
execute_process(COMMAND "${APP}" basins --set forcing.omega=2.4 --param initial.x[2]
  --from -4 --to 0.09 --steps 16 --param2 initial.v[2] --from2 -6 --to2 6 --steps2 12
  --transient 1000 --record 30 --method exact --quiet -o "${DIR}/fig2basins.h5"
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "vibroimpact basins failed: ${rc}")
endif()
execute_process(COMMAND /usr/bin/python3 "${SCRIPT}" "${DIR}/fig2basins.h5" --out "${DIR}"
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plot_basins.py failed: ${rc}")
endif()
set(png "${DIR}/fig2basins_basins.png")
if(NOT EXISTS "${png}")
  message(FATAL_ERROR "missing ${png}")
endif()
file(SIZE "${png}" size)
if(size LESS 20000)
  message(FATAL_ERROR "${png} is only ${size} bytes")
endif()
message(STATUS "basins figure written to ${png}")
