# Script mode: writes OUTPUT, a header with one `inline constexpr std::string_view` per file
# in FILES, named after the file with '.' and '-' turned into '_'.
set(_text "// Generated from the files in shaders/ at build time. Do not edit.\n#pragma once\n#include <string_view>\n\nnamespace ${NAMESPACE} {\n")
foreach(_file IN LISTS FILES)
  get_filename_component(_name ${_file} NAME)
  string(MAKE_C_IDENTIFIER ${_name} _identifier)
  file(READ ${_file} _content)
  string(APPEND _text "inline constexpr std::string_view ${_identifier} = R\"polder_embed(${_content})polder_embed\";\n")
endforeach()
string(APPEND _text "}  // namespace ${NAMESPACE}\n")
file(WRITE ${OUTPUT}.tmp "${_text}")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)
