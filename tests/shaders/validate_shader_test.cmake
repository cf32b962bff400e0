# The build's shader check (shaders/cmake/validate_shader.cmake, the very command each
# stage runs at build time) on a copy of shaders/ with one deliberate mistake: it must fail
# and name the original file and line (an include file's own line, not the line in the
# pasted text), and leave no output behind. CASE "accepts" checks the good copy passes and
# the resolved text carries the #line directives.
#
#   cmake -DCASE=<case> -DSHADERS_DIR=<shaders/> -DVALIDATOR=<glslangValidator>
#         -DWORK_DIR=<scratch folder> -P validate_shader_test.cmake
cmake_minimum_required(VERSION 3.25)

set(work "${WORK_DIR}/shaders")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
file(COPY "${SHADERS_DIR}/" DESTINATION "${work}")
set(out "${WORK_DIR}/resolved/stage")

macro(fail what)
  message(FATAL_ERROR "shaders.validate.${CASE}: ${what}")
endmacro()

# Sets <line_var> to the 1-based line of `good` in <file> and writes `bad` in its place.
function(break_line file good bad line_var)
  file(READ "${work}/${file}" text)
  string(FIND "${text}" "${good}" at)
  if(at EQUAL -1)
    fail("'${good}' is not in shaders/${file} any more: update this test")
  endif()
  string(SUBSTRING "${text}" 0 ${at} before)
  string(REGEX MATCHALL "\n" newlines "${before}")
  list(LENGTH newlines count)
  math(EXPR line "${count} + 1")
  string(REPLACE "${good}" "${bad}" text "${text}")
  file(WRITE "${work}/${file}" "${text}")
  set(${line_var} ${line} PARENT_SCOPE)
endfunction()

# Runs the check on <stage>; sets rc and log in the caller.
macro(validate stage)
  get_filename_component(ext "${stage}" LAST_EXT)
  set(out "${WORK_DIR}/resolved/stage${ext}")
  execute_process(
    COMMAND "${CMAKE_COMMAND}" "-DSTAGE=${work}/${stage}" "-DROOT=${work}" "-DOUTPUT=${out}"
            "-DVALIDATOR=${VALIDATOR}" -P "${SHADERS_DIR}/cmake/validate_shader.cmake"
    RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  message(STATUS "validate_shader.cmake on ${stage}: exit ${rc}\n${log}")
endmacro()

# The check failed, named file:line with an error, and wrote nothing.
macro(expect_failure file line)
  if(rc EQUAL 0)
    fail("the broken ${file} passed validation")
  endif()
  string(FIND "${log}" "${work}/${file}:${line}: error: " named)
  if(named EQUAL -1)
    fail("the error does not name ${work}/${file}:${line}:\n${log}")
  endif()
  if(EXISTS "${out}")
    fail("${out} was written although validation failed")
  endif()
endmacro()

if(CASE STREQUAL "accepts")
  set(include_line 0)
  file(READ "${work}/viewer_points.vert" text)
  string(FIND "${text}" "#include \"include/jet.glsl\"" at)
  string(SUBSTRING "${text}" 0 ${at} before)
  string(REGEX MATCHALL "\n" newlines "${before}")
  list(LENGTH newlines include_line)
  math(EXPR resume "${include_line} + 2")   # the line after the #include (1-based)
  validate(viewer_points.vert)
  if(NOT rc EQUAL 0)
    fail("the shipped viewer_points.vert failed validation")
  endif()
  file(READ "${out}" resolved)
  file(READ "${out}.files" legend)
  foreach(want "#version 450 core\n" "\n#line 1 1\n" "\n#line ${resume} 0\n" "vec3 jetColour(")
    string(FIND "${resolved}" "${want}" found)
    if(found EQUAL -1)
      fail("the resolved text lacks '${want}'")
    endif()
  endforeach()
  if(NOT legend STREQUAL "0 = viewer_points.vert, 1 = include/jet.glsl, 2 = include/viewer_point_style.glsl")
    fail("legend is '${legend}'")
  endif()
elseif(CASE STREQUAL "broken_include")
  break_line(include/jet.glsl "int bin = 0;" "int bin = not_declared;" line)
  validate(viewer_points.vert)
  expect_failure(include/jet.glsl ${line})
elseif(CASE STREQUAL "broken_stage_after_include")
  break_line(viewer_points.vert "gl_Position = u_projection * p;" "gl_Position = u_projection * q;" line)
  validate(viewer_points.vert)
  expect_failure(viewer_points.vert ${line})
elseif(CASE STREQUAL "fragment_stage_rules")
  # gl_VertexID exists in a vertex stage only: the extension picks the stage's rules.
  break_line(eye_dome_resolve.frag "ivec2 size = u_size;"
             "ivec2 size = ivec2(gl_VertexID);" line)
  validate(eye_dome_resolve.frag)
  expect_failure(eye_dome_resolve.frag ${line})
elseif(CASE STREQUAL "broken_compute")
  break_line(include/metric_counts.glsl "if (i1) atomicAdd(s_counts[0], 1u);"
             "if (i1) atomicAdd(s_counts[0], 1.0);" line)
  validate(metric_count_rgba.comp)
  expect_failure(include/metric_counts.glsl ${line})
elseif(CASE STREQUAL "missing_include")
  break_line(mode_indicator.frag "out vec4 o_colour;" "#include \"include/absent.glsl\"" line)
  validate(mode_indicator.frag)
  expect_failure(mode_indicator.frag ${line})
else()
  fail("unknown CASE '${CASE}'")
endif()
