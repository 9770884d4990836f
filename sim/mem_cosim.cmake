# The memory system (docs/memory-system.md): one Verilated rpu_mem_cosim_top per named
# configuration of spec/configs.toml, its caches' parameters from gen.py --list
# rtl-configs (read by spu_cosim.cmake), and one with the top's own defaults, the
# corner cases, served by tiny's DRAM. mem_cosim drives them against a data oracle
# and the cycle model's DRAM.
set(rpu_mem_model_includes "")
set(rpu_mem_model_entries "")
set(rpu_mem_models)
add_library(rpu_mem_rtl_models STATIC ${CMAKE_CURRENT_BINARY_DIR}/mem_models.cpp)
target_include_directories(rpu_mem_rtl_models PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
set_source_files_properties(${CMAKE_CURRENT_BINARY_DIR}/mem_models.cpp PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/cmodel)
target_link_libraries(rpu_mem_rtl_models PUBLIC rpu_spec)
foreach(line IN LISTS rpu_rtl_config_lines)
  if(NOT line)
    continue()
  endif()
  rpu_rtl_config("${line}" "^(Node|Triangle|Data)" config params)
  rpu_verilate(rpu_mem_rtl_models Vmem_${config} rpu_mem_cosim_top TRACE ASSERT PARAMS ${params})
  string(APPEND rpu_mem_model_includes "#include \"Vmem_${config}.h\"\n")
  string(APPEND rpu_mem_model_entries "    {\"${config}\", \"${config}\", &make<Vmem_${config}>},\n")
  list(APPEND rpu_mem_models ${config})
endforeach()
rpu_verilate(rpu_mem_rtl_models Vmem_corners rpu_mem_cosim_top TRACE ASSERT)
string(APPEND rpu_mem_model_includes "#include \"Vmem_corners.h\"\n")
string(APPEND rpu_mem_model_entries "    {\"corners\", \"tiny\", &make<Vmem_corners>},\n")
list(APPEND rpu_mem_models corners)
configure_file(mem_models.cpp.in ${CMAKE_CURRENT_BINARY_DIR}/mem_models.cpp @ONLY)

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
