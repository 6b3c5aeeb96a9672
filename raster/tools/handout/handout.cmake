# Makes the students' handout (docs/HANDOUT.md):
#   cmake -DSOURCE_DIR=<raster's source tree> -DOUTPUT_DIR=<folder> -DRASTER=<build/bin/raster>
#         -P raster/tools/handout/handout.cmake
# The build target `handout` runs it: build/handout/raster-course/ and build/handout/raster-course.tar.gz.
#
# The handout is git's tracked files of SOURCE_DIR (as they are on disk) less what would give the
# answers or the hidden grading away, plus each lab's reference images, written by RASTER (a build
# with solutions/) at every public scene's options and at the lab's defaults, and the students'
# README (README.md beside this file) in place of the project's.
cmake_minimum_required(VERSION 3.25)
foreach(var SOURCE_DIR OUTPUT_DIR RASTER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "handout.cmake: -D${var}=... is required")
  endif()
endforeach()
set(name raster-course)
set(stage ${OUTPUT_DIR}/${name})

# What stays out, as regular expressions over paths relative to SOURCE_DIR:
#   solutions/                   the answers and the hidden scenes (solutions/<lab>/grading.json)
#   slides/                      the lecture's decks quote the solutions' code
#   tests/                       the project's suites: tests/grader's submissions are patches against
#                                the solutions, its root/ declares the hidden scenes, and the suites
#                                render <lab>@solution; a student's test is `raster grade labs --public`
#   docs/GRADING.md              the lecturer's grading guide: names every hidden scene and its options
#   docs/HANDOUT.md              how this handout is made (for lecturers)
#   raster/tools/handout/        this script and the students' README (which becomes README.md)
#   raster/tools/grade/gradescope/  the lecturer's autograder zip, made from solutions/
#   .ci/run                      runs the project's suites, which the handout has not
set(excluded
  "^solutions/" "^slides/" "^tests/" "^docs/GRADING\\.md$" "^docs/HANDOUT\\.md$"
  "^raster/tools/handout/" "^raster/tools/grade/gradescope/" "^\\.ci/run$" "^README\\.md$")

execute_process(COMMAND git -C ${SOURCE_DIR} ls-files
                OUTPUT_VARIABLE tracked RESULT_VARIABLE git_failed ERROR_VARIABLE git_error)
if(git_failed)
  message(FATAL_ERROR "handout.cmake: the handout is made of git's tracked files, and 'git ls-files' "
                      "failed in ${SOURCE_DIR}: ${git_error}")
endif()
string(REPLACE "\n" ";" tracked "${tracked}")

file(REMOVE_RECURSE ${stage} ${OUTPUT_DIR}/${name}.tar.gz)
file(MAKE_DIRECTORY ${stage})
set(count 0)
foreach(path IN LISTS tracked)
  if(path STREQUAL "")
    continue()
  endif()
  set(keep TRUE)
  foreach(pattern IN LISTS excluded)
    if(path MATCHES "${pattern}")
      set(keep FALSE)
    endif()
  endforeach()
  # A tracked file deleted in the working tree is not part of the handout either.
  if(keep AND EXISTS ${SOURCE_DIR}/${path})
    get_filename_component(dir ${stage}/${path} DIRECTORY)
    file(MAKE_DIRECTORY ${dir})
    file(COPY_FILE ${SOURCE_DIR}/${path} ${stage}/${path})
    math(EXPR count "${count} + 1")
  endif()
endforeach()
file(COPY_FILE ${CMAKE_CURRENT_LIST_DIR}/README.md ${stage}/README.md)
# The handout's Markdown links to nothing it leaves out: a relative link whose file is not in the
# handout (docs/GRADING.md, slides/...) becomes its text. tests/handout_test.py checks that every
# relative link of the handout's Markdown resolves inside it.
file(GLOB_RECURSE markdown RELATIVE ${stage} ${stage}/*.md)
set(unlinked 0)
foreach(doc IN LISTS markdown)
  file(READ ${stage}/${doc} text)
  get_filename_component(doc_dir ${stage}/${doc} DIRECTORY)
  string(REGEX MATCHALL "!?\\[[^]\n]*\\]\\([^)\n]*\\)" links "${text}")
  set(changed FALSE)
  foreach(link IN LISTS links)
    string(REGEX REPLACE "^!?\\[([^]]*)\\]\\(.*$" "\\1" words "${link}")
    string(REGEX REPLACE "^!?\\[[^]]*\\]\\([ <]*([^)#> ]*).*$" "\\1" target "${link}")
    if(target STREQUAL "" OR target MATCHES "^[A-Za-z][A-Za-z0-9+.-]*:" OR EXISTS ${doc_dir}/${target})
      continue()
    endif()
    string(REPLACE "${link}" "${words}" text "${text}")
    set(changed TRUE)
    math(EXPR unlinked "${unlinked} + 1")
  endforeach()
  if(changed)
    file(WRITE ${stage}/${doc} "${text}")
  endif()
endforeach()

# The reference images: what K shows, J compares with and `raster grade --public` grades against.
execute_process(COMMAND ${RASTER} references ${stage} --grading-root ${SOURCE_DIR}
                RESULT_VARIABLE failed OUTPUT_VARIABLE said ERROR_VARIABLE said)
if(failed)
  message(FATAL_ERROR "handout.cmake: ${RASTER} references failed: ${said}")
endif()
file(GLOB_RECURSE references RELATIVE ${stage} ${stage}/labs/*/reference/*.png)
list(LENGTH references reference_count)

# Every entry dated 2000-01-01, not when the handout was made.
execute_process(COMMAND ${CMAKE_COMMAND} -E tar czf ${name}.tar.gz --format=gnutar --mtime=2000-01-01 ${name}
                WORKING_DIRECTORY ${OUTPUT_DIR} RESULT_VARIABLE failed)
if(failed)
  message(FATAL_ERROR "handout.cmake: the archive ${OUTPUT_DIR}/${name}.tar.gz could not be written")
endif()
file(SIZE ${OUTPUT_DIR}/${name}.tar.gz bytes)
math(EXPR total "${count} + 1 + ${reference_count}")
message(STATUS "handout: ${OUTPUT_DIR}/${name}.tar.gz, ${bytes} bytes: ${total} files (${reference_count} "
               "reference images; ${unlinked} links to files it leaves out made text), and the folder ${stage}")
