# What cmake/embed_text.cmake and cmake/embed_spirv.cmake share: the NAMES and FILES lists they are
# given (separated by commas: a semicolon would not survive the custom command's shell line), each
# file read as hex, and the generated source written only when it changed, so that an unchanged
# input does not recompile the library.

# Calls `callback`(index name file hex) for each NAMES/FILES pair, hex the file's bytes as
# hexadecimal. A macro, so that what the callback sets with PARENT_SCOPE reaches the script.
macro(embed_for_each_file callback)
  string(REPLACE "," ";" names "${NAMES}")
  string(REPLACE "," ";" files "${FILES}")
  list(LENGTH names count)
  math(EXPR last "${count} - 1")
  foreach(i RANGE ${last})
    list(GET names ${i} name)
    list(GET files ${i} file)
    file(READ "${file}" hex HEX)
    cmake_language(CALL ${callback} ${i} "${name}" "${file}" "${hex}")
  endforeach()
endmacro()

# Writes `text` to OUTPUT unless OUTPUT already holds it.
function(embed_write_output text)
  file(WRITE "${OUTPUT}.tmp" "${text}")
  file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
  file(REMOVE "${OUTPUT}.tmp")
endfunction()
