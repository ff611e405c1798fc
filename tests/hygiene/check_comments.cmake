# cmake -DROOT=<checkout> -P tests/hygiene/check_comments.cmake
# Comments in library code describe what the code does, not its history: no issue numbers, no
# "used to" / "previously" / "formerly", no dates, no "now uses/reads/..." (docs/conventions.md,
# "Comments and internals").
# And no stale contract: a "Throws InputError" comment right above `std::string Validate() const`,
# which returns the problem instead. Library code: every module's src/ and include/ folders.
# Prints every violation, then fails.
cmake_minimum_required(VERSION 3.22)
if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<checkout> -P check_comments.cmake")
endif()
set(violations 0)
file(GLOB_RECURSE sources ${ROOT}/*/src/*.h ${ROOT}/*/src/*.cpp ${ROOT}/*/include/*.h ${ROOT}/*/*/src/*.h
     ${ROOT}/*/*/src/*.cpp ${ROOT}/*/*/include/*.h ${ROOT}/*/*/src/*.def ${ROOT}/*/*/include/*.def ${ROOT}/tools/*.cpp
     ${ROOT}/tools/*.h)
# History in a comment (// or a /* */ line). Dates are history; ISO 8601 examples with a time
# ("2026-11-29T09:41:07Z") describe a format and pass, and so does the Unix epoch (allowed below).
set(history
    "[Ii]ssue[ -]?#?[0-9]+"
    "[Tt]he issue (asks|says|wants|requires)"
    "(^|[^a-z])(it|we|this|that|they|which|[a-z]+\\(\\)) used to "
    "(^|[^a-z])[Pp]reviously[^a-z]"
    "(^|[^a-z])[Ff]ormerly[^a-z]"
    "(^|[^a-z])(is|are) now (a|an|the|in|done|read|written|computed|handled)[^a-z]"
    "(^|[^a-z])now (uses|reads|writes|takes|returns|lives|goes|calls)[^a-z]"
    "(19|20)[0-9][0-9]-[01][0-9]-[0-3][0-9]([^T0-9]|$)")
foreach(source IN LISTS sources)
  file(RELATIVE_PATH relative ${ROOT} ${source})
  if(relative MATCHES "(^|/)(build[^/]*|tests|third_party|_deps)/")
    continue()
  endif()
  file(STRINGS ${source} comments ENCODING UTF-8 REGEX "(//|^[ \t]*/?\\*)")
  foreach(line IN LISTS comments)
    string(REGEX REPLACE "^.*(//|^[ \t]*/?\\*)" "" text "${line}")
    string(REPLACE "1970-01-01" "the epoch" text "${text}")
    foreach(pattern IN LISTS history)
      if(text MATCHES "${pattern}")
        message(NOTICE "${source}: history in a comment (${pattern}): ${line}")
        math(EXPR violations "${violations} + 1")
        break()
      endif()
    endforeach()
  endforeach()
  file(READ ${source} content)
  if(content MATCHES "Throws InputError[^\n]*\n[ \t]*std::string Validate\\(\\)")
    message(NOTICE "${source}: 'Throws InputError' above std::string Validate(), which returns the problem")
    math(EXPR violations "${violations} + 1")
  endif()
endforeach()
if(violations GREATER 0)
  message(FATAL_ERROR "${violations} comment(s) carry history or a stale contract")
endif()
message(STATUS "comments: no history, no stale contract")
