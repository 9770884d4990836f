# The shader core (docs/chip.md "Shader core"): one Verilated rpu_spu per named
# configuration of spec/configs.toml, its build-time parameters from the same table
# (gen.py --list rtl-configs); spu_cosim runs firmware on it in lockstep with the
# functional model (sim/spu_checker.hpp).
execute_process(COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/spec/gen.py
                        --spec-dir ${PROJECT_SOURCE_DIR}/spec --list rtl-configs
                OUTPUT_VARIABLE rpu_rtl_config_lines COMMAND_ERROR_IS_FATAL ANY)
string(REPLACE "\n" ";" rpu_rtl_config_lines "${rpu_rtl_config_lines}")
set(rpu_spu_code_words 4096)

set(rpu_spu_configs)
rpu_cosim_library(spu)
foreach(line IN LISTS rpu_rtl_config_lines)
  if(NOT line)
    continue()
  endif()
  rpu_rtl_config("${line}" spu config config_params)
  string(REGEX MATCH "-GIssueLanes=([0-9]+)" issue_lanes_flag "${line}")
  set(issue_lanes ${CMAKE_MATCH_1})
  string(REGEX MATCH "-GSfuThreads=([0-9]+)" sfu_threads_flag "${line}")
  set(facts config=${config} issue_lanes=${issue_lanes} sfu_threads=${CMAKE_MATCH_1} code_words=${rpu_spu_code_words})
  # A core another configuration already has (drpu's is rpu2005's) is built once, and
  # its tests are that configuration's.
  string(MD5 core_key "${config_params}")
  if(DEFINED rpu_spu_core_${core_key})
    rpu_cosim_alias(spu ${rpu_spu_core_${core_key}} FACTS ${facts})
    continue()
  endif()
  set(rpu_spu_core_${core_key} Vspu_${config})
  rpu_cosim_model(spu Vspu_${config} TRACE ASSERT FACTS ${facts}
                  PARAMS -GCodeWords=${rpu_spu_code_words} ${config_params})
  list(APPEND rpu_spu_configs ${config})
  # tiny's chunks of 2 also as a core that issues both lanes at once (--issue-lanes 2),
  # and as one with an sfu for each lane (--sfu-threads 2).
  if(config STREQUAL "tiny")
    set(lanes2_params ${config_params})
    list(FILTER lanes2_params EXCLUDE REGEX "^-GIssueLanes=")
    rpu_cosim_model(spu Vspu_tiny_lanes2 TRACE ASSERT
                    FACTS config=tiny issue_lanes=2 sfu_threads=1 code_words=${rpu_spu_code_words}
                    PARAMS -GCodeWords=${rpu_spu_code_words} ${lanes2_params} -GIssueLanes=2)
    set(sfus2_params ${config_params})
    list(FILTER sfus2_params EXCLUDE REGEX "^-GSfuThreads=")
    rpu_cosim_model(spu Vspu_tiny_sfus2 TRACE ASSERT
                    FACTS config=tiny issue_lanes=${issue_lanes} sfu_threads=2 code_words=${rpu_spu_code_words}
                    PARAMS -GCodeWords=${rpu_spu_code_words} ${sfus2_params} -GSfuThreads=2)
  endif()
endforeach()
rpu_cosim_registry(spu)

