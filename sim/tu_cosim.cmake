# The traversal unit (docs/rtl.md, "Traversal unit"): per co-simulated format and
# intersection mode, one Verilated model of the TU alone (its IU port answered by the
# C++ IU) and one of the ray unit (the TU with the RTL IU, rpu_ray_unit); tu_cosim
# compares either ray by ray with the golden tracer.
rpu_cosim_library(tu)
# The kinds of model per format and mode, and their slots and pipeline:
#   tu        the TU alone with one ray slot (its step cycles are measured ray by ray);
#   ray       the ray unit with rpu_tu_cosim_slots walker slots sharing its memory port
#             and its IU;
#   tu_slots  the TU alone with those slots, its IU answered out of order by the harness;
#   tu_pipe   the TU alone with rpu_tu_cosim_pipe_slots slots sharing one node-step
#             pipeline, rpu_tu_cosim_pipe_setups set-up engines and 2^rpu_tu_cosim_line_tag_bits
#             lines in flight (rpu_tu_pipe), its memory answered by tag in any order;
#   ray_pipe  the ray unit with it.
# Every kind in fp32 with Woop's test, the others every kind but tu_slots (whose walker
# slots no named configuration has). The `ci` tier builds the units of its chips and one
# of each other kind: in fp32 Woop the TU alone and the ray unit with walkers (tiny's),
# the TU alone with packets and the ray unit with them (default's); in rpu24 Woop the ray
# unit with packets (rpu2005's and drpu's); in fp32 watertight the pipelined ray unit of
# single rays; no rpu24 watertight. rpu_tu_built lists what is built, "<format> <isect>
# <kind>".
set(rpu_tu_cosim_slots 4)
set(rpu_tu_cosim_pipe_slots 16)
set(rpu_tu_cosim_pipe_setups 4)
set(rpu_tu_cosim_line_tag_bits 4)
set(rpu_tu_kind_tu "0 1 0 1")
set(rpu_tu_kind_ray "1 ${rpu_tu_cosim_slots} 0 1")
set(rpu_tu_kind_tu_slots "0 ${rpu_tu_cosim_slots} 0 1")
set(rpu_tu_kind_tu_pipe "0 ${rpu_tu_cosim_pipe_slots} 1 1")
set(rpu_tu_kind_ray_pipe "1 ${rpu_tu_cosim_pipe_slots} 1 1")
set(rpu_tu_kind_tu_packet2 "0 ${rpu_tu_cosim_pipe_slots} 1 2")
set(rpu_tu_kind_tu_packet4 "0 ${rpu_tu_cosim_pipe_slots} 1 4")
set(rpu_tu_kind_ray_packet4 "1 ${rpu_tu_cosim_pipe_slots} 1 4")
set(rpu_tu_built)
foreach(format IN LISTS rpu_ray_unit_formats)
  foreach(isect woop watertight)
    if("${format} ${isect}" STREQUAL "fp32 woop" AND RPU_COSIM_TIER STREQUAL "full")
      set(kinds tu ray tu_slots tu_pipe ray_pipe tu_packet2 tu_packet4 ray_packet4)
    elseif("${format} ${isect}" STREQUAL "fp32 woop")
      set(kinds tu ray tu_packet4 ray_packet4)
    elseif(RPU_COSIM_TIER STREQUAL "full")
      set(kinds tu ray tu_pipe ray_pipe tu_packet2 tu_packet4 ray_packet4)
    elseif("${format} ${isect}" STREQUAL "rpu24 woop")
      set(kinds ray_packet4)
    elseif("${format} ${isect}" STREQUAL "fp32 watertight")
      set(kinds ray_pipe)
    else()
      set(kinds)
    endif()
    foreach(kind IN LISTS kinds)
      rpu_fields("${rpu_tu_kind_${kind}}" with_iu slots pipe packet)
      set(prefix Vtu_${format}_${isect})
      if(with_iu)
        set(prefix Vray_${format}_${isect})
      endif()
      if(NOT slots EQUAL 1)
        string(APPEND prefix _s${slots})
      endif()
      if(pipe)
        string(APPEND prefix _pipe)
      endif()
      if(NOT packet EQUAL 1)
        string(APPEND prefix _p${packet})
      endif()
      rpu_cosim_model(tu ${prefix} TRACE
                      FACTS format=${format} isect=${isect} with_iu=${with_iu} slots=${slots} pipe=${pipe}
                            packet=${packet} setups=${rpu_tu_cosim_pipe_setups}
                            line_tag_bits=${rpu_tu_cosim_line_tag_bits}
                      PARAMS ${rpu_widths_${format}} -GIsectMode=${rpu_isect_${isect}} -GWithIu=${with_iu}
                             -GSlots=${slots} -GPipe=${pipe} -GPacket=${packet} -GSetups=${rpu_tu_cosim_pipe_setups}
                             -GLineTagBits=${rpu_tu_cosim_line_tag_bits})
      list(APPEND rpu_tu_built "${format} ${isect} ${kind}")
    endforeach()
    if(kinds)
      list(APPEND rpu_tu_cosim_cases "${format} ${isect}")
    endif()
  endforeach()
