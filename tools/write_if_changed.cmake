# write_if_changed(FILE CONTENT): writes CONTENT to FILE unless FILE already holds exactly that, so
# that a generated source keeps its timestamp and its object is not rebuilt needlessly. Included by
# the generators that server/CMakeLists.txt runs in script mode (tools/embed_*.cmake).
function(write_if_changed file content)
  if(EXISTS "${file}")
    file(READ "${file}" old)
    if(old STREQUAL content)
      return()
    endif()
  endif()
  file(WRITE "${file}" "${content}")
endfunction()
