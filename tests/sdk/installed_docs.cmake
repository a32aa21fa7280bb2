# Every page (NAME.md) or figure (NAME.svg) an installed page names must be
# installed too: a third party reads the pages under <prefix>/share/doc
# without the source tree. DOCS: the installed files (relative to
# SOURCE_DIR), as the top CMakeLists.txt lists them; docs/figures is
# installed whole.
file(GLOB installed RELATIVE ${SOURCE_DIR}/docs/figures ${SOURCE_DIR}/docs/figures/*)
foreach(doc ${DOCS})
  get_filename_component(name ${doc} NAME)
  list(APPEND installed ${name})
endforeach()
set(missing "")
foreach(doc ${DOCS})
  if(NOT doc MATCHES "\\.md$")
    continue()
  endif()
  file(READ ${SOURCE_DIR}/${doc} text)
  string(REGEX MATCHALL "[A-Za-z0-9_-]+\\.(md|svg)" named "${text}")
  list(REMOVE_DUPLICATES named)
  foreach(page ${named})
    list(FIND installed ${page} at)
    if(at EQUAL -1)
      list(APPEND missing "${doc} names ${page}")
    endif()
  endforeach()
endforeach()
if(missing)
  list(JOIN missing "\n  " lines)
  message(FATAL_ERROR "installed pages name pages that are not installed:\n  ${lines}")
endif()
