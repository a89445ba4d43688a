# biota_add_test(NAME <n> SOURCES <files> LIBS <targets> [PROCESSES <p>...] [LABELS <l>...])
# Registers a gtest binary; with PROCESSES it becomes an MPI test run once per rank count
# (waLBerla's waLBerla_execute_test / Cabana's np sweep). Rank counts above the core count
# use --oversubscribe.
set(BIOTA_MPIEXEC_EXTRA "" CACHE STRING "extra flags for mpiexec in tests")
function(biota_add_test)
  cmake_parse_arguments(T "" "NAME" "SOURCES;LIBS;PROCESSES;LABELS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  if(T_PROCESSES)
    target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} biota_mpi_gtest_main biota_warnings)
    foreach(np IN LISTS T_PROCESSES)
      add_test(NAME ${T_NAME}_np${np}
               COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} ${np} --oversubscribe
                       ${BIOTA_MPIEXEC_EXTRA} $<TARGET_FILE:${T_NAME}>)
      set_tests_properties(${T_NAME}_np${np} PROPERTIES PROCESSORS ${np}
        LABELS "mpi;${T_LABELS}" ENVIRONMENT
        "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1;OMPI_MCA_mpi_yield_when_idle=1"
        TIMEOUT 600)
    endforeach()
  else()
    target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest_main biota_warnings)
    add_test(NAME ${T_NAME} COMMAND ${T_NAME})
    set_tests_properties(${T_NAME} PROPERTIES LABELS "unit;${T_LABELS}" TIMEOUT 600)
  endif()
endfunction()
