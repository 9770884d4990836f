# The chip (docs/chip.md): one Verilated rpu_top per named configuration of
# spec/configs.toml (its build-time parameters from gen.py --list rtl-configs) with the
# Woop test, and tiny's also with the watertight test; chip_cosim renders frames on it
# with every core in lockstep, and the rtl backend of the Device API (rtl_device.hpp)
# renders on it for `rpu render --backend rtl`. RPU_CHIP_MODELS narrows the set (CI
# builds two: its time budget, docs/rtl.md "Tiers").
set(RPU_CHIP_MODELS "" CACHE STRING
    "Chips to verilate as config/isect pairs, e.g. tiny/woop;rpu2005/woop (default: all)")
set(RPU_CHIP_THREADS 1 CACHE STRING
    "Host threads a chip model's evaluation uses (Verilator --threads; docs/chip.md \"Simulation speed\")")
set(rpu_chip_cases)
rpu_cosim_library(chip)
foreach(line IN LISTS rpu_rtl_config_lines)
  if(NOT line)
    continue()
  endif()
  rpu_rtl_config("${line}" chip config config_params)
  set(params -GCodeWords=${rpu_spu_code_words} ${config_params})
  string(REGEX MATCH "-GCores=([0-9]+)" cores_flag "${line}")
  set(cores ${CMAKE_MATCH_1})
  string(REGEX MATCH "-GRayUnits=([0-9]+)" ray_units_flag "${line}")
  set(ray_units ${CMAKE_MATCH_1})
  string(REGEX MATCH "-GRayCaches=([0-9]+)" ray_caches_flag "${line}")
  set(ray_caches ${CMAKE_MATCH_1})
  string(REGEX MATCH "-GIssueLanes=([0-9]+)" issue_lanes_flag "${line}")
  set(issue_lanes ${CMAKE_MATCH_1})
  set(isects woop)
  if(config STREQUAL "tiny")
    list(APPEND isects watertight)
  endif()
  foreach(isect IN LISTS isects)
    if(RPU_CHIP_MODELS AND NOT "${config}/${isect}" IN_LIST RPU_CHIP_MODELS)
      continue()
    endif()
    rpu_cosim_model(chip Vchip_${config}_${isect} TRACE ASSERT THREADS ${RPU_CHIP_THREADS}
                    FACTS config=${config} isect=${isect} cores=${cores} ray_units=${ray_units} ray_caches=${ray_caches}
                          issue_lanes=${issue_lanes} code_words=${rpu_spu_code_words}
                    PARAMS ${params} -GIsectMode=${rpu_isect_${isect}})
    list(APPEND rpu_chip_cases "${config} ${isect}")
  endforeach()
endforeach()
rpu_cosim_registry(chip)