endforeach()
rpu_cosim_registry(tu)

add_executable(tu_cosim tu_cosim.cpp)
target_link_libraries(tu_cosim PRIVATE rpu_tu_rtl_models rpu_sim_host rpu_test_support rpu_output_file rpu_cycle CLI11::CLI11 rpu_flags)

# The ray units' test scenes, and a test name's part for one ("balls:2" -> balls2).
set(rpu_ray_scenes cornell balls:2 ${PROJECT_SOURCE_DIR}/scenes/bunny.json)
function(rpu_scene_name out scene)
  get_filename_component(name "${scene}" NAME_WE)
  string(REPLACE ":" "" name "${name}")
  set(${out} "${name}" PARENT_SCOPE)
endfunction()

# tu_test(NAME LABEL TIMEOUT ARGS...): a tu_cosim run as a test.
function(rpu_tu_test name label timeout)
  add_test(NAME ${name} COMMAND tu_cosim ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS ${label} TIMEOUT ${timeout})
endfunction()

# Rays of each kind per scene in the cycle model's comparisons with the RTL ray units.
set(rpu_cycle_model_rays 3300)
if(RPU_COSIM_TIER STREQUAL "ci")
  set(rpu_cycle_model_rays 1000)
endif()

# Per format, mode and scene, what the build has of (CI budget, docs/rtl.md): the TU alone
# (tu), with the RTL IU (ray, 3-8x slower), the TU with a shared node-step pipeline, its IU
# answered in random order by tag (tu_pipe, 24 in flight), and the ray unit built with it
# (ray_pipe). Rays of each kind (camera, random, shadow): in CI 1,000 through a TU alone
# and 500 through a ray unit; under `slow` 34,000 (10^5 rays per scene) through each.
foreach(case IN LISTS rpu_tu_cosim_cases)
  rpu_fields("${case}" format isect)
  # The configuration named for the format, whose step cycles the cycle model takes.
  if(format STREQUAL "fp32")
    set(config default)
  else()
    set(config rpu2005)
  endif()
  foreach(scene IN LISTS rpu_ray_scenes)
    rpu_scene_name(scene_name "${scene}")
    set(at ${scene_name}.${format}.${isect})
    set(args --scene ${scene} --format ${format} --isect ${isect})
    set(ray_args ${args} --with-iu --slots ${rpu_tu_cosim_slots} --in-flight 8)
    set(pipe_args ${args} --pipe --slots ${rpu_tu_cosim_pipe_slots} --in-flight 24)
    if("${format} ${isect} tu" IN_LIST rpu_tu_built)
      rpu_tu_test(cosim.tu.${at} cosim 900 ${args} --rays 1000)
      rpu_tu_test(slow.cosim.tu.${at} slow 7200 ${args} --rays 34000)
    endif()
    if("${format} ${isect} ray" IN_LIST rpu_tu_built)
      rpu_tu_test(cosim.ray.${at} cosim 900 ${ray_args} --rays 500)
      rpu_tu_test(slow.cosim.ray.${at} slow 7200 ${ray_args} --rays 34000)
    endif()
    if("${format} ${isect} tu_pipe" IN_LIST rpu_tu_built)
      rpu_tu_test(cosim.tu_pipe.${at} cosim 900 ${pipe_args} --rays 1000)
      rpu_tu_test(slow.cosim.tu_pipe.${at} slow 7200 ${pipe_args} --rays 34000)
    endif()
    if("${format} ${isect} ray_pipe" IN_LIST rpu_tu_built)
      rpu_tu_test(cosim.ray_pipe.${at} cosim 900 ${pipe_args} --with-iu --rays 500)
      # The cycle model's pipelined unit against the RTL ray unit's, cycle for cycle, at
      # the pipe_* cycles of the configuration (spec/latencies.toml [tu]).
      rpu_tu_test(cosim.ray_pipe.cycle_model.${at} cosim 900 ${pipe_args} --with-iu --rays ${rpu_cycle_model_rays}
                  --stall 0 --mem-jitter 0 --cycle-model ${config} --cycle-tolerance 0)
      # ... with the lines answered out of request order (--mem-spread: a delay of 0-12
      # cycles by address): the unit's line table and the model's, by tag (fp32 Woop).
      if("${format} ${isect}" STREQUAL "fp32 woop")
        rpu_tu_test(cosim.ray_pipe.cycle_model_spread.${at} cosim 900 ${pipe_args} --with-iu
                    --rays ${rpu_cycle_model_rays} --stall 0 --mem-jitter 0 --mem-spread 12 --cycle-model ${config}
                    --cycle-tolerance 0)
      endif()
      rpu_tu_test(slow.cosim.ray_pipe.${at} slow 7200 ${pipe_args} --with-iu --rays 34000)
    endif()
    # Packets (docs/traversal.md "Packets"): every ray's answer and counters the single
    # walk's, with the rays in packets of 2 and 4 (some ended early).
    foreach(packet 2 4)
      if("${format} ${isect} tu_packet${packet}" IN_LIST rpu_tu_built)
        rpu_tu_test(cosim.tu_packet${packet}.${at} cosim 900 ${pipe_args} --packet ${packet} --rays 1000)
        rpu_tu_test(slow.cosim.tu_packet${packet}.${at} slow 7200 ${pipe_args} --packet ${packet} --rays 34000)
      endif()
    endforeach()
    if("${format} ${isect} ray_packet4" IN_LIST rpu_tu_built)
      rpu_tu_test(cosim.ray_packet4.${at} cosim 900 ${pipe_args} --with-iu --packet 4 --rays 500)
      # The cycle model's unit with packets against the RTL's, cycle for cycle and node line
      # for node line, with lines answered in order of address hash too (--mem-spread).
      rpu_tu_test(cosim.ray_packet4.cycle_model.${at} cosim 900 ${pipe_args} --with-iu --packet 4
                  --rays ${rpu_cycle_model_rays} --stall 0 --mem-jitter 0 --cycle-model ${config} --cycle-tolerance 0)
      rpu_tu_test(cosim.ray_packet4.cycle_model_spread.${at} cosim 900 ${pipe_args} --with-iu --packet 4
                  --rays ${rpu_cycle_model_rays} --stall 0 --mem-jitter 0 --mem-spread 12 --cycle-model ${config}
                  --cycle-tolerance 0)
      rpu_tu_test(slow.cosim.ray_packet4.${at} slow 7200 ${pipe_args} --with-iu --packet 4 --rays 34000)
    endif()
  endforeach()
  if(NOT "${format} ${isect} ray" IN_LIST rpu_tu_built)
    continue()
  endif()
  # The Cornell box at 2^-60 and 2^60 of its size: kd scale exponents of -56 and 64
  # through the ray unit's scaling of rays and hits (docs/traversal.md §1).
  foreach(k -60 60)
    string(REPLACE "-" "m" k_name "${k}")
    rpu_tu_test(cosim.ray.cornell_2e${k_name}.${format}.${isect} cosim 900 --scene cornell --scale ${k}
                --format ${format} --isect ${isect} --with-iu --slots ${rpu_tu_cosim_slots} --in-flight 8 --rays 300)
  endforeach()
