# The memory system (docs/memory-system.md): one Verilated rpu_mem_cosim_top per named
# configuration of spec/configs.toml, its caches' parameters from gen.py --list
# rtl-configs (read by spu_cosim.cmake), and one with the top's own defaults, the
# corner cases, served by tiny's DRAM. mem_cosim drives them against a data oracle
# and the cycle model's DRAM.
set(rpu_mem_models)
rpu_cosim_library(mem)
foreach(line IN LISTS rpu_rtl_config_lines)
  if(NOT line)
    continue()
  endif()
  rpu_rtl_config("${line}" mem config params)
  rpu_cosim_model(mem Vmem_${config} TRACE ASSERT FACTS name=${config} dram=${config} PARAMS ${params})
  list(APPEND rpu_mem_models ${config})
endforeach()
rpu_cosim_model(mem Vmem_corners TRACE ASSERT FACTS name=corners dram=tiny)
list(APPEND rpu_mem_models corners)
rpu_cosim_registry(mem)

add_executable(mem_cosim mem_cosim.cpp mem_agents.cpp)
target_include_directories(mem_cosim PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(mem_cosim PRIVATE rpu_mem_rtl_models rpu_cycle rpu_output_file CLI11::CLI11 fmt::fmt rpu_flags)

# Per model and cache: random traffic from every port of that cache (CI-sized), the
# same on all three caches at once through the memory arbiter, one request at a time
# against the LRU reference; under `slow` 10^6 requests per cache on all three.
foreach(model IN LISTS rpu_mem_models)
  foreach(cache node triangle data all)
    add_test(NAME cosim.mem.${model}.${cache}
             COMMAND mem_cosim --model ${model} --cache ${cache} --requests 20000 --coverage)
    set_tests_properties(cosim.mem.${model}.${cache} PROPERTIES LABELS cosim TIMEOUT 300)
  endforeach()
  foreach(cache node triangle data)
    add_test(NAME cosim.mem.${model}.${cache}.lru
             COMMAND mem_cosim --model ${model} --cache ${cache} --serial --requests 5000)
    set_tests_properties(cosim.mem.${model}.${cache}.lru PROPERTIES LABELS cosim TIMEOUT 300)
  endforeach()
  add_test(NAME slow.cosim.mem.${model}
           COMMAND mem_cosim --model ${model} --cache all --requests 1000000 --coverage)
  set_tests_properties(slow.cosim.mem.${model} PROPERTIES LABELS slow TIMEOUT 7200)
endforeach()

if(RPU_YOSYS)
  # tiny's data cache alone, then tiny's memory system, whose netlist replays every
  # cycle of a mem_cosim run (rtl/flow.py synth --unit mem; docs/memory-system.md).
  add_test(NAME slow.synth.mem.tiny
    COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/rtl/flow.py synth
            --unit mem --config tiny --pkg ${RPU_SPEC_SV} --cosim $<TARGET_FILE:mem_cosim>
            --out ${CMAKE_CURRENT_BINARY_DIR}/synth_mem --vectors 10000
            --yosys ${RPU_YOSYS} --verilator ${VERILATOR_BIN})
  set_tests_properties(slow.synth.mem.tiny PROPERTIES LABELS slow TIMEOUT 3600)
endif()