add_library(rpu_rtl_device STATIC chip_run.cpp device_dram.cpp rtl_device.cpp)
target_include_directories(rpu_rtl_device PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(rpu_rtl_device PUBLIC rpu_device rpu_cycle PRIVATE rpu_chip_rtl_models rpu_spu_check rpu_config
                      fmt::fmt rpu_flags)

add_executable(chip_cosim chip_cosim.cpp)
target_link_libraries(chip_cosim PRIVATE rpu_rtl_device rpu_chip_rtl_models rpu_asm rpu_builtin_firmware rpu_scene
                      rpu_kdtree rpu_output_file CLI11::CLI11 rpu_flags)

# Frames in lockstep on every configuration's chip.
foreach(case IN LISTS rpu_chip_cases)
  rpu_fields("${case}" config isect)
  foreach(scene cornell balls:1)
    string(REPLACE ":" "" scene_name "${scene}")
    add_test(NAME cosim.chip.${config}.${isect}.${scene_name}
             COMMAND chip_cosim --config ${config} --isect ${isect} --scene ${scene} --width 8 --height 6
                     --max-depth 2)
    set_tests_properties(cosim.chip.${config}.${isect}.${scene_name} PROPERTIES LABELS cosim TIMEOUT 900)
  endforeach()
endforeach()

# Frames of `rpu render --backend rtl` equal to `--backend functional` bit for bit, on
# every configuration's chip: the Cornell box, SPD balls, the bunny and a mesh no other
# test renders (Assimp's Wuson); small in CI, larger under `slow`.
find_program(RPU_IDIFF idiff)
if(RPU_IDIFF)
  set(rpu_frame_scenes cornell balls:1 ${PROJECT_SOURCE_DIR}/scenes/bunny.json
      /usr/share/assimp/models/OBJ/WusonOBJ.obj)
  foreach(case IN LISTS rpu_chip_cases)
    rpu_fields("${case}" config isect)
    foreach(scene IN LISTS rpu_frame_scenes)
      get_filename_component(scene_name "${scene}" NAME_WE)
      string(REPLACE ":" "" scene_name "${scene_name}")
      if(scene MATCHES "^/" AND NOT EXISTS ${scene})
        continue()
      endif()
      set(name frame.${config}.${isect}.${scene_name})
      add_test(NAME cosim.${name}
               COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/rtl_frames.py ${CMAKE_CURRENT_BINARY_DIR}/${name}
                       ${RPU_IDIFF} -- $<TARGET_FILE:rpu> ${scene} --config ${config} --isect ${isect}
                       --width 8 --height 6 --spp 1 --max-depth 2)
      set_tests_properties(cosim.${name} PROPERTIES LABELS cosim TIMEOUT 900)
      add_test(NAME slow.cosim.${name}
               COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/rtl_frames.py
                       ${CMAKE_CURRENT_BINARY_DIR}/slow_${name} ${RPU_IDIFF} -- $<TARGET_FILE:rpu> ${scene}
                       --config ${config} --isect ${isect} --width 64 --height 48 --spp 2 --max-depth 3)
      set_tests_properties(slow.cosim.${name} PROPERTIES LABELS slow TIMEOUT 14400)
    endforeach()
    # Selected ray tracing (docs/selection.md): two launches, the second reading the
    # first's framebuffer from the launch segment; blocks cut short by the frame's edge.
    set(name frame_select.${config}.${isect}.cornell)
    add_test(NAME cosim.${name}
             COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/rtl_frames.py ${CMAKE_CURRENT_BINARY_DIR}/${name}
                     ${RPU_IDIFF} -- $<TARGET_FILE:rpu> cornell --config ${config} --isect ${isect}
                     --width 11 --height 8 --spp 1 --max-depth 2 --select 3:0.05)
    set_tests_properties(cosim.${name} PROPERTIES LABELS cosim TIMEOUT 900)
    # The compiled GLSL Whitted (docs/shaders.md) on the chip: the same frame as the
    # functional model's (which equals firmware/whitted.s's: tests/glsl).
    set(glsl ${PROJECT_SOURCE_DIR}/firmware/glsl)
    set(name frame_glsl.${config}.${isect}.cornell)
    add_test(NAME cosim.${name}
             COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/rtl_frames.py ${CMAKE_CURRENT_BINARY_DIR}/${name}
                     ${RPU_IDIFF} -- $<TARGET_FILE:rpu> cornell --config ${config} --isect ${isect}
                     --width 8 --height 6 --spp 2 --max-depth 2
                     --firmware ${glsl}/whitted.rgen ${glsl}/whitted.rchit ${glsl}/background.rmiss)
    set_tests_properties(cosim.${name} PROPERTIES LABELS cosim TIMEOUT 900
                         ENVIRONMENT RPU_CACHE_DIR=${CMAKE_CURRENT_BINARY_DIR}/cc-cache)
    # A raygen that reads its pixel back (imageLoad) before each imageStore: the stores
    # hit the line the load brought into the data cache, so with write-back the image
    # reaches memory only through the end-of-frame flush.
    set(name frame_image_load.${config}.${isect})
    add_test(NAME cosim.${name}
             COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/rtl_frames.py ${CMAKE_CURRENT_BINARY_DIR}/${name}
                     ${RPU_IDIFF} -- $<TARGET_FILE:rpu> cornell --config ${config} --isect ${isect}
                     --width 8 --height 6 --spp 1 --max-depth 1
                     --firmware ${PROJECT_SOURCE_DIR}/tests/glsl/programs/image_load/raygen.rgen ${glsl}/whitted.rchit
                     ${glsl}/background.rmiss)
    set_tests_properties(cosim.${name} PROPERTIES LABELS cosim TIMEOUT 900
                         ENVIRONMENT RPU_CACHE_DIR=${CMAKE_CURRENT_BINARY_DIR}/cc-cache)
    # The library's distributed effects (thin lens, glossy lobe): the camera record and
    # the material's roughness as the chip reads them.
    set(name frame_glsl_distributed.${config}.${isect})
    add_test(NAME cosim.${name}
             COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/rtl_frames.py ${CMAKE_CURRENT_BINARY_DIR}/${name}
                     ${RPU_IDIFF} -- $<TARGET_FILE:rpu> ${PROJECT_SOURCE_DIR}/scenes/cornell_distributed.json
                     --config ${config} --isect ${isect} --width 8 --height 6 --spp 2 --max-depth 2
                     --firmware ${glsl}/thin_lens.rgen ${glsl}/whitted.rchit ${glsl}/glossy.rchit
                     ${glsl}/background.rmiss)
    set_tests_properties(cosim.${name} PROPERTIES LABELS cosim TIMEOUT 900
                         ENVIRONMENT RPU_CACHE_DIR=${CMAKE_CURRENT_BINARY_DIR}/cc-cache)
  endforeach()
endif()

# The cycle model's shader-core timing against the chip's, loop by loop (docs/chip.md
# "Calibration"), on every configuration's chip.
foreach(case IN LISTS rpu_chip_cases)
  rpu_fields("${case}" config isect)
  if(isect STREQUAL "woop")
    add_test(NAME cosim.timing.core.${config}
             COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/core_timing.py $<TARGET_FILE:rpu> --config ${config})
    # COST (about its seconds in CI): a fresh build has no timings, and ctest starts the
    # costliest tests first instead of leaving them to run alone at the end.
    set(cost 70)
    if(config STREQUAL "default")
      set(cost 120)  # its ray loops also run on two and four lanes of four ray units
    endif()
    set_tests_properties(cosim.timing.core.${config} PROPERTIES LABELS cosim TIMEOUT 900 COST ${cost})
  endif()
  # The same loops on 4 and 8 chunks of rpu2005's one core: chunks that contend for
  # the code memory, the load/store unit's queue and miss registers and the pipeline's
  # entry (docs/cycle-model.md "Shader cores").
  if(isect STREQUAL "woop" AND config STREQUAL "rpu2005")
    add_test(NAME cosim.timing.core_chunks.${config}
             COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/core_timing.py $<TARGET_FILE:rpu> --config ${config}
                     --lanes 16 --lanes 32)
    set_tests_properties(cosim.timing.core_chunks.${config} PROPERTIES LABELS cosim TIMEOUT 900 COST 65)
  endif()
endforeach()

# The rtl backend's refusals (docs/chip.md "The rtl backend").
if(rpu_chip_cases)
  list(GET rpu_chip_cases 0 first_case)
  rpu_fields("${first_case}" config)
  set(cli ${PROJECT_SOURCE_DIR}/tests/cli/expect_cli.py)
  set(out ${CMAKE_CURRENT_BINARY_DIR})
  add_test(NAME cli.rtl_backend_refuses_a_changed_configuration
           COMMAND Python3::Interpreter ${cli} --status 1
                   --stderr "rpu: error: the rtl backend runs the named configurations as spec/configs.toml has them"
                   -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --set shader_cores=2
                   -o ${out}/never.png)
  add_test(NAME cli.rtl_backend_refuses_a_chip_not_built
           COMMAND Python3::Interpreter ${cli} --status 1
                   --stderr "rpu: error: no RTL chip model for configuration 'rpu2005' with the watertight test in this build \\(built: "
                   -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config rpu2005 --isect watertight
                   -o ${out}/never.png)
  add_test(NAME cli.rtl_backend_waves_must_be_fst
           COMMAND Python3::Interpreter ${cli} --status 1 --stderr "rpu: error: --waves .*never.vcd"
                   -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --waves ${out}/never.vcd
                   -o ${out}/never.png)
  # Waveforms record one launch; a selected frame takes two.
  add_test(NAME cli.rtl_backend_waves_refuse_a_selection
           COMMAND Python3::Interpreter ${cli} --status 1
                   --stderr "rpu: error: --waves records one launch and --select 2 renders the frame in two"
                   -- $<TARGET_FILE:rpu> render cornell --backend rtl --config ${config} --select 2
                   --waves ${out}/never.fst -o ${out}/never.png)
  add_test(NAME cli.rtl_backend_wave_window_needs_the_waves
           COMMAND Python3::Interpreter ${cli} --status 1
                   --stderr "rpu: error: --wave-window needs --waves: it chooses the cycles --waves records"
                   -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --wave-window 0 100
                   -o ${out}/never.png)
  add_test(NAME cli.rtl_backend_wave_window_must_not_be_empty
           COMMAND Python3::Interpreter ${cli} --status 1 --stderr "rpu: error: --wave-window 100 10: the window is empty"
                   -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --waves ${out}/never.fst
                   --wave-window 100 10 -o ${out}/never.png)
  # A shader that spins (a loop that writes nothing) is stopped on the chip as on the
  # models, at the default watchdog, within a minute (docs/robustness.md).
  foreach(case IN LISTS rpu_chip_cases)
    rpu_fields("${case}" config isect)
    add_test(NAME cli.rtl_backend_stops_a_spinning_shader_at_once.${config}.${isect}
             COMMAND Python3::Interpreter ${cli} --status 1
                     --stderr "rpu: error: shader fault in thread 0 .*pixel 0, 0\\) at pc 0 \\(bra 0\\): spin: the thread loops"
                     -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --isect ${isect}
                     --width 32 --height 32 --firmware ${PROJECT_SOURCE_DIR}/tests/cli/firmware/runaway.s
                     -o ${out}/never.png)
    set_tests_properties(cli.rtl_backend_stops_a_spinning_shader_at_once.${config}.${isect}
                         PROPERTIES LABELS unit TIMEOUT 60)
    # A GLSL shader's fault names its file:line on the RTL too.
    add_test(NAME cli.rtl_backend_names_a_glsl_faults_line.${config}.${isect}
             COMMAND Python3::Interpreter ${cli} --status 1
                     --stderr "rpu: error: shader fault in thread 0 .*: load of 16 bytes at address 0x[0-9a-f]+ is outside the device memory \\(${PROJECT_SOURCE_DIR}/tests/glsl/programs/fault_at_line/raygen.rgen:7\\x3b code label .*\\)"
                     -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --isect ${isect}
                     --width 4 --height 4 --spp 1
                     --firmware ${PROJECT_SOURCE_DIR}/tests/glsl/programs/fault_at_line/raygen.rgen
                     ${PROJECT_SOURCE_DIR}/firmware/glsl/whitted.rchit ${PROJECT_SOURCE_DIR}/firmware/glsl/background.rmiss
                     -o ${out}/never.png)
    set_tests_properties(cli.rtl_backend_names_a_glsl_faults_line.${config}.${isect} PROPERTIES LABELS unit TIMEOUT 60)
  endforeach()
  set_tests_properties(cli.rtl_backend_refuses_a_changed_configuration cli.rtl_backend_refuses_a_chip_not_built
                       cli.rtl_backend_waves_must_be_fst cli.rtl_backend_waves_refuse_a_selection
                       cli.rtl_backend_wave_window_needs_the_waves cli.rtl_backend_wave_window_must_not_be_empty
                       PROPERTIES LABELS unit)
  # A chip the ci tier built without waveforms (rpu_cosim_ci_waves) refuses --waves,
  # naming the file and the tier.
  foreach(case IN LISTS rpu_chip_cases)
    rpu_fields("${case}" config isect)
    if(NOT TEST cli.rtl_backend_waves_need_a_model_built_with_them
       AND RPU_COSIM_TIER STREQUAL "ci" AND NOT Vchip_${config}_${isect} IN_LIST rpu_cosim_ci_waves)
      add_test(NAME cli.rtl_backend_waves_need_a_model_built_with_them
               COMMAND Python3::Interpreter ${cli} --status 1
                       --stderr "rpu: error: .*no_waves.fst: this model was built without FST waveforms \\(the ci tier"
                       -- $<TARGET_FILE:rpu> render tetra:1 --backend rtl --config ${config} --isect ${isect}
                       --waves ${out}/no_waves.fst -o ${out}/never.png)
      set_tests_properties(cli.rtl_backend_waves_need_a_model_built_with_them PROPERTIES LABELS unit)
    endif()
  endforeach()
endif()

if(RPU_YOSYS)
  # The whole chip (rtl/flow.py synth --unit chip; docs/area.md): cells per unit for tiny
  # and default; tiny's netlist also replays every cycle of a Cornell box frame that
  # chip_cosim renders on the RTL, and its memory-port writes must rebuild the frame.
  if("tiny woop" IN_LIST rpu_chip_cases)
    add_test(NAME slow.synth.chip.tiny
      COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
              --unit chip --config tiny --netlist --code-words ${rpu_spu_code_words} --pkg ${RPU_SPEC_SV}
              --cosim $<TARGET_FILE:chip_cosim> --out ${CMAKE_CURRENT_BINARY_DIR}/synth_chip
              --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
    set_tests_properties(slow.synth.chip.tiny PROPERTIES LABELS slow TIMEOUT 14400)
  endif()
  add_test(NAME slow.synth.chip.default
    COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
            --unit chip --config default --code-words ${rpu_spu_code_words} --pkg ${RPU_SPEC_SV}
            --out ${CMAKE_CURRENT_BINARY_DIR}/synth_chip --yosys ${RPU_YOSYS})
  set_tests_properties(slow.synth.chip.default PROPERTIES LABELS slow TIMEOUT 14400)
  # rpu2005's shader core alone at one and four issue lanes: what issuing a chunk at once
  # costs (docs/area.md).
  foreach(lanes 1 4)
    add_test(NAME slow.synth.core.rpu2005.lanes${lanes}
      COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
              --unit core --config rpu2005 --issue-lanes ${lanes} --code-words ${rpu_spu_code_words}
              --pkg ${RPU_SPEC_SV} --out ${CMAKE_CURRENT_BINARY_DIR}/synth_chip --yosys ${RPU_YOSYS})
    set_tests_properties(slow.synth.core.rpu2005.lanes${lanes} PROPERTIES LABELS slow TIMEOUT 14400)
  endforeach()
endif()