endforeach()

# The cycle model's ray unit against the RTL's (docs/cycle-model.md "Traversal and
# intersection units"): the same 10^4 rays per scene (3,000 in the ci tier), 4 slots, the
# cycles within 2%, at the step cycles of the named configuration in that format; fp32
# Woop in CI, the rest under slow.
foreach(pair "fp32 default" "rpu24 rpu2005")
  rpu_fields("${pair}" format config)
  foreach(isect woop watertight)
    if(NOT "${format} ${isect} ray" IN_LIST rpu_tu_built)
      continue()
    endif()
    set(name cosim.ray.cycle_model)
    set(label cosim)
    if(NOT "${format} ${isect}" STREQUAL "fp32 woop")
      set(name slow.cosim.ray.cycle_model)
      set(label slow)
    endif()
    foreach(scene IN LISTS rpu_ray_scenes)
      rpu_scene_name(scene_name "${scene}")
      rpu_tu_test(${name}.${scene_name}.${format}.${isect} ${label} 1800 --scene ${scene} --format ${format}
                  --isect ${isect} --with-iu --slots ${rpu_tu_cosim_slots} --in-flight 8 --rays ${rpu_cycle_model_rays}
                  --stall 0 --mem-jitter 0 --cycle-model ${config} --cycle-tolerance 2)
    endforeach()
  endforeach()
