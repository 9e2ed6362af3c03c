# The include rule of the layers (docs/architecture.md), checked when the build is configured: the
# application layer (app/) includes no front end, and no front end (cli/, python/, editors/lsp/)
# includes another -- except the command line's `thermnet lsp`, which starts the language server
# through its one entry header. A violation stops the configuration, naming the file and line.
function(thermnet_check_layer folder forbidden)
  file(GLOB_RECURSE files CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*.cpp
       ${PROJECT_SOURCE_DIR}/${folder}/*.hpp)
  foreach(f ${files})
    file(STRINGS ${f} lines REGEX "^#include \"")
    foreach(line ${lines})
      foreach(other ${forbidden})
        if(line MATCHES "^#include \"${other}/" AND NOT line MATCHES "editors/lsp/lsp_server.hpp\""
           OR line MATCHES "^#include \"${other}/" AND NOT folder STREQUAL "cli")
          file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${f})
          message(FATAL_ERROR "${rel}: '${line}': ${folder}/ may not include ${other}/ "
                              "(the include rule, docs/architecture.md)")
        endif()
      endforeach()
    endforeach()
  endforeach()
endfunction()

thermnet_check_layer(app "cli;python;editors")
thermnet_check_layer(cli "python;editors")
thermnet_check_layer(python "cli;editors")
thermnet_check_layer(editors/lsp "cli;python")
