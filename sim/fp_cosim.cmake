# The floating-point units (docs/rtl.md): one Verilated model per unit and co-simulated
# format, fp_cosim against rpu::fp::soft, and synthesis with netlist simulation.
rpu_cosim_library(fp_unit)
foreach(format IN LISTS rpu_cosim_formats)
  set(unit_index 0)
  foreach(unit IN LISTS rpu_fp_units)
    rpu_cosim_model(fp_unit Vfp_${unit}_${format} TRACE FACTS unit=${unit} format=${format}
                    PARAMS -GUnit=${unit_index} ${rpu_widths_${format}})
    math(EXPR unit_index "${unit_index} + 1")
  endforeach()
endforeach()
rpu_cosim_registry(fp_unit)

add_executable(fp_cosim fp_cosim.cpp)
target_link_libraries(fp_cosim PRIVATE rpu_fp_unit_rtl_models rpu_fp_check rpu_output_file CLI11::CLI11 rpu_flags)

# One test per op and format: all edge and constructed vectors plus 10^6 random ones;
# the `slow` label runs 10^8.
foreach(line IN LISTS rpu_fp_op_lines)
  if(NOT line)
    continue()
  endif()
  rpu_fields("${line}" op unit)
  foreach(format IN LISTS rpu_cosim_formats)
    add_test(NAME cosim.${unit}.${op}.${format}
             COMMAND fp_cosim --unit ${unit} --op ${op} --format ${format} --count 1000000)
    set_tests_properties(cosim.${unit}.${op}.${format} PROPERTIES LABELS cosim TIMEOUT 900)
    add_test(NAME slow.cosim.${unit}.${op}.${format}
             COMMAND fp_cosim --unit ${unit} --op ${op} --format ${format} --count 100000000)
    set_tests_properties(slow.cosim.${unit}.${op}.${format} PROPERTIES LABELS slow TIMEOUT 14400)
  endforeach()
endforeach()

# spec/latencies.toml's [latency.<format>] (fpu, sfu, rsq) against the RTL's, for every
# co-simulated format.
foreach(format IN LISTS rpu_cosim_formats)
  foreach(op add lt div rsqrt)
    add_test(NAME cosim.timing.${op}.${format}
             COMMAND fp_cosim --unit ${rpu_fp_unit_of_${op}} --op ${op} --format ${format} --count 1000
                              --check-config)
    set_tests_properties(cosim.timing.${op}.${format} PROPERTIES LABELS cosim TIMEOUT 300)
  endforeach()
endforeach()

# Synthesis of every unit for fp32, rpu24 and fp16 with Debian's Yosys, and the
# netlist simulated (Verilator; `rtl/flow.py synth --sim icarus` for Icarus) against
# 10^4 vectors and results of the C++ model (rtl/flow.py synth).
# The `ci` tier synthesises the formats of the named configurations, fp32 and rpu24.
set(rpu_synth_formats fp32 rpu24 fp16)
if(RPU_COSIM_TIER STREQUAL "ci")
  set(rpu_synth_formats fp32 rpu24)
endif()
if(RPU_YOSYS)
  foreach(format IN LISTS rpu_synth_formats)
    foreach(unit IN LISTS rpu_fp_units)
      add_test(NAME synth.${unit}.${format}
        COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
                --unit ${unit} --format ${format} --pkg ${RPU_SPEC_SV} --cosim $<TARGET_FILE:fp_cosim>
                --out ${CMAKE_CURRENT_BINARY_DIR}/synth --vectors 10000
                --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
      set_tests_properties(synth.${unit}.${format} PROPERTIES LABELS synth TIMEOUT 900)
    endforeach()
  endforeach()
endif()

# The narrowest format built (fp16, else rpu24): the smallest waves.
set(rpu_trace_format)
foreach(format rpu24 fp16)
  if(format IN_LIST rpu_cosim_formats)
    set(rpu_trace_format ${format})
  endif()
endforeach()
if(rpu_trace_format)
  rpu_trace_outputs_test(fp --small-waves --
                         $<TARGET_FILE:fp_cosim> --unit fma --op add --format ${rpu_trace_format} --count 100000)
endif()