endforeach()

# The TU alone with ray slots, its IU answers in random order by tag.
if("fp32 woop tu_slots" IN_LIST rpu_tu_built)
  foreach(scene IN LISTS rpu_ray_scenes)
    rpu_scene_name(scene_name "${scene}")
    rpu_tu_test(cosim.tu_slots.${scene_name}.fp32.woop cosim 900 --scene ${scene} --format fp32 --isect woop
                --slots ${rpu_tu_cosim_slots} --in-flight 8 --rays 1000)
  endforeach()
endif()

# --trace's failures (rpu_trace_outputs_test).
if("fp32 woop tu" IN_LIST rpu_tu_built)
  rpu_trace_outputs_test(tu --
                         $<TARGET_FILE:tu_cosim> --scene cornell --format fp32 --isect woop --rays 100)
endif()

# The step cycles of spec/latencies.toml [tu.<format>] against the RTL's (docs/rtl.md):
# every walking ray's cycles besides memory and IU waits must equal setup + inner * inner
# nodes + leaf * leaves + pop * pops with the table's numbers.
execute_process(COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/spec/gen.py
                        --spec-dir ${PROJECT_SOURCE_DIR}/spec --list tu-timing
                OUTPUT_VARIABLE rpu_tu_timing_lines COMMAND_ERROR_IS_FATAL ANY)
string(REPLACE "\n" ";" rpu_tu_timing_lines "${rpu_tu_timing_lines}")
foreach(line IN LISTS rpu_tu_timing_lines)
  if(NOT line)
    continue()
  endif()
  rpu_fields("${line}" format setup_woop setup_watertight inner leaf pop)
  foreach(isect woop watertight)
    if(NOT "${format} ${isect} tu" IN_LIST rpu_tu_built)
      continue()
    endif()
    add_test(NAME cosim.tu.timing.${format}.${isect}
             COMMAND tu_cosim --scene cornell --format ${format} --isect ${isect} --rays 1000
                     --expect-timing ${setup_${isect}},${inner},${leaf},${pop})
    set_tests_properties(cosim.tu.timing.${format}.${isect} PROPERTIES LABELS cosim TIMEOUT 300)
  endforeach()
endforeach()

