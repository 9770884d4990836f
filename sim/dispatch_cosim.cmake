# The ray dispatch alone (docs/rtl.md "Ray dispatch"), included by sim/CMakeLists.txt:
# Verilated rpu_ray_dispatch with the shapes of the chips that have several cores or
# units, and dispatch_cosim, which drives it with random rays and random unit readiness
# and compares each cycle's choice with the cycle model's RayDispatch.
rpu_cosim_library(dispatch)
set(rpu_dispatch_cases)
# cores units unit-rays packets: default's, drpu's, rpu2005's with 3 cores and 2 units
# (docs/perf.md), and default's without packets.
foreach(shape "4 4 64 1" "8 4 128 1" "3 2 128 1" "4 4 64 0")
  rpu_fields("${shape}" cores units rays packets)
  set(name c${cores}_u${units}_p${packets})
  rpu_cosim_model(dispatch Vdispatch_${name} FACTS cores=${cores} units=${units} packets=${packets} unit_rays=${rays}
                  PARAMS -GCores=${cores} -GUnits=${units} -GUnitRays=${rays} -GPackets=${packets})
  list(APPEND rpu_dispatch_cases "${cores} ${units} ${packets}")
endforeach()
rpu_cosim_registry(dispatch)

add_executable(dispatch_cosim dispatch_cosim.cpp)
target_link_libraries(dispatch_cosim PRIVATE rpu_dispatch_rtl_models rpu_cycle CLI11::CLI11 fmt::fmt rpu_flags)

foreach(case IN LISTS rpu_dispatch_cases)
  rpu_fields("${case}" cores units packets)
  set(name cosim.dispatch.c${cores}_u${units}_p${packets})
  add_test(NAME ${name} COMMAND dispatch_cosim --cores ${cores} --units ${units} --packets ${packets} --runs 500)
  set_tests_properties(${name} PROPERTIES LABELS cosim TIMEOUT 300)
endforeach()