add_library(rpu_spu_check STATIC spu_checker.cpp spu_agents.cpp)
target_include_directories(rpu_spu_check PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(rpu_spu_check PUBLIC rpu_sim_host rpu_functional rpu_isa rpu_progen fmt::fmt PRIVATE rpu_flags)

add_executable(spu_cosim spu_cosim.cpp)
target_link_libraries(spu_cosim PRIVATE rpu_spu_rtl_models rpu_spu_check rpu_device rpu_asm rpu_builtin_firmware
                      rpu_scene rpu_kdtree rpu_output_file CLI11::CLI11 rpu_flags)

rpu_trace_outputs_test(spu --
                       $<TARGET_FILE:spu_cosim> --config tiny --scene cornell --width 2 --height 2 --max-depth 0)

# Frames of the built-in firmware on every configuration's core.
foreach(config IN LISTS rpu_spu_configs)
  foreach(scene cornell balls:1)
    string(REPLACE ":" "" scene_name "${scene}")
    add_test(NAME cosim.spu.${config}.${scene_name}
             COMMAND spu_cosim --config ${config} --scene ${scene} --width 8 --height 6 --max-depth 2)
    set_tests_properties(cosim.spu.${config}.${scene_name} PROPERTIES LABELS cosim TIMEOUT 900)
  endforeach()
endforeach()
add_test(NAME cosim.spu.tiny_lanes2.cornell
         COMMAND spu_cosim --config tiny --issue-lanes 2 --scene cornell --width 8 --height 6 --max-depth 2)
set_tests_properties(cosim.spu.tiny_lanes2.cornell PROPERTIES LABELS cosim TIMEOUT 900)
add_test(NAME cosim.spu.tiny_sfus2.balls1
         COMMAND spu_cosim --config tiny --sfu-threads 2 --scene balls:1 --width 8 --height 6 --max-depth 2)
set_tests_properties(cosim.spu.tiny_sfus2.balls1 PROPERTIES LABELS cosim TIMEOUT 900)

# Every instruction and fault program of tests/isa on the core its .exp names (the
# programs in a format other than their configuration's are the functional tests' alone).
file(GLOB rpu_isa_programs ${PROJECT_SOURCE_DIR}/tests/isa/programs/*.s)
foreach(program IN LISTS rpu_isa_programs)
  get_filename_component(name ${program} NAME_WE)
  string(REGEX REPLACE "\\.s$" ".exp" exp ${program})
  file(STRINGS ${exp} exp_lines REGEX "^(config|scene|format) ")
  set(config tiny)
  set(scene tetra:1)
  set(other_format FALSE)
  foreach(l IN LISTS exp_lines)
    if(l MATCHES "^config ([^ ]+)")
      set(config ${CMAKE_MATCH_1})
    elseif(l MATCHES "^scene ([^ ]+)")
      set(scene ${PROJECT_SOURCE_DIR}/${CMAKE_MATCH_1})
    elseif(l MATCHES "^format ")
      set(other_format TRUE)
    endif()
  endforeach()
  if(other_format OR NOT config IN_LIST rpu_spu_configs)
    continue()
  endif()
  add_test(NAME cosim.spu.isa.${name}
           COMMAND spu_cosim --config ${config} --scene ${scene} --firmware ${program} --empty-shader-table
                   --width 3 --height 2 --max-depth 0 --watchdog 100000)
  set_tests_properties(cosim.spu.isa.${name} PROPERTIES LABELS cosim TIMEOUT 300)
endforeach()

# Random programs (sim/progen, docs/random-programs.md) in lockstep, every fifth ending
# in a fault class in turn, each chunk of a thousand required to cover every
# instruction, event and fault class: programs of at most 5 statements a block, 4,000 on
# tiny and 3,000 on each other core (1,000 in the `ci` tier); `slow` and `soak`: 10^6 of
# progen's full size.
foreach(config IN LISTS rpu_spu_configs)
  set(chunks 3)
  if(config STREQUAL "tiny")
    set(chunks 4)
  elseif(RPU_COSIM_TIER STREQUAL "ci")
    set(chunks 1)
  endif()
  math(EXPR last "${chunks} - 1")
  foreach(k RANGE ${last})
    math(EXPR seed "1 + ${k} * 1000")
    add_test(NAME cosim.spu.random.${config}.${k}
             COMMAND spu_cosim --config ${config} --scene tetra:1 --width 3 --height 2 --random 1000 --seed ${seed}
                     --statements 5 --require-coverage)
    set_tests_properties(cosim.spu.random.${config}.${k} PROPERTIES LABELS cosim TIMEOUT 900)
  endforeach()
  if(config STREQUAL "tiny")
    add_test(NAME cosim.spu.random.tiny_lanes2
             COMMAND spu_cosim --config tiny --issue-lanes 2 --scene tetra:1 --width 3 --height 2 --random 1000
                     --seed 7001 --statements 5 --require-coverage)
    set_tests_properties(cosim.spu.random.tiny_lanes2 PROPERTIES LABELS cosim TIMEOUT 900)
  endif()
  # The first 33,334 in `slow` (16 to 41 min each); the other 300,006 a core in `soak`
  # (about 5 h a core on one host core), for a machine left to them; `soak` tests carry
  # `slow` too, so `-LE slow` leaves them out.
  foreach(k RANGE 9)
    math(EXPR seed "1000000 + ${k} * 33334")
    set(tier slow)
    set(labels slow)
    if(k GREATER 0)
      set(tier soak)
      set(labels "slow;soak")
    endif()
    add_test(NAME ${tier}.cosim.spu.random.${config}.${k}
             COMMAND spu_cosim --config ${config} --scene tetra:1 --width 3 --height 2 --random 33334 --seed ${seed}
                     --require-coverage)
    set_tests_properties(${tier}.cosim.spu.random.${config}.${k} PROPERTIES LABELS "${labels}" TIMEOUT 14400)
  endforeach()
endforeach()
