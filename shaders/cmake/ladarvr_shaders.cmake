# ladarvr_embed_shaders(<target> HEADER <include path> STAGES <files...> INCLUDES <files...>)
#
# Makes the INTERFACE library <target>: its include directory holds <include path> (e.g.
# shaders/shaders.hpp), generated at build time with every stage of STAGES (.vert, .frag,
# .comp, relative to the current source directory) as a std::string_view. Each stage is
# first include-resolved and validated by glslangValidator (validate_shader.cmake): a
# shader error fails the build with "<file>:<line>: error: ...", naming the original file
# (stage or include) and line. INCLUDES lists the include files, so that editing one
# revalidates the stages. Targets that link <target> wait for the header.
set(_ladarvr_shaders_dir "${CMAKE_CURRENT_LIST_DIR}")

function(ladarvr_embed_shaders target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "HEADER" "STAGES;INCLUDES")
  if(NOT arg_HEADER OR NOT arg_STAGES)
    message(FATAL_ERROR "ladarvr_embed_shaders(${target}): HEADER and STAGES are required")
  endif()
  set(validate "${_ladarvr_shaders_dir}/validate_shader.cmake")
  set(embed "${_ladarvr_shaders_dir}/embed_shaders.cmake")
  set(resolved_dir "${CMAKE_CURRENT_BINARY_DIR}/resolved")
  set(include_dir "${CMAKE_CURRENT_BINARY_DIR}/include")
  set(header "${include_dir}/${arg_HEADER}")

  set(include_paths "")
  foreach(inc IN LISTS arg_INCLUDES)
    list(APPEND include_paths "${CMAKE_CURRENT_SOURCE_DIR}/${inc}")
  endforeach()

  set(resolved "")
  foreach(stage IN LISTS arg_STAGES)
    set(out "${resolved_dir}/${stage}")
    add_custom_command(
      OUTPUT "${out}" "${out}.files"
      COMMAND "${CMAKE_COMMAND}" "-DSTAGE=${CMAKE_CURRENT_SOURCE_DIR}/${stage}"
              "-DROOT=${CMAKE_CURRENT_SOURCE_DIR}" "-DOUTPUT=${out}"
              "-DVALIDATOR=${LADARVR_GLSLANG_VALIDATOR}" -P "${validate}"
      DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/${stage}" ${include_paths} "${validate}"
      COMMENT "shaders: validating ${stage} (glslangValidator, GLSL 4.50 core)"
      VERBATIM)
    list(APPEND resolved "${out}" "${out}.files")
  endforeach()

  list(JOIN arg_STAGES "," stage_list)
  add_custom_command(
    OUTPUT "${header}"
    COMMAND "${CMAKE_COMMAND}" "-DHEADER=${header}" "-DRESOLVED_DIR=${resolved_dir}"
            "-DSTAGES=${stage_list}" -P "${embed}"
    DEPENDS ${resolved} "${embed}"
    COMMENT "shaders: embedding ${arg_HEADER}"
    VERBATIM)
  add_custom_target(${target}_embed DEPENDS "${header}" SOURCES ${arg_STAGES} ${arg_INCLUDES})
  add_library(${target} INTERFACE)
  target_include_directories(${target} INTERFACE "${include_dir}")
  add_dependencies(${target} ${target}_embed)
endfunction()
