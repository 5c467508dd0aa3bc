# The same sweep serially and under `mpirun -np 2`: the JSON diagrams must be
# byte-identical, and rank 0 alone writes the HDF5 file.
set(ARGS sweep --param forcing.omega --from 0.8 --to 1.2 --steps 9 --both
    --chunks 3 --transient 100 --record 10 --method exact --orbits=60 --json)
file(REMOVE "${DIR}/mpi_sweep.h5")
execute_process(COMMAND "${APP}" ${ARGS} OUTPUT_VARIABLE serial RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "serial sweep failed: ${rc}")
endif()
execute_process(COMMAND "${MPIEXEC}" -np 2 --allow-run-as-root --oversubscribe
  "${APP}" ${ARGS} -o "${DIR}/mpi_sweep.h5" OUTPUT_VARIABLE par RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "mpirun -np 2 sweep failed: ${rc}")
endif()
if(NOT serial STREQUAL par)
  message(FATAL_ERROR "serial and 2-rank diagrams differ:\n${serial}\n${par}")
endif()
if(NOT EXISTS "${DIR}/mpi_sweep.h5")
  message(FATAL_ERROR "no HDF5 file from rank 0")
endif()
string(LENGTH "${serial}" n)
message(STATUS "serial and mpirun -np 2 diagrams identical (${n} bytes of JSON)")
