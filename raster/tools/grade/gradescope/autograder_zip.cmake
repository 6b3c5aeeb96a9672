# Makes Gradescope's autograder zip (docs/GRADING.md, "Grading on Gradescope"):
#   cmake -DSOURCE_DIR=<raster's source tree> -DOUTPUT=<path of the zip> [-DLABS=<lab,lab...>]
#         -P raster/tools/grade/gradescope/autograder_zip.cmake
# LABS: commas or semicolons between the names.
# The build target autograder_zip runs it (build/autograder.zip). At the zip's root, as Gradescope's
# specification requires: setup.sh and run_autograder (executable), then what setup.sh builds the
# grader from: CMakeLists.txt, raster/, labs/ and solutions/ (not tests/ nor docs/), and
# gradescope_labs.txt, the labs run_autograder grades (one a line; none listed: every lab that
# declares its grading). Gradescope unpacks it into /autograder/source.
cmake_minimum_required(VERSION 3.25)
foreach(var SOURCE_DIR OUTPUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "autograder_zip.cmake: -D${var}=... is required")
  endif()
endforeach()
set(here ${CMAKE_CURRENT_LIST_DIR})
string(REPLACE "," ";" LABS "${LABS}")
foreach(lab IN LISTS LABS)
  if(NOT EXISTS ${SOURCE_DIR}/labs/${lab}/grading.json)
    message(FATAL_ERROR "autograder_zip.cmake: LABS names '${lab}', but ${SOURCE_DIR}/labs/${lab}/grading.json does not exist")
  endif()
endforeach()

# The tree, staged beside the zip: the scripts at the root, the sources under their own paths.
set(stage ${OUTPUT}.stage)
file(REMOVE_RECURSE ${stage})
file(MAKE_DIRECTORY ${stage})
file(COPY ${here}/setup.sh ${here}/run_autograder DESTINATION ${stage}
     FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
list(JOIN LABS "\n" lab_lines)
if(lab_lines)
  string(APPEND lab_lines "\n")
endif()
file(WRITE ${stage}/gradescope_labs.txt "${lab_lines}")
set(entries setup.sh run_autograder gradescope_labs.txt)
file(GLOB_RECURSE tree LIST_DIRECTORIES false RELATIVE ${SOURCE_DIR}
     ${SOURCE_DIR}/raster/* ${SOURCE_DIR}/labs/* ${SOURCE_DIR}/solutions/*)
list(APPEND tree CMakeLists.txt)
foreach(path IN LISTS tree)
  # Editors' and Python's leftovers and hidden files stay out.
  if(path MATCHES "(^|/)(\\.|__pycache__/)|(~|\\.swp|\\.pyc|\\.orig|\\.rej)$")
    continue()
  endif()
  get_filename_component(dir ${path} DIRECTORY)
  file(COPY ${SOURCE_DIR}/${path} DESTINATION ${stage}/${dir})
  list(APPEND entries ${path})
endforeach()
list(SORT entries)
foreach(required labs solutions raster/CMakeLists.txt)
  if(NOT EXISTS ${stage}/${required})
    message(FATAL_ERROR "autograder_zip.cmake: ${SOURCE_DIR} has no ${required}")
  endif()
endforeach()

file(REMOVE ${OUTPUT})
execute_process(COMMAND ${CMAKE_COMMAND} -E tar cf ${OUTPUT} --format=zip -- ${entries}
                WORKING_DIRECTORY ${stage} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "autograder_zip.cmake: making ${OUTPUT} failed (${status})")
endif()
file(REMOVE_RECURSE ${stage})
list(LENGTH entries count)
message(STATUS "${OUTPUT}: ${count} files")
