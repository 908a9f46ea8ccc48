# Project-wide warning and sanitizer flags, applied per target through hvx_apply_flags().
function(hvx_apply_flags target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                         -Wconversion -Wno-sign-conversion)
  if(HVX_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Sanitizer trees keep line tables only (-g1): reports name file and line, and the trees build
# in CI's time. Their presets build them with clang, whose sanitizers these are and which
# compiles them in half gcc's time here (a cold ASan tree: 308 s against 600 s on 2 cores).
if(HVX_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined -g1)
  add_link_options(-fsanitize=address,undefined)
  add_compile_definitions(HVX_SANITIZED=1)
endif()

if(HVX_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer -O1 -g1)
  add_link_options(-fsanitize=thread)
  add_compile_definitions(HVX_SANITIZED=1)
endif()

if(HVX_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
