# raw_string_literal(<out-var> <text>): <text> as a C++ raw string literal R"d(...)d" whose
# delimiter d ("wisp", "wisp1", ...) does not close early inside the text. Included by the
# build-time scripts that embed files into the binary (presets, the editor's bundle).
function(raw_string_literal out text)
  set(delimiter "wisp")
  set(counter 0)
  string(FIND "${text}" ")${delimiter}\"" found)
  while(NOT found EQUAL -1)
    math(EXPR counter "${counter} + 1")
    set(delimiter "wisp${counter}")
    string(FIND "${text}" ")${delimiter}\"" found)
  endwhile()
  set(${out} "R\"${delimiter}(${text})${delimiter}\"" PARENT_SCOPE)
endfunction()
