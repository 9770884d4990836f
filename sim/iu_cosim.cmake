# The intersection unit (docs/rtl.md, "Intersection unit"), included by sim/CMakeLists.txt:
# one Verilated rpu_iu per intersection mode for fp32 and rpu24 (the formats of the
# spec's configurations) when they are co-simulated, and iu_cosim, which compares it
# with the functional tracer's IU tests.
set(rpu_iu_cases)
if(NOT rpu_ray_unit_formats)
  return()  # neither fp32 nor rpu24 is co-simulated (RPU_COSIM_FORMATS)
endif()
rpu_cosim_library(iu)
foreach(format IN LISTS rpu_ray_unit_formats)
  foreach(isect woop watertight)
    # The `ci` tier: both tests in fp32, rpu24 (rpu2005's format) with Woop's.
    if(RPU_COSIM_TIER STREQUAL "ci" AND "${format} ${isect}" STREQUAL "rpu24 watertight")
      continue()
    endif()
    rpu_cosim_model(iu Viu_${format}_${isect} TRACE FACTS format=${format} isect=${isect}
                    PARAMS ${rpu_widths_${format}} -GIsectMode=${rpu_isect_${isect}})
    list(APPEND rpu_iu_cases "${format} ${isect}")
  endforeach()
endforeach()
rpu_cosim_registry(iu)

add_executable(iu_cosim iu_cosim.cpp)
target_link_libraries(iu_cosim PRIVATE rpu_iu_rtl_models rpu_test_support rpu_output_file CLI11::CLI11 rpu_flags)

# CI: a thousand camera and random rays per scene; `slow`: the issue's 10^5 per kind.
# cosim.iu.timing.*: the measured latency and interval against spec/latencies.toml, and
# at least 0.9 tests per cycle on a burst of 1,000 tests (the pipeline's fill included).
foreach(case IN LISTS rpu_iu_cases)
  rpu_fields("${case}" format isect)
  set(scenes --scene cornell --scene balls:2 --scene ${PROJECT_SOURCE_DIR}/scenes/bunny.json)
  add_test(NAME cosim.iu.${format}.${isect}
           COMMAND iu_cosim --format ${format} --isect ${isect} ${scenes} --rays 1000)
  set_tests_properties(cosim.iu.${format}.${isect} PROPERTIES LABELS cosim TIMEOUT 900)
  add_test(NAME cosim.iu.timing.${format}.${isect}
           COMMAND iu_cosim --format ${format} --isect ${isect} --scene cornell --rays 200 --check-config
                   --min-tests-per-cycle 0.9)
  set_tests_properties(cosim.iu.timing.${format}.${isect} PROPERTIES LABELS cosim TIMEOUT 300)
  add_test(NAME slow.cosim.iu.${format}.${isect}
           COMMAND iu_cosim --format ${format} --isect ${isect} ${scenes} --rays 100000)
  set_tests_properties(slow.cosim.iu.${format}.${isect} PROPERTIES LABELS slow TIMEOUT 14400)
endforeach()

# Synthesis of the IU in both modes with Yosys, each netlist simulated against 10^4 IU
# tests captured from the functional tracer (rtl/flow.py synth --unit iu). Each takes
# several minutes of CPU (docs/rtl.md), more than CI's budget has left: all under `slow`.
if(RPU_YOSYS)
  foreach(isect woop watertight)
    foreach(format fp16 rpu24 fp32)
      set(name slow.synth.iu_${isect}.${format})
      set(label slow)
      add_test(NAME ${name}
        COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
                --unit iu --isect ${isect} --format ${format} --pkg ${RPU_SPEC_SV}
                --cosim $<TARGET_FILE:iu_cosim> --out ${CMAKE_CURRENT_BINARY_DIR}/synth --vectors 10000
                --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
      set_tests_properties(${name} PROPERTIES LABELS ${label} TIMEOUT 3600)
    endforeach()
  endforeach()
endif()

# --trace's failures (rpu_trace_outputs_test).
if("fp32 woop" IN_LIST rpu_iu_cases)
  rpu_trace_outputs_test(iu --
                         $<TARGET_FILE:iu_cosim> --format fp32 --isect woop --scene cornell --rays 300)
endif()
