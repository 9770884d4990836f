# The chip (docs/rtl.md "Chip"): one Verilated rpu_top per named configuration of
# spec/configs.toml (its build-time parameters from gen.py --list rtl-configs) with the
# Woop test, and tiny's also with the watertight test; chip_cosim renders frames on it
# with every core in lockstep, and the rtl backend of the Device API (rtl_device.hpp)
# renders on it for `rpu render --backend rtl`.
set(rpu_chip_top_params Cores Threads ChunkSize Registers CallDepth StackBytes SfuUnits StackDepth RayUnits
    NodeBytes NodeWays NodeHitLatency NodeMshrs TriangleBytes TriangleWays TriangleHitLatency TriangleMshrs
    DataBytes DataWays DataHitLatency DataMshrs ExpBits FracBits)
set(rpu_chip_model_includes "")
set(rpu_chip_model_entries "")
set(rpu_chip_cases)
add_library(rpu_chip_rtl_models STATIC ${CMAKE_CURRENT_BINARY_DIR}/chip_models.cpp)
target_include_directories(rpu_chip_rtl_models PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
set_source_files_properties(${CMAKE_CURRENT_BINARY_DIR}/chip_models.cpp PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/cmodel)
target_link_libraries(rpu_chip_rtl_models PUBLIC rpu_spec)
foreach(line IN LISTS rpu_rtl_config_lines)
  if(NOT line)
    continue()
  endif()
  list(JOIN rpu_chip_top_params "|" names)
  rpu_rtl_config("${line}" "^(${names})$" config config_params)
  set(params -GCodeWords=${rpu_spu_code_words} ${config_params})
  string(REGEX MATCH "-GCores=([0-9]+)" cores_flag "${line}")
  set(cores ${CMAKE_MATCH_1})
  set(isects woop)
  if(config STREQUAL "tiny")
    list(APPEND isects watertight)
  endif()
  foreach(isect IN LISTS isects)
    set(prefix Vchip_${config}_${isect})
    rpu_verilate(rpu_chip_rtl_models ${prefix} rpu_chip_cosim_top TRACE ASSERT
                 PARAMS ${params} -GIsectMode=${rpu_isect_${isect}})
    string(APPEND rpu_chip_model_includes "#include \"${prefix}.h\"\n")
    string(APPEND rpu_chip_model_entries
           "    {\"${config}\", \"${isect}\", &make<${prefix}, ${cores}, ${rpu_spu_code_words}>},\n")
    list(APPEND rpu_chip_cases "${config} ${isect}")
  endforeach()
endforeach()
configure_file(chip_models.cpp.in ${CMAKE_CURRENT_BINARY_DIR}/chip_models.cpp @ONLY)

add_library(rpu_rtl_device STATIC chip_run.cpp device_dram.cpp rtl_device.cpp)
target_include_directories(rpu_rtl_device PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(rpu_rtl_device PUBLIC rpu_device rpu_cycle PRIVATE rpu_chip_rtl_models rpu_spu_check rpu_config
                      fmt::fmt rpu_flags)

add_executable(chip_cosim chip_cosim.cpp)
target_link_libraries(chip_cosim PRIVATE rpu_rtl_device rpu_chip_rtl_models rpu_asm rpu_builtin_firmware rpu_scene
                      rpu_kdtree rpu_output_file CLI11::CLI11 rpu_flags)

# Frames in lockstep on every configuration's chip.
foreach(case IN LISTS rpu_chip_cases)
  string(REPLACE " " ";" case "${case}")
  list(GET case 0 config)
  list(GET case 1 isect)
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
    string(REPLACE " " ";" case "${case}")
    list(GET case 0 config)
    list(GET case 1 isect)
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
  endforeach()
endif()