# Synthesis of the TU with Yosys, the netlist walking 10^4 Cornell box rays with the
# memory image and the Tracer's IU tests (rtl/flow.py synth --unit tu). All under
# `slow`: for Woop fp16, Yosys and the Verilated netlist's build alone took 327 s CPU
# (docs/rtl.md, docs/area.md).
if(RPU_YOSYS)
  foreach(isect woop watertight)
    foreach(format fp16 rpu24 fp32)
      add_test(NAME slow.synth.tu_${isect}.${format}
        COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
                --unit tu --isect ${isect} --format ${format} --pkg ${RPU_SPEC_SV}
                --cosim $<TARGET_FILE:tu_cosim> --out ${CMAKE_CURRENT_BINARY_DIR}/synth --vectors 10000
                --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
      set_tests_properties(slow.synth.tu_${isect}.${format} PROPERTIES LABELS slow TIMEOUT 3600)
    endforeach()
  endforeach()
  # The price of a ray slot (docs/area.md): rpu_tu_slots with 2 and 4 slots, its netlist
  # keeping that many rays in flight with the IU's answers out of order.
  foreach(slots 2 4)
    add_test(NAME slow.synth.tu_woop.fp16.slots${slots}
      COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
              --unit tu --isect woop --format fp16 --slots ${slots} --pkg ${RPU_SPEC_SV}
              --cosim $<TARGET_FILE:tu_cosim> --out ${CMAKE_CURRENT_BINARY_DIR}/synth --vectors 10000
              --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
    set_tests_properties(slow.synth.tu_woop.fp16.slots${slots} PROPERTIES LABELS slow TIMEOUT 7200)
  endforeach()
  # The price of packets (docs/area.md): rpu_tu_pipe with 4 slots of packets of 4 rays,
  # its netlist walking 10^4 rays in packets.
  add_test(NAME slow.synth.tu_woop.fp16.pipe4.packet4
    COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
            --unit tu --isect woop --format fp16 --slots 4 --pipe --setups 2 --packet 4 --pkg ${RPU_SPEC_SV}
            --cosim $<TARGET_FILE:tu_cosim> --out ${CMAKE_CURRENT_BINARY_DIR}/synth --vectors 10000
            --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
  set_tests_properties(slow.synth.tu_woop.fp16.pipe4.packet4 PROPERTIES LABELS slow TIMEOUT 7200)
  # rpu2005's and drpu's traversal unit (packets of 4 in rpu24) with 4 and 8 slots, for
  # the chips' area estimates, which extrapolate to their 16 (docs/area.md "Chips that
  # were not synthesised whole"; Yosys ran out of 24 GB on 16): synthesis only, the
  # netlist's walk is the one above.
  foreach(slots 4 8)
    add_test(NAME slow.synth.tu_woop.rpu24.pipe${slots}.packet4
      COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
              --unit tu --isect woop --format rpu24 --slots ${slots} --pipe --setups 2 --packet 4
              --pkg ${RPU_SPEC_SV} --out ${CMAKE_CURRENT_BINARY_DIR}/synth --yosys ${RPU_YOSYS})
    set_tests_properties(slow.synth.tu_woop.rpu24.pipe${slots}.packet4 PROPERTIES LABELS slow TIMEOUT 7200)
  endforeach()
  # rpu_tu_pipe with 4 and 16 slots and 2 set-up engines, its netlist walking 10^4 rays
  # with its slots full and several tests of a ray in flight (docs/area.md).
  foreach(slots 4 16)
    add_test(NAME slow.synth.tu_woop.fp16.pipe${slots}
      COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
              --unit tu --isect woop --format fp16 --slots ${slots} --pipe --setups 2 --pkg ${RPU_SPEC_SV}
              --cosim $<TARGET_FILE:tu_cosim> --out ${CMAKE_CURRENT_BINARY_DIR}/synth --vectors 10000
              --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
    set_tests_properties(slow.synth.tu_woop.fp16.pipe${slots} PROPERTIES LABELS slow TIMEOUT 7200)
  endforeach()
endif()
